"""Tune one compiled spec in this process (what the worker process runs): register its agent,
then search each controller's gains (``robospec.tune.search``) in the first mode that uses it,
as ``robospec check`` steps each controller once. A crash inside ManiSkill or SAPIEN is a
diagnostic (RS514, RS516, RS517), never a traceback."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from robospec.description.ratings import joint_ratings
from robospec.diagnostics import SpecError
from robospec.maniskill.crash import from_exception
from robospec.physics import crash_diagnostics
from robospec.physics.batch import precheck
from robospec.physics.check_run import CheckRun
from robospec.pipeline import CompiledSpec
from robospec.tune.results import ControllerTuning, TuneReport
from robospec.tune.search import Search
from robospec.tune.targets import targets_for

CHECK = "tune"


def tune_compiled(
    item: CompiledSpec,
    only: Sequence[str] = (),
    phase: Callable[[str], None] | None = None,
    traces: bool = True,
) -> TuneReport:
    finished = precheck(item)
    if finished is not None:
        return TuneReport(finished.spec, finished.uid, [], finished.diagnostics)
    robot, context = item.robot, item.context
    assert robot is not None and context is not None
    report = TuneReport(item.display, robot.uid, [], list(item.diagnostics))
    from robospec.output.register import register

    if phase is not None:
        phase("registering the agent")
    try:
        register(item.path)
    except SpecError as exc:
        report.diagnostics.extend(exc.diagnostics)
        return report
    except Exception as exc:  # the generated module or a hook crashed on import
        crash = from_exception(exc)
        report.diagnostics.append(crash_diagnostics.check_failure(context, "register", None, crash))
        return report
    run = CheckRun(robot.uid, context, context.spec.checks, on_phase=phase)
    run.check = CHECK
    try:
        broken = run.open_modes()
        for mode, crash in broken.items():
            report.diagnostics.append(crash_diagnostics.mode_failure(context, mode, crash))
        if broken and not run.modes:
            crashes = list(broken.values())
            report.diagnostics[-len(crashes) :] = [
                crash_diagnostics.load_failure(context, robot.uid, crashes[0])
            ]
            return report
        for mode in run.modes:
            _tune_mode(run, mode, only, report, traces)
    finally:
        run.close()
    return report


def _tune_mode(
    run: CheckRun, mode: str, only: Sequence[str], report: TuneReport, traces: bool
) -> None:
    seen = {c.controller for c in report.controllers}
    try:
        sim = run.sim(mode)
        groups = sim.groups()
    except Exception as exc:  # upstream's crash becomes a diagnostic
        crash = from_exception(exc)
        report.diagnostics.append(crash_diagnostics.check_failure(run.context, CHECK, mode, crash))
        return
    for group in groups:
        controller = run.controller_name(mode, group.name)
        if controller in seen or (only and controller not in only):
            continue
        seen.add(controller)
        if group.kind not in ("position", "velocity") or not group.joint_indices:
            joints = tuple(sim.joint_names[j] for j in group.joint_indices)
            report.controllers.append(
                ControllerTuning(controller, mode, group.name, group.kind, joints, "skipped")
            )
            continue
        run.phase(f"tuning controller {controller} in mode {mode}")
        step = run.settings.step_response.for_controller(controller)
        ratings = joint_ratings(run.context.description)
        caps = np.array(
            [
                ratings[name].value if name in ratings else np.inf
                for name in (sim.joint_names[j] for j in group.joint_indices)
            ]
        )
        search = Search(
            sim,
            group.name,
            controller,
            run.keyframes[0],
            step,
            targets_for(run.settings, controller),
            force_caps=caps,
        )
        try:
            result = search.run()
        except Exception as exc:  # upstream's crash becomes a diagnostic
            crash = from_exception(exc)
            report.diagnostics.append(
                crash_diagnostics.check_failure(run.context, CHECK, mode, crash)
            )
            continue
        if not traces:
            result.before_trace = result.after_trace = None
        report.controllers.append(result)
