"""The text of ``robospec new``'s spec, and the warnings about it: the scaffold (:mod:`.scaffold`)
at a rest pose searched in ManiSkill (:mod:`.rest_pose`) with gains measured there
(:mod:`.refinement`), each in the probe's child process, and its ``never_collide`` fitted to
the collision-group bits ``robospec validate`` has for it. Without simulation, both stay as
computed from the description.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path

from robospec.authoring.new.analysis import RobotAnalysis
from robospec.authoring.new.gains import JointGains
from robospec.authoring.new.rest_pose import RefinedGains, RestPose
from robospec.diagnostics import Diagnostic, Location, warning
from robospec.diagnostics.codes import REST_NOT_CHECKED, REST_TOUCHES

# why a rest pose went unchecked that the user should hear about as a warning (ManiSkill is
# installed but failed); "not installed" and --no-sim are only said in the scaffold's header
CANNOT_LOAD_PREFIXES = ("ManiSkill could not load", "the simulator crashed", "loading it in")


def scaffold_text(
    analysis: RobotAnalysis, out: Path, uid: str | None, schema: str, simulate: bool
) -> tuple[str, list[Diagnostic]]:
    """The spec's text, and warnings about its rest pose and its gains.

    With ``simulate``: the rest pose is searched in ManiSkill, then the gains computed there
    are measured and changed where they miss, in one child process; without, both stay as
    computed from the description."""
    from robospec.authoring.new.joint_gains import joint_gains, rating_warnings, with_refined
    from robospec.authoring.new.scaffold_controllers import unbalanced

    rest, found = _measured(analysis, out, schema, simulate)
    gains = joint_gains(analysis, rest.qpos, unbalanced(analysis))
    refined = False
    iterations: int | None = None
    problems: list[Diagnostic] = []
    if isinstance(found, str):
        problems.append(
            warning(
                Location(str(analysis.source.path)),
                REST_NOT_CHECKED,
                f"the gains were not measured in ManiSkill: {found}",
                "they are written as computed from the description; robospec check measures them",
            )
        )
    elif found is not None:
        gains = with_refined(gains, found.gains, found.over_rating)
        refined = bool(found.changed)
        iterations = found.solver_position_iterations
    text, rest = _fitted(analysis, out, uid, schema, rest, gains, refined, iterations)
    return text, [
        *rating_warnings(analysis, gains),
        *problems,
        *_rest_warnings(analysis, rest, text, out),
    ]


def _measured(
    analysis: RobotAnalysis, out: Path, schema: str, simulate: bool
) -> tuple[RestPose, RefinedGains | str | None]:
    """The rest pose and the refined gains (a string: why they were not measured; None: not
    asked for): from the probe's child process with ``simulate``, else the starting pose."""
    from robospec.authoring.new.rest_pose import (
        PROBE_MODE,
        PROBE_UID,
        Refinement,
        probe_rest_pose,
    )
    from robospec.authoring.new.scaffold import scaffold
    from robospec.importer.yamlout import to_yaml

    start = analysis.start_qpos()
    if not simulate:
        return RestPose(start, unchecked_because="robospec new --no-sim"), None
    draft = scaffold(analysis, out, RestPose(start), PROBE_UID, absolute_paths=True)
    refinement: Refinement | None = Refinement(
        str(analysis.source.path.resolve()), str(out), schema
    )
    mode = PROBE_MODE
    if "control_modes" not in draft.data:  # a base and nothing else: no gains to refine
        from robospec.resolve.mechanisms import BASE_MODE

        mode, refinement = BASE_MODE, None
    return probe_rest_pose(
        to_yaml(draft, schema),
        analysis.description,
        start,
        analysis.probe_mimic(start),
        analysis.body.floating,
        refinement,
        analysis.upright(start),
        analysis.loop_joined_pairs(),
        mode,
    )


def _fitted(
    analysis: RobotAnalysis,
    out: Path,
    uid: str | None,
    schema: str,
    rest: RestPose,
    gains: Mapping[str, JointGains],
    refined: bool,
    iterations: int | None,
) -> tuple[str, RestPose]:
    """The spec's text at ``rest``, its never_collide pairs fewer until validate takes them,
    and the rest pose whose pairs it declares."""
    from robospec.authoring.new.scaffold import scaffold
    from robospec.importer.yamlout import to_yaml

    def written(rest: RestPose) -> str:
        doc = scaffold(
            analysis, out, rest, uid, gains=gains, refined=refined, iterations=iterations
        )
        return to_yaml(doc, schema)

    text = written(rest)
    depth = {(a, b): d for a, b, d in rest.touching}
    while rest.never_collide and _never_collide_rejected(text, out):
        # validate would refuse the pairs (no collision-group bit left for them all): adjacent
        # pairs go first (the last found), then the shallowest overlapping pair (it was the last
        # one found: the Shadow hand lost its 24 mm thumb overlap for a 1 mm one), and the rest
        # warnings name it as touching
        if rest.adjacent:
            rest = dataclasses.replace(rest, adjacent=rest.adjacent[:-1])
        else:
            shallowest = min(rest.overlapping, key=lambda pair: depth.get(pair, 0.0))
            kept = tuple(pair for pair in rest.overlapping if pair != shallowest)
            rest = dataclasses.replace(rest, overlapping=kept)
        text = written(rest)
    return text, rest


def _never_collide_rejected(text: str, out: Path) -> bool:
    """Whether ``robospec validate`` would refuse the scaffold's never_collide: pairs left
    colliding for want of a free collision-group bit, or pairs it does not list disabled."""
    from robospec.pipeline import compile_spec

    robot = compile_spec(out, text=text.encode("utf-8")).robot
    record = robot.never_collide if robot is not None else None
    return record is not None and bool(record.uncovered or record.side_effects)


def _rest_warnings(
    analysis: RobotAnalysis, rest: RestPose, text: str, out: Path
) -> list[Diagnostic]:
    from robospec.load.reader import parse_spec_bytes

    loaded, _ = parse_spec_bytes(text.encode("utf-8"), str(out), "yaml")
    if loaded is None:
        return []
    at = loaded.source.key(("keyframes", "rest"))
    left = [t for t in rest.touching if (t[0], t[1]) not in rest.never_collide]
    if left:
        pairs = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for a, b, d in left)
        return [
            warning(
                at,
                REST_TOUCHES,
                f"no rest pose free of self-contact found in {rest.tried} tries: {pairs}",
                "move the keyframe apart, or declare the contact with never_collide if it is meant",
            )
        ]
    if rest.unchecked_because and rest.unchecked_because.startswith(CANNOT_LOAD_PREFIXES):
        return [
            warning(
                Location(str(analysis.source.path)),
                REST_NOT_CHECKED,
                f"the rest keyframe was not checked: {rest.unchecked_because}",
                "robospec check loads it the same way and will say more; the scaffold is "
                "written without the check",
            )
        ]
    return []
