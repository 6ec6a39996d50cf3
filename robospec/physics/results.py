"""What ``robospec check`` reports per robot, and the options it runs with: plain records that
cross from a worker process to ``robospec check`` (they pickle)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robospec.diagnostics import Diagnostic, has_errors
from robospec.maniskill.upstream_output import UpstreamMessage
from robospec.physics.findings import Finding
from robospec.physics.sim import CPU, Backend


@dataclass
class RobotReport:
    spec: str
    uid: str | None
    findings: list[Finding] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)  # from compiling the spec
    # what ManiSkill and SAPIEN printed while the robot was checked, each distinct message once
    messages: list[UpstreamMessage] = field(default_factory=list)

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
    plot_dir: Path | None = None  # save a PNG of each controller's step response there
    # check --task: the tasks to run each robot in (robospec.physics.task_run.TaskRequest)
    tasks: tuple[Any, ...] = ()


DEFAULT_OPTIONS = Options()
LOAD = "load"  # the check of a finding about a robot or a mode that could not be loaded
Progress = Callable[[int, int, str], None]  # (checks done, checks in all, what runs now)
RobotProgress = Callable[[int, str], None]  # (checks of this robot done, what runs now)
