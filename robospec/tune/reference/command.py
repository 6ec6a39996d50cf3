"""``robospec tune SPEC --reference FILE|mujoco``: fit the spec's gains to a recorded trajectory.

The command's process compiles the spec, reads the reference and decides which joints and
controllers the fit is about (bad input: a located diagnostic and exit 2); a worker process
(:mod:`robospec.tune.reference.worker`) does everything that touches ManiSkill, SAPIEN or
MuJoCo. The report (text or JSON) gives each joint's gains and normalized error before and
after; exit 0 when the fitted robot matches the reference (normalized error at most
:data:`MATCH`), 1 when it cannot (RS648, saying which joints stay off and what may be why).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robospec.diagnostics import Diagnostic, Location, Severity, error, has_errors, warning
from robospec.diagnostics.codes import (
    REFERENCE_FIT_CRASH,
    REFERENCE_JOINT_NOT_POSITION_DRIVEN,
    REFERENCE_JOINT_STILL,
    REFERENCE_MUJOCO_UNUSABLE,
    REFERENCE_UNDETERMINED,
    REFERENCE_UNMATCHED,
)
from robospec.physics.findings import significant
from robospec.pipeline import CompiledSpec, compile_spec
from robospec.tune.reference.plan import Plan, plan
from robospec.tune.reference.trajectory import Reference, read_reference
from robospec.tune.reference.worker import Outcome, Request

COMMAND_LINE = "<command line>"
MUJOCO = "mujoco"
MATCH = 0.1  # normalized error (RMS error over RMS motion) a fit must reach to match
FIT_DIGITS = 4  # significant digits: what a fit from a recording can claim
STILL = 1e-4  # a joint whose measured motion is below this (rad or m, RMS) shows no gains
# what a position trajectory cannot show, said in every report
ARMATURE_NOTE = (
    "armature is not fitted: a position trajectory shows K/I and D/I, so rotor inertia "
    "cannot be told from the gains (its effect is absorbed into them), and a spec has no "
    "field for it (an MJCF with loader: mujoco brings its own)"
)
MUJOCO_NOTES = (
    "ManiSkill's MJCF loader recomputes masses and inertias from the geoms (not the file's "
    "<inertial>s) and does not load joint damping, armature or frictionloss: the fitted gains "
    "absorb these differences only in the joints' response to their own targets",
    "the fit matches each joint's drive; links that collide, tendons and equality constraints "
    "(which the loader drops) cannot be matched by gains",
)
# the same, where MuJoCo compiled the MJCF into the URDF ManiSkill loads (loader: mujoco)
MUJOCO_COMPILED_NOTES = (
    "MuJoCo compiled the MJCF into the URDF ManiSkill loads (loader: mujoco): masses, "
    "inertias, armature and frictionloss are MuJoCo's in both; a driven joint's own damping "
    "is not (its drive's damping is the controller's), so the fitted damping absorbs it",
    "the fit matches each joint's drive; tendons and equality constraints (which the URDF does "
    "not carry) cannot be matched by gains",
)


def run_reference(
    spec: Path,
    uid: str | None,
    reference: str,
    controllers: list[str],
    write: bool,
    plot: Path | None,
    output_format: str,
) -> int:
    """Fit, print the report; the exit code (0 matching, 1 cannot match, 2 usage error)."""
    code, text = reference_report(spec, uid, reference, controllers, write, plot, output_format)
    if text:
        sys.stdout.write(text if text.endswith("\n") else text + "\n")
    return code


def reference_report(
    spec: Path,
    uid: str | None,
    reference: str,
    controllers: Sequence[str],
    write: bool,
    plot: Path | None,
    output_format: str = "text",
) -> tuple[int, str]:
    item = compile_spec(spec)
    diagnostics = list(item.diagnostics)
    report = _Report(item, reference)
    if not item.ok or item.context is None or item.robot is None:
        return 1, report.render(output_format, diagnostics)
    usage = _unknown_controllers(item, controllers)
    source = _reference_source(item, reference)
    usage.extend(source.problems)
    if has_errors(usage):
        return 2, report.render(output_format, [*diagnostics, *usage])
    chosen, problems = _fit_plan(item, reference, source, controllers)
    if chosen is None or has_errors(problems):
        return 2, report.render(output_format, [*diagnostics, *problems])
    request = Request(item.path.resolve(), item.display, chosen, source.ref, source.mjcf)
    outcome = _run_worker(item, request)
    report.outcome = outcome
    diagnostics += [d for d in outcome.diagnostics if d not in diagnostics]
    if outcome.fit is None:
        return 1, report.render(output_format, diagnostics)
    diagnostics += _fit_findings(item, outcome, reference)
    if write and not has_errors(diagnostics):
        report.written, found = _write(item, outcome, uid)
        diagnostics += found
    if plot is not None:
        from robospec.tune.reference.plot import plot_reference

        report.plots = [str(plot_reference(plot, item.robot.uid, outcome))]
    return (1 if has_errors(diagnostics) else 0), report.render(output_format, diagnostics)


@dataclass(frozen=True)
class _ReferenceSource:
    """What the fit replays: a recorded trajectory (``ref``) or the robot's MJCF in MuJoCo
    (``mjcf``); the joints it moves, and what is wrong with it."""

    joints: tuple[str, ...]
    ref: Reference | None
    mjcf: str | None
    problems: tuple[Diagnostic, ...]


def _reference_source(item: CompiledSpec, reference: str) -> _ReferenceSource:
    """``--reference``'s argument read: ``mujoco`` (the MJCF's position actuators), or a
    trajectory file."""
    if reference != MUJOCO:
        ref, read_problems = read_reference(Path(reference), reference)
        return _ReferenceSource(
            ref.joints if ref is not None else (), ref, None, tuple(read_problems)
        )
    robot, context = item.robot, item.context
    assert robot is not None and context is not None
    problems: list[Diagnostic] = []
    mjcf = _mjcf_file(item)
    if mjcf is None:
        problems.append(
            error(
                Location(COMMAND_LINE),
                REFERENCE_MUJOCO_UNUSABLE,
                f"--reference mujoco needs an MJCF robot; '{robot.uid}' is described in URDF",
                "record a trajectory (CSV or NPZ) and pass it as --reference FILE",
            )
        )
    joints = tuple(
        a.joint
        for a in context.description.actuators
        if a.type in ("position", "general") and a.kp is not None and a.joint is not None
    )
    if mjcf is not None and not joints:
        problems.append(
            error(
                Location(context.description_file),
                REFERENCE_MUJOCO_UNUSABLE,
                f"--reference mujoco: '{context.description_file}' has no position "
                "actuator (<position>, or <general> with a servo's gain and bias)",
                "MuJoCo would not move the robot: record a trajectory instead",
            )
        )
    return _ReferenceSource(joints, None, mjcf, tuple(problems))


def _mjcf_file(item: CompiledSpec) -> str | None:
    """The MJCF MuJoCo replays: the file the spec names, whether ManiSkill's MJCF loader reads
    it or MuJoCo compiles it into the URDF ManiSkill loads (``loader: mujoco``: the resolved
    description is then that URDF, a derived copy that keeps the MJCF's path); None for a
    robot described in URDF (or composed of parts, which no single MJCF describes)."""
    robot, context = item.robot, item.context
    assert robot is not None and context is not None
    if robot.description_kind == "mjcf":
        return str(robot.description.absolute)
    declared = context.spec.description
    if declared is not None and declared.compiled and not context.spec.parts:
        return str(robot.description.absolute)
    return None


def _fit_plan(
    item: CompiledSpec, reference: str, source: _ReferenceSource, controllers: Sequence[str]
) -> tuple[Plan | None, list[Diagnostic]]:
    """The joints and controllers the fit is about, and why there are none."""
    assert item.robot is not None and item.context is not None
    active = item.context.description.active_joint_names
    if reference == MUJOCO:
        joints = tuple(j for j in active if j in set(source.joints))  # ManiSkill's order
        return _mujoco_plan(item, joints, controllers)
    ref = source.ref
    assert ref is not None
    chosen, problems = plan(item.robot, active, source.joints, ref.location, controllers)
    if chosen is not None:
        problems += _still(ref)
    return chosen, problems


def _fit_findings(item: CompiledSpec, outcome: Outcome, reference: str) -> list[Diagnostic]:
    """RS649 for joints whose stiffness and damping the reference does not tell apart, RS648
    when the fitted robot still does not match."""
    assert item.context is not None and outcome.fit is not None
    fitted = outcome.fit
    where = item.context.key(("controllers", outcome.plan.controllers[0]))
    found: list[Diagnostic] = []
    ill = [outcome.plan.joints[k] for k in fitted.ill_determined]
    if ill:
        found.append(
            warning(
                where,
                REFERENCE_UNDETERMINED,
                "the reference does not pin down stiffness and damping each for joint(s) "
                f"{', '.join(ill)}: their response shows only a combination (a far overdamped "
                "drive shows only D/K); their fitted values are one choice among many that "
                "match",
                "record steps that the joints overshoot or ring after, or fit with the other "
                "gain fixed",
            )
        )
    if fitted.error_after > MATCH:
        worst = np.argsort(-np.nan_to_num(fitted.errors_after, nan=np.inf))[:3]
        off = ", ".join(
            f"{outcome.plan.joints[k]} {fitted.errors_after[k]:.1%}"
            for k in worst
            if not fitted.errors_after[k] <= MATCH
        )
        found.append(
            error(
                where,
                REFERENCE_UNMATCHED,
                f"the simulated robot cannot match the reference: normalized error "
                f"{fitted.error_before:.1%} before, {fitted.error_after:.1%} after the fit "
                f"(at most {MATCH:.0%} matches; worst joints: {off})",
                "what gains cannot absorb: a force limit the recording saturates, backlash, "
                "masses the description has wrong, contacts or coupling"
                + (", and what ManiSkill's MJCF loader drops" if reference == MUJOCO else ""),
            )
        )
    return found


def _unknown_controllers(item: CompiledSpec, names: Sequence[str]) -> list[Diagnostic]:
    assert item.robot is not None
    known = {c.name for c in item.robot.controllers}
    return [
        error(
            Location(COMMAND_LINE),
            REFERENCE_JOINT_NOT_POSITION_DRIVEN,
            f"--controller {name!r}: '{item.robot.uid}' has no controller of that name",
            f"its controllers: {', '.join(sorted(known))}",
        )
        for name in names
        if name not in known
    ]


def _mujoco_plan(
    item: CompiledSpec, joints: Sequence[str], controllers: Sequence[str]
) -> tuple[Plan | None, list[Diagnostic]]:
    """The MuJoCo-actuated joints that a position controller drives (in the mode that drives
    most of them): the others are simply not part of the reference."""
    from robospec.tune.reference.plan import driving

    assert item.robot is not None and item.context is not None
    wanted = set(controllers)
    best: Plan | None = None
    for mode, found in driving(item.robot).items():
        usable = [j for j in joints if j in found and (not wanted or found[j][1] in wanted)]
        if usable and (best is None or len(usable) > len(best.joints)):
            best = Plan(
                mode,
                tuple(usable),
                tuple(found[j][1] for j in usable),
                tuple(found[j][0] for j in usable),
            )
    if best is None:
        return None, [
            error(
                Location(item.display),
                REFERENCE_MUJOCO_UNUSABLE,
                "--reference mujoco: no joint-position controller of the spec drives a joint "
                "that a MuJoCo position actuator drives",
                "drive the actuated joints with pd_joint_pos controllers",
            )
        ]
    return best, []


def _still(reference: Reference) -> list[Diagnostic]:
    motion = np.sqrt(np.mean((reference.qpos - reference.qpos.mean(axis=0)) ** 2, axis=0))
    return [
        error(
            reference.location(joint),
            REFERENCE_JOINT_STILL,
            f"reference joint '{joint}' does not move (RMS motion {m:.2g}): nothing in its "
            "response shows its gains",
            "leave its columns out, or record targets that move it",
        )
        for joint, m in zip(reference.joints, motion, strict=True)
        if m < STILL
    ]


# -- writing -------------------------------------------------------------------------------


def _write(item: CompiledSpec, outcome: Outcome, uid: str | None) -> tuple[bool, list[Diagnostic]]:
    """The fitted stiffness and damping into the spec, through ``robospec tune``'s writer
    (only the gain values change). Fitted friction is reported, not written."""
    from robospec.tune.results import ControllerTuning, Gains
    from robospec.tune.write import write_gains

    assert item.robot is not None and outcome.fit is not None
    fitted = outcome.fit
    tunings = []
    for name in dict.fromkeys(outcome.plan.controllers):
        controller = next(c for c in item.robot.controllers if c.name == name)
        kwargs = dict(controller.kwargs)
        joints = tuple(controller.joint_names)
        before = Gains(
            _per_joint(kwargs.get("stiffness"), len(joints)),
            _per_joint(kwargs.get("damping"), len(joints)),
            _per_joint(kwargs.get("force_limit", 1e10), len(joints)),
        )
        stiffness, damping = list(before.stiffness), list(before.damping)
        for k, joint in enumerate(outcome.plan.joints):
            if outcome.plan.controllers[k] == name and joint in joints:
                stiffness[joints.index(joint)] = significant(fitted.after.stiffness[k], FIT_DIGITS)
                damping[joints.index(joint)] = significant(fitted.after.damping[k], FIT_DIGITS)
        group = outcome.plan.groups[outcome.plan.controllers.index(name)]
        after = Gains(tuple(stiffness), tuple(damping), before.force_limit)
        tunings.append(
            ControllerTuning(
                name, outcome.plan.mode, group, "position", joints, "tuned", None, before, after
            )
        )
    return write_gains(item, tunings, uid)


def _per_joint(value: float | list[float] | tuple[float, ...] | None, n: int) -> tuple[float, ...]:
    if isinstance(value, list | tuple):
        return tuple(float(v) for v in value)
    return (float(value),) * n if value is not None else (0.0,) * n


# -- the worker process --------------------------------------------------------------------


def _run_worker(item: CompiledSpec, request: Request) -> Outcome:
    """The fit, in a worker process; one that dies is RS650 (what it was doing, the last
    ManiSkill/SAPIEN/MuJoCo frame)."""
    from robospec.maniskill.crash import from_fault_log
    from robospec.maniskill.upstream_output import UpstreamLog
    from robospec.physics.one_shot import Death, run_once

    found = run_once("robospec.tune.reference.worker", request, "robospec-reference-")
    if not isinstance(found, Death):
        outcome: Outcome = found
        return outcome
    said = UpstreamLog()
    said.feed(found.log)
    crash = from_fault_log(found.fault_log, found.returncode)
    why = found.last_line() if found.at_start else crash.what
    outcome = Outcome(request.plan, request.reference)
    outcome.diagnostics.append(
        error(
            Location(item.display),
            REFERENCE_FIT_CRASH,
            f"the reference fit's process died while {found.doing}: {why} ({crash.where()})",
            "it needs the maniskill extra (and mujoco for --reference mujoco: the reference "
            "extra); run robospec check on the spec to see which part of the robot fails",
        )
    )
    outcome.messages = list(said.messages())
    return outcome


# -- the report ----------------------------------------------------------------------------


class _Report:
    def __init__(self, item: CompiledSpec, reference: str) -> None:
        self.item = item
        self.reference = reference
        self.outcome: Outcome | None = None
        self.written = False
        self.plots: list[str] = []

    def notes(self) -> list[str]:
        notes = [ARMATURE_NOTE]
        if self.reference == MUJOCO:
            robot = self.item.robot
            compiled = robot is not None and robot.description_kind == "urdf"
            notes += list(MUJOCO_COMPILED_NOTES if compiled else MUJOCO_NOTES)
        if self.outcome is not None:
            notes += self.outcome.notes
            fit = self.outcome.fit
            if fit is not None and not fit.friction_fitted:
                notes.append("joint friction was tried only where the gains left an error")
        return notes

    def data(self, diagnostics: Sequence[Diagnostic]) -> dict[str, object]:
        robot = self.item.robot
        out: dict[str, object] = {
            "spec": self.item.display,
            "uid": robot.uid if robot is not None else None,
            "reference": self.reference,
            "status": "error",
        }
        outcome = self.outcome
        fit = outcome.fit if outcome is not None else None
        if outcome is not None and fit is not None:
            p = outcome.plan
            out["status"] = "matched" if fit.error_after <= MATCH else "not matched"
            out["mode"] = p.mode
            out["error_before"] = _round(fit.error_before)
            out["error_after"] = _round(fit.error_after)
            out["friction_fitted"] = fit.friction_fitted
            out["replays"] = fit.replays
            out["seconds"] = round(fit.seconds, 2)
            joints = []
            for k, joint in enumerate(p.joints):
                entry: dict[str, object] = {
                    "joint": joint,
                    "controller": p.controllers[k],
                    "stiffness": {
                        "before": _round(fit.before.stiffness[k]),
                        "after": _round(fit.after.stiffness[k]),
                    },
                    "damping": {
                        "before": _round(fit.before.damping[k]),
                        "after": _round(fit.after.damping[k]),
                    },
                    "friction": {
                        "before": _round(fit.before.friction[k]),
                        "after": _round(fit.after.friction[k]),
                    },
                    "error": {
                        "before": _round(fit.errors_before[k]),
                        "after": _round(fit.errors_after[k]),
                    },
                    "well_determined": k not in fit.ill_determined,
                }
                if joint in outcome.mujoco_gains:
                    kp, kv = outcome.mujoco_gains[joint]
                    entry["mujoco"] = {"kp": _round(kp), "kv": _round(kv)}
                joints.append(entry)
            out["joints"] = joints
        out["notes"] = self.notes()
        out["written"] = self.written
        out["plots"] = self.plots
        out["diagnostics"] = [d.to_json() for d in diagnostics]
        return out

    def render(self, output_format: str, diagnostics: Sequence[Diagnostic]) -> str:
        if output_format == "json":
            return json.dumps(self.data(diagnostics), indent=2)
        return self._text(diagnostics)

    def _text(self, diagnostics: Sequence[Diagnostic]) -> str:
        from robospec.reporting.text import render

        lines: list[str] = []
        outcome = self.outcome
        fit = outcome.fit if outcome is not None else None
        if outcome is not None and fit is not None:
            p = outcome.plan
            robot = self.item.robot
            assert robot is not None
            lines.append(
                f"{self.item.display}: {robot.uid} fitted to {self.reference} "
                f"(mode {p.mode}, {fit.replays} replays, {fit.seconds:.1f} s)"
            )
            header = (
                "joint",
                "controller",
                "stiffness",
                "damping",
                "friction" if fit.friction_fitted else "",
                "error",
            )
            rows = [header]
            for k, joint in enumerate(p.joints):
                mark = "" if k not in fit.ill_determined else " *"
                rows.append(
                    (
                        joint + mark,
                        p.controllers[k],
                        f"{fit.before.stiffness[k]:.4g} -> {fit.after.stiffness[k]:.4g}",
                        f"{fit.before.damping[k]:.4g} -> {fit.after.damping[k]:.4g}",
                        f"{fit.before.friction[k]:.3g} -> {fit.after.friction[k]:.3g}"
                        if fit.friction_fitted
                        else "",
                        f"{fit.errors_before[k]:.1%} -> {fit.errors_after[k]:.1%}",
                    )
                )
            widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
            for row in rows:
                lines.append(
                    "  " + "  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip()
                )
            status = "matches" if fit.error_after <= MATCH else "does not match"
            lines.append(
                f"normalized error (RMS error / RMS motion): {fit.error_before:.1%} before, "
                f"{fit.error_after:.1%} after: {status} (at most {MATCH:.0%})"
            )
            if outcome.mujoco_gains:
                lines.append(
                    "MuJoCo's servos (kp, kv): "
                    + ", ".join(
                        f"{j} ({kp:g}, {kv:g})" for j, (kp, kv) in outcome.mujoco_gains.items()
                    )
                )
            if fit.ill_determined:
                lines.append("  * only a combination of stiffness and damping is determined")
            for note in self.notes():
                lines.append(f"note: {note}")
            if self.written:
                lines.append(f"wrote the fitted stiffness and damping into {self.item.display}")
            for path in self.plots:
                lines.append(f"plot: {path}")
        shown = [d for d in diagnostics if d.severity in (Severity.ERROR, Severity.WARNING)]
        if shown or not lines:
            lines.append(render(shown, 1).rstrip())
        return "\n".join(lines)


def _round(value: float) -> float | None:
    value = float(value)
    if not np.isfinite(value):
        return None
    return float(f"{value:.6g}")
