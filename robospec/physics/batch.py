"""``robospec check``: compile each spec, register its agent, and run the physics checks on it.

Specs that do not compile get their diagnostics and no checks; robots whose description is not
downloaded yet are reported as not checkable (RS510). Everything else runs every check, in a
fixed order, and reports :class:`~robospec.physics.findings.Finding` records.

Each robot is checked in isolation: in a worker process (``robospec.physics.isolation``), so a
robot that crashes ManiSkill or SAPIEN — a segmentation fault included — is a located
diagnostic (RS514-RS517) and every other robot's results are still reported; and each
measurement starts from a freshly built scene (``Sim.start``), so no result depends on which
checks ran before it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, SpecError, error, without_codes
from robospec.diagnostics.codes import ROBOT_NOT_LOADABLE
from robospec.maniskill.crash import Crash, from_exception
from robospec.model.frozen import Checks
from robospec.physics import (
    action_layout,
    crash_diagnostics,
    described,
    gravity,
    ground,
    keyframe_hold,
    loops,
    mimic_limits,
    random_actions,
    render,
    self_contact,
    step_response,
    task_run,
)
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status
from robospec.physics.isolation import WorkerPool
from robospec.physics.results import (
    DEFAULT_OPTIONS,
    LOAD,
    Options,
    Progress,
    RobotProgress,
    RobotReport,
)
from robospec.pipeline import CompiledSpec, compile_all, silenced_codes

# (name, check) in the order they run and are reported
CHECKS: tuple[tuple[str, Callable[[CheckRun], list[Finding]]], ...] = (
    (action_layout.NAME, action_layout.check),  # what the actions are, not how the robot behaves
    # before any behaviour: the robot loaded is the one described, or nothing more is judged
    (described.NAME, described.check),
    (ground.NAME, ground.check),
    (mimic_limits.NAME, mimic_limits.check),
    (keyframe_hold.NAME, keyframe_hold.check),
    (gravity.NAME, gravity.check),
    (self_contact.NAME, self_contact.check),
    (loops.NAME, loops.check),
    (step_response.NAME, step_response.check),
    (random_actions.NAME, random_actions.check),
)
Phase = Callable[[str], None]  # what is about to happen ("loading the robot in mode X")


def check_paths(
    paths: Sequence[Path],
    options: Options = DEFAULT_OPTIONS,
    progress: Progress | None = None,
    *,
    isolate: bool = True,
    silence: frozenset[str] = frozenset(),
) -> tuple[list[RobotReport], list[Diagnostic]]:
    """Reports for every spec found under ``paths``, plus diagnostics not tied to one spec.

    With ``isolate`` (the default) robots are checked in a worker process, one after another,
    and a worker that dies is replaced; without, in this process. ``silence``: warning codes
    not to report (``--silence``), with those each spec's ``silence`` lists — the simulation's
    warnings as well as the compiler's."""
    compiled, diagnostics = compile_all(paths, silence=silence)
    reports: list[RobotReport] = []
    pending = [(item, precheck(item)) for item in compiled]
    total = len(CHECKS) * sum(report is None for _, report in pending)
    done = 0
    with WorkerPool() as pool:
        for item, finished in pending:
            if finished is not None:
                reports.append(finished)
                continue

            def step(index: int, label: str, done: int = done) -> None:
                if progress is not None:
                    progress(done + index, total, label)

            report = (
                pool.check(item, options, step) if isolate else check_compiled(item, options, step)
            )
            reports.append(without_silenced(report, silenced_codes(item, silence)))
            done += len(CHECKS)
    if progress is not None:
        progress(total, total, "done")
    return reports, diagnostics


def without_silenced(report: RobotReport, codes: frozenset[str]) -> RobotReport:
    """``report`` without the warnings (never the errors) whose codes are silenced."""
    if codes:
        report.findings = [
            replace(f, diagnostics=tuple(without_codes(f.diagnostics, codes)))
            for f in report.findings
        ]
    return report


def precheck(item: CompiledSpec) -> RobotReport | None:
    """The finished report of a spec that cannot be checked (it does not compile, or its
    description is not downloaded: RS510), or None when it can."""
    robot = item.robot
    report = RobotReport(item.display, robot.uid if robot else None, [], list(item.diagnostics))
    if not item.ok or item.context is None or robot is None:
        return report
    if item.context.description.assumed:
        report.diagnostics.append(
            error(
                Location(item.display),
                ROBOT_NOT_LOADABLE,
                f"'{robot.uid}' cannot be checked: its robot description is not downloaded yet",
                "download it (python -m mani_skill.utils.download_asset "
                + " ".join(robot.download_ids or ("<id>",))
                + "), then run robospec check again",
            )
        )
        return report
    return None


def check_compiled(
    item: CompiledSpec,
    options: Options = DEFAULT_OPTIONS,
    progress: RobotProgress | None = None,
    on_phase: Phase | None = None,
) -> RobotReport:
    """Check one compiled spec in this process (what a worker process runs)."""
    finished = precheck(item)
    if finished is not None:
        return finished
    assert item.robot is not None
    findings, diagnostics = check_loaded(item, options, progress, on_phase)
    return RobotReport(item.display, item.robot.uid, findings, [*item.diagnostics, *diagnostics])


def check_loaded(
    item: CompiledSpec,
    options: Options = DEFAULT_OPTIONS,
    progress: RobotProgress | None = None,
    on_phase: Phase | None = None,
) -> tuple[list[Finding], list[Diagnostic]]:
    """Register the spec's agent and run every check: the findings, and diagnostics of the
    registration. A crash inside ManiSkill or SAPIEN (a Python exception) becomes a finding
    with its diagnostic; the checks that can still run, run."""
    robot, context = item.robot, item.context
    assert robot is not None and context is not None
    from robospec.output.register import register

    if on_phase is not None:
        on_phase("registering the agent")
    try:
        register(item.path)
    except SpecError as exc:
        return [], list(exc.diagnostics)
    except Exception as exc:  # the generated module or a hook crashed on import
        crash = from_exception(exc)
        diagnostic = crash_diagnostics.check_failure(context, "register", None, crash)
        return [_crashed(LOAD, None, crash, diagnostic)], []
    run = CheckRun(
        robot.uid, context, _settings(item, options), options.backend, on_phase, options.plot_dir
    )
    run.tasks = options.tasks
    try:
        findings = run_checks(run, progress)
        if options.render_dir is not None:
            findings.extend(render.check(run, options.render_dir))
        return findings, []
    finally:
        run.close()


def run_checks(run: CheckRun, progress: RobotProgress | None = None) -> list[Finding]:
    """Every check of :data:`CHECKS` on ``run``'s robot, each mode's environment made first: a
    mode ManiSkill or SAPIEN cannot make, or a check that crashes inside them (a Python
    exception), becomes a finding with its diagnostic, and the checks that can still run, run."""
    broken = run.open_modes()
    if broken and not run.modes:
        return _unloadable(run, broken)
    findings = [
        _crashed(LOAD, mode, crash, crash_diagnostics.mode_failure(run.context, mode, crash))
        for mode, crash in broken.items()
    ]
    for index, (name, check) in enumerate(CHECKS):
        if progress is not None:
            progress(index, f"{run.uid}: {name}")
        run.check = name
        try:
            findings.extend(check(run))
        except Exception as exc:  # upstream's crash becomes a diagnostic
            crash = from_exception(exc)
            diagnostic = crash_diagnostics.check_failure(run.context, name, run.mode, crash)
            findings.append(_crashed(name, run.mode, crash, diagnostic))
        if described.failed(findings):
            # behaviour of another robot than the one described proves nothing about it
            return findings + [_not_judged(name) for name, _ in CHECKS[index + 1 :]]
    if run.tasks and not run.backend.gpu:
        if progress is not None:
            progress(len(CHECKS), f"{run.uid}: tasks")
        run.check = task_run.NAME
        findings.extend(task_run.check(run, run.tasks))
    return findings


def _unloadable(run: CheckRun, broken: dict[str, Crash]) -> list[Finding]:
    """No mode loads: one RS514 when they all fail alike (the robot itself), else one RS516
    per mode."""
    crashes = list(broken.values())
    if len({(c.what, c.frame) for c in crashes}) == 1:
        diagnostic = crash_diagnostics.load_failure(run.context, run.uid, crashes[0])
        return [_crashed(LOAD, None, crashes[0], diagnostic)]
    return [
        _crashed(LOAD, mode, crash, crash_diagnostics.mode_failure(run.context, mode, crash))
        for mode, crash in broken.items()
    ]


def _not_judged(check: str) -> Finding:
    return Finding(
        check, None, "-", Status.SKIP, f"not judged: not the robot described ({described.NAME})"
    )


def _crashed(check: str, mode: str | None, crash: Crash, diagnostic: Diagnostic) -> Finding:
    return Finding(check, mode, "-", Status.FAIL, f"crashed: {crash.what}", {}, (diagnostic,))


def _settings(item: CompiledSpec, options: Options) -> Checks:
    """The spec's thresholds, with ``--steps`` applied."""
    assert item.context is not None
    settings = item.context.spec.checks
    if options.steps is None:
        return settings
    steps = {"steps": options.steps}
    return settings.model_copy(
        update={
            "keyframe_hold": settings.keyframe_hold.model_copy(update=steps),
            "random_actions": settings.random_actions.model_copy(update=steps),
        }
    )


__all__ = [
    "CHECKS",
    "Options",
    "RobotReport",
    "check_compiled",
    "check_loaded",
    "check_paths",
    "precheck",
    "run_checks",
]
