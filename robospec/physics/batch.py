"""``robospec check``: compile each spec, register its agent, and run the physics checks on it.

Specs that do not compile get their diagnostics and no checks; robots whose description is not
downloaded yet are reported as not checkable (RS510). Everything else runs every check, in a
fixed order, and reports :class:`~robospec.physics.findings.Finding` records.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, SpecError, error, has_errors
from robospec.model.frozen import Checks
from robospec.physics import (
    action_layout,
    keyframe_hold,
    random_actions,
    render,
    self_contact,
    step_response,
)
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding
from robospec.physics.sim import CPU, Backend
from robospec.pipeline import CompiledSpec, compile_all

# (name, check) in the order they run and are reported
CHECKS: tuple[tuple[str, Callable[[CheckRun], list[Finding]]], ...] = (
    (action_layout.NAME, action_layout.check),
    (keyframe_hold.NAME, keyframe_hold.check),
    (self_contact.NAME, self_contact.check),
    (step_response.NAME, step_response.check),
    (random_actions.NAME, random_actions.check),
)


@dataclass
class RobotReport:
    spec: str
    uid: str | None
    findings: list[Finding] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)  # from compiling the spec

    @property
    def failed(self) -> bool:
        return has_errors(self.diagnostics) or any(f.failed for f in self.findings)

    @property
    def all_diagnostics(self) -> list[Diagnostic]:
        return self.diagnostics + [d for f in self.findings for d in f.diagnostics]


@dataclass(frozen=True)
class Options:
    steps: int | None = None  # overrides keyframe_hold.steps and random_actions.steps
    backend: Backend = CPU
    render_dir: Path | None = None  # save each camera's image there (needs a render device)


Progress = Callable[[int, int, str], None]  # (checks done, checks in all, what runs now)


def check_paths(
    paths: Sequence[Path], options: Options = Options(), progress: Progress | None = None
) -> tuple[list[RobotReport], list[Diagnostic]]:
    """Reports for every spec found under ``paths``, plus diagnostics not tied to one spec."""
    compiled, diagnostics = compile_all(paths)
    total = len(CHECKS) * sum(item.ok for item in compiled)
    reports = []
    done = 0
    for item in compiled:

        def step(index: int, label: str, done: int = done) -> None:
            if progress is not None:
                progress(done + index, total, label)

        reports.append(check_compiled(item, options, step))
        done += len(CHECKS) if item.ok else 0
    if progress is not None:
        progress(total, total, "done")
    return reports, diagnostics


def check_compiled(
    item: CompiledSpec,
    options: Options = Options(),
    progress: Callable[[int, str], None] | None = None,
) -> RobotReport:
    robot = item.robot
    report = RobotReport(item.display, robot.uid if robot else None, [], list(item.diagnostics))
    if not item.ok or item.context is None or robot is None:
        return report
    if item.context.description.assumed:
        report.diagnostics.append(
            error(
                Location(item.display),
                "RS510",
                f"'{robot.uid}' cannot be checked: its robot description is not downloaded yet",
                "download it (python -m mani_skill.utils.download_asset "
                + " ".join(robot.download_ids or ("<id>",))
                + "), then run robospec check again",
            )
        )
        return report
    from robospec.output.register import register

    try:
        register(item.path)
    except SpecError as exc:
        report.diagnostics.extend(exc.diagnostics)
        return report
    run = CheckRun(robot.uid, item.context, _settings(item, options), options.backend)
    try:
        for index, (name, check) in enumerate(CHECKS):
            if progress is not None:
                progress(index, f"{robot.uid}: {name}")
            report.findings.extend(check(run))
        if options.render_dir is not None:
            report.findings.extend(render.check(run, options.render_dir))
    finally:
        run.close()
    return report


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


__all__ = ["CHECKS", "Options", "RobotReport", "check_compiled", "check_paths"]
