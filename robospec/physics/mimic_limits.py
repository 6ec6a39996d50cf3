"""RS545: a mimic joint whose relation can never hold it within its own limits.

A ``pd_joint_pos_mimic`` controller holds each mimic joint at ``multiplier * control + offset``
(the description's ``<mimic>``). Where that value, over the whole range of the control joint,
lies outside the mimic joint's own ``<limit>`` (example-robot-data's PR2: each gripper's
``r_parallel_root_joint`` mimics the finger with multiplier -1 yet is limited to [0, 0.548]),
the joint cannot follow: it is pressed against its limit, whatever the gains, and every check
that moves it (a keyframe hold, a step) fails for that reason. The description's ``<mimic>``
and ``<limit>`` disagree; the finding says so at the joint in the description, and the checks
that the contradiction makes fail name it (:func:`contradiction_words`).
"""

from __future__ import annotations

from dataclasses import dataclass

from robospec.diagnostics import error
from robospec.diagnostics.codes import MIMIC_OUTSIDE_LIMITS
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status

NAME = "mimic_limits"
# the share of the relation's range that must lie within the joint's limits: below it, the
# joint can follow only at a point (its limit), not over a range
MIN_SHARE = 0.01
# the mend, for RS545 itself and for every check the contradiction makes fail
HINT = (
    "the description's <mimic> and <limit> of this joint disagree: mend the description (the "
    "multiplier's sign, or the limits); no gains or keyframe make the joint follow"
)


@dataclass(frozen=True)
class Contradiction:
    joint: str  # the mimic joint
    control: str  # the joint it mimics
    multiplier: float
    offset: float
    control_range: tuple[float, float]
    held_range: tuple[float, float]  # where the relation holds it over the control's range
    limits: tuple[float, float]  # its own

    def words(self) -> str:
        lo, hi = self.held_range
        return (
            f"'{self.joint}' mimics '{self.control}' (multiplier {self.multiplier:g}, offset "
            f"{self.offset:g}): over the control joint's range [{self.control_range[0]:.4g}, "
            f"{self.control_range[1]:.4g}] that holds it in [{lo:.4g}, {hi:.4g}], outside its "
            f"own limits [{self.limits[0]:.4g}, {self.limits[1]:.4g}]"
        )


def contradictions(run: CheckRun) -> dict[str, Contradiction]:
    """The mimic joints of the spec's ``pd_joint_pos_mimic`` controllers that their relation
    holds outside their limits over (nearly) all of the control joint's range."""
    joints = {joint.name: joint for joint in run.context.description.joints}
    found: dict[str, Contradiction] = {}
    for controller in run.robot.controllers:
        if not controller.kind.mimic:
            continue
        for name, rule in (dict(controller.kwargs).get("mimic") or {}).items():
            joint, control = joints.get(name), joints.get(rule["joint"])
            if joint is None or control is None or name in found:
                continue
            if control.lower is None or control.upper is None:
                continue
            if joint.lower is None or joint.upper is None:
                continue
            multiplier = float(rule.get("multiplier", 1.0))
            offset = float(rule.get("offset", 0.0))
            ends = sorted(multiplier * v + offset for v in (control.lower, control.upper))
            assert joint.lower is not None and joint.upper is not None
            inside = min(ends[1], joint.upper) - max(ends[0], joint.lower)
            span = ends[1] - ends[0]
            if span <= 0 or inside >= MIN_SHARE * span:
                continue
            assert control.lower is not None and control.upper is not None
            found[name] = Contradiction(
                name,
                control.name,
                multiplier,
                offset,
                (control.lower, control.upper),
                (ends[0], ends[1]),
                (joint.lower, joint.upper),
            )
    return found


def contradiction_words(run: CheckRun, joint: str) -> str | None:
    """'; <the contradiction> (RS545)' when ``joint`` is one: the cause, for another check's
    message about it."""
    found = contradictions(run).get(joint)
    return None if found is None else f"; {found.words()} ({MIMIC_OUTSIDE_LIMITS})"


def check(run: CheckRun) -> list[Finding]:
    findings = []
    lines = {joint.name: joint.line for joint in run.context.description.joints}
    for name, found in sorted(contradictions(run).items()):
        diagnostic = error(
            run.context.at_description(lines[name]),
            MIMIC_OUTSIDE_LIMITS,
            f"{found.words()}: it cannot follow, and stays pressed against its "
            "limit whatever the gains",
            HINT,
        )
        summary = f"held in [{found.held_range[0]:.4g}, {found.held_range[1]:.4g}], limits "
        summary += f"[{found.limits[0]:.4g}, {found.limits[1]:.4g}]"
        findings.append(Finding(NAME, None, name, Status.FAIL, summary, {}, (diagnostic,)))
    return findings
