"""``robospec tune`` end to end: options in, exit code and rendered report out.

The spec is compiled here (its diagnostics come first, and ``--controller`` names are checked
against it), the search runs in a worker process (``robospec.tune.worker``: ManiSkill is
imported there, and a robot that kills the process is RS515, not a lost run), then the
controllers that miss a target get RS620 at their gains, ``--write`` edits the spec
(``robospec.tune.write``) and ``--plot`` draws each controller before and after.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error, has_errors, warning
from robospec.diagnostics.codes import (
    ROBOT_NOT_LOADABLE,
    TUNED_GAINS_OVER_RATING,
    TUNING_TARGETS_UNMET,
    UNKNOWN_TUNED_CONTROLLER,
)
from robospec.pipeline import CompiledSpec, compile_spec
from robospec.tune.report import render_json, render_text
from robospec.tune.results import ControllerTuning, TuneReport
from robospec.tune.worker import Request

COMMAND_LINE = "<command line>"


def run_tune(
    spec: Path,
    uid: str | None = None,
    controllers: Sequence[str] = (),
    write: bool = False,
    plot: Path | None = None,
    output_format: str = "text",
    reference: str | None = None,
) -> tuple[int, str]:
    """Tune ``spec``'s controllers (only ``controllers`` when given); the exit code (0: every
    controller meets its targets, 1: one cannot, or errors) and the report."""
    if reference is not None:  # fitting a recorded trajectory: its own command
        from robospec.tune.reference.command import run_reference

        code = run_reference(
            spec=spec,
            uid=uid,
            reference=reference,
            controllers=list(controllers),
            write=write,
            plot=plot,
            output_format=output_format,
        )
        return code, ""
    report = tune_report(spec, uid, controllers, write, plot)
    text = render_json(report) if output_format == "json" else render_text(report)
    return (1 if report.failed else 0), text


def tune_report(
    spec: Path,
    uid: str | None = None,
    controllers: Sequence[str] = (),
    write: bool = False,
    plot: Path | None = None,
) -> TuneReport:
    item = compile_spec(spec)
    report = TuneReport(item.display, item.robot.uid if item.robot else None)
    report.diagnostics.extend(item.diagnostics)
    if not item.ok or item.context is None or item.robot is None:
        return report
    problems = _unknown_controllers(item, controllers) + _invalid_uid(uid)
    from robospec.maniskill.installed import installed, mixed_install_problem

    mixed = mixed_install_problem(installed())
    problems += [mixed] if mixed is not None else []
    if has_errors(problems):
        report.diagnostics.extend(problems)
        return report
    found = run_worker(item, tuple(controllers), traces=plot is not None)
    report.controllers = found.controllers
    # the worker compiled the spec again: its compile diagnostics are already here
    report.diagnostics.extend(d for d in found.diagnostics if d not in item.diagnostics)
    report.messages = found.messages
    report.diagnostics.extend(_not_met(item, c) for c in found.controllers if c.status == "failed")
    report.diagnostics.extend(_over_rating(item, found.controllers))
    if write:
        from robospec.tune.write import write_gains

        written, diagnostics = write_gains(item, found.controllers, uid)
        report.written = written
        report.diagnostics.extend(diagnostics)
    if plot is not None:
        report.plots = _plots(plot, report)
    return report


def _unknown_controllers(item: CompiledSpec, names: Sequence[str]) -> list[Diagnostic]:
    assert item.robot is not None
    used: set[str] = set()
    for mode in item.robot.modes:
        used.update(dict(mode.groups).values() if mode.groups else [mode.controller or mode.name])
    known = sorted(c.name for c in item.robot.controllers)
    problems = []
    for name in names:
        if name in used:
            continue
        hint = (
            "it is defined but no control mode uses it: tune measures a controller in a mode"
            if name in known
            else f"the spec's controllers: {', '.join(known)}"
        )
        problems.append(
            error(
                Location(COMMAND_LINE),
                UNKNOWN_TUNED_CONTROLLER,
                f"--controller {name!r}: no control mode of '{item.robot.uid}' uses a "
                f"controller of that name",
                hint,
            )
        )
    return problems


def _invalid_uid(uid: str | None) -> list[Diagnostic]:
    if uid is None:
        return []
    from robospec.model.uid import invalid_uid

    found = invalid_uid(uid, Location(COMMAND_LINE))
    return [found] if found is not None else []


def _not_met(item: CompiledSpec, tuning: ControllerTuning) -> Diagnostic:
    assert item.context is not None
    joints = "; ".join(f"'{joint}': {why}" for joint, why in tuning.reasons)
    targets = tuning.targets
    aim = (
        f"overshoot <= {targets.max_overshoot:.0%}, settling <= {targets.max_settling_time:g} s, "
        f"error <= {targets.max_steady_state_error:.0%}"
        if targets is not None
        else "its targets"
    )
    kinds = {why.split(":", 1)[0] for _, why in tuning.reasons}
    hint = {
        "force limit": "allow a larger force_limit (checks.tune.keep_force_limit: false) where "
        "the motor can give it; at its rating, accept a slower joint (relax checks.tune) or "
        "lighten what it moves",
        "coupling between joints": "stiffen the joints that push it (their damping too), or "
        "relax checks.tune for this controller",
    }
    return error(
        item.context.key(("controllers", tuning.controller)),
        TUNING_TARGETS_UNMET,
        f"controller '{tuning.controller}' ({tuning.mode}/{tuning.group}) cannot meet its "
        f"tuning targets ({aim}): {joints}",
        "; ".join(hint[k] for k in sorted(kinds) if k in hint)
        or "relax checks.tune for this controller, or look at the plot (--plot DIR)",
    )


def _over_rating(item: CompiledSpec, tunings: Sequence[ControllerTuning]) -> list[Diagnostic]:
    """RS623 per joint whose tuned gains would need more force than the description rates its
    motor for: at the joint's rating in the description (the force limit stays at it)."""
    assert item.context is not None
    from robospec.description.ratings import joint_ratings

    description = item.context.description
    ratings = joint_ratings(description)
    found = []
    for tuning in tunings:
        for joint, demand, cap in tuning.over_rating:
            rating = ratings.get(joint)
            where = (
                item.context.at_description(rating.line)
                if rating is not None
                else item.context.key(("controllers", tuning.controller))
            )
            what = rating.what if rating is not None else "its rating"
            found.append(
                warning(
                    where,
                    TUNED_GAINS_OVER_RATING,
                    f"joint '{joint}' (controller '{tuning.controller}'): its tuned gains ask "
                    f"for {demand:.3g} in the step, more than {what} of {cap:g}; tune kept "
                    f"force_limit at {cap:g}",
                    "the motor cannot give more: accept a slower joint (relax checks.tune for "
                    "this controller), or check the rating",
                )
            )
    return found


def _plots(folder: Path, report: TuneReport) -> list[str]:
    from robospec.physics.plot import Limits, plot_controller

    written = []
    for tuning in report.controllers:
        targets = tuning.targets
        if tuning.before_trace is None or tuning.after_trace is None or targets is None:
            continue
        series = [("before", tuning.before_trace)]
        if tuning.status != "met":
            series.append(("after", tuning.after_trace))
        limits = Limits(targets.settling_band, targets.max_overshoot, targets.max_settling_time)
        uid = report.uid or "robot"
        written.append(str(plot_controller(folder, uid, tuning.controller, series, limits)))
    return written


# -- the worker process --------------------------------------------------------------------


def run_worker(item: CompiledSpec, controllers: tuple[str, ...], traces: bool) -> TuneReport:
    """Tune in a worker process; a worker that dies is RS515 (what it was doing, the last
    ManiSkill/SAPIEN frame), a worker that cannot start is RS510."""
    from robospec.maniskill.crash import from_fault_log
    from robospec.maniskill.upstream_output import UpstreamLog
    from robospec.physics.crash_diagnostics import process_died
    from robospec.physics.one_shot import Death, run_once

    assert item.robot is not None and item.context is not None
    request = Request(item.path.resolve(), item.display, controllers, traces)
    found = run_once("robospec.tune.worker", request, "robospec-tune-")
    if not isinstance(found, Death):
        tuned: TuneReport = found
        return tuned
    said = UpstreamLog()
    said.feed(found.log)
    report = TuneReport(item.display, item.robot.uid)
    if found.at_start:
        report.diagnostics.append(
            error(
                Location(item.display),
                ROBOT_NOT_LOADABLE,
                f"'{item.robot.uid}' cannot be tuned: the tune process could not start "
                f"({found.last_line()})",
                "it imports ManiSkill: install the maniskill extra (pip install -e "
                "'.[maniskill]'), then run robospec tune again",
            )
        )
        return report
    crash = from_fault_log(found.fault_log, found.returncode)
    report.diagnostics.append(
        process_died(item.context, item.robot.uid, crash, found.doing, said.messages())
    )
    report.messages = said.messages()
    return report
