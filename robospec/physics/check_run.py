"""What every physics check gets: the compiled robot, its thresholds and its simulations."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, Location, error
from robospec.load.source_map import KeyPath
from robospec.maniskill.crash import Crash, from_exception
from robospec.model.frozen import Checks
from robospec.physics.sim import CPU, Backend, Sim
from robospec.resolve.resolved import ResolvedKeyframe, ResolvedRobot


@dataclass
class CheckRun:
    """One robot under check. ``sim(mode)`` gives that mode's environment, made once and
    shared by the checks (each starts from a freshly built scene: ``Sim.start``).

    ``on_phase`` hears what is about to happen ("loading the robot in mode X", "keyframe_hold
    in mode X"): if it kills the process, the parent of a worker process can say what it was."""

    uid: str
    context: CheckContext
    settings: Checks
    backend: Backend = CPU
    on_phase: Callable[[str], None] | None = None
    plot_dir: Path | None = None  # check --plot: one PNG of each controller's step there
    check: str | None = None  # the check running now
    mode: str | None = None  # the mode it used last
    # modes whose environment could not be made, with what crashed (robospec.maniskill.crash)
    broken: dict[str, Crash] = field(default_factory=dict)
    # which links start inside the ground, by start (robospec.physics.ground)
    clearances: dict[str, Any] = field(default_factory=dict)
    # check --task: the tasks to run the robot in (robospec.physics.task_run.TaskRequest)
    tasks: tuple[Any, ...] = ()
    _sims: dict[str, Sim] = field(default_factory=dict)

    @property
    def robot(self) -> ResolvedRobot:
        return self.context.robot

    @property
    def modes(self) -> list[str]:
        """The control modes the checks walk through: every mode of the spec that loads."""
        return [m.name for m in self.context.robot.modes if m.name not in self.broken]

    @property
    def keyframes(self) -> list[ResolvedKeyframe | None]:
        """The spec's keyframes, or the robot as the environment loads it when there are none."""
        return list(self.context.robot.keyframes) or [None]

    def sim(self, mode: str) -> Sim:
        self.mode = mode
        if mode not in self._sims:
            self.phase(f"loading the robot in mode {mode}")
            self._sims[mode] = Sim(self.uid, mode, self.backend)
        self.phase(f"running {self.check} in mode {mode}" if self.check else f"mode {mode}")
        return self._sims[mode]

    def phase(self, doing: str) -> None:
        if self.on_phase is not None:
            self.on_phase(doing)

    def open_modes(self) -> dict[str, Crash]:
        """Make every mode's environment; returns ``{mode: crash}`` for those ManiSkill or
        SAPIEN could not make (they leave :attr:`modes`)."""
        for mode in [m.name for m in self.context.robot.modes]:
            try:
                self.sim(mode)
            except Exception as exc:  # upstream's crash becomes a diagnostic
                self.broken[mode] = from_exception(exc)
        return dict(self.broken)

    def close(self) -> None:
        for sim in self._sims.values():
            sim.close()
        self._sims.clear()

    def at(self, path: KeyPath) -> Location:
        """The spec position of ``path``'s key (falling back to the nearest written parent)."""
        return self.context.key(path)

    def keyframe_path(self, keyframe: ResolvedKeyframe | None) -> KeyPath:
        return ("keyframes", keyframe.name) if keyframe is not None else ("uid",)

    def controller_name(self, mode: str, group: str) -> str:
        """The spec's controller name behind ``group`` of ``mode``."""
        resolved = next(m for m in self.context.robot.modes if m.name == mode)
        if resolved.groups is None:
            return resolved.controller or group
        return dict(resolved.groups).get(group, group)

    def fail(self, path: KeyPath, code: str, message: str, hint: str | None = None) -> Diagnostic:
        return error(self.at(path), code, message, hint)


def keyframe_label(keyframe: ResolvedKeyframe | None) -> str:
    return keyframe.name if keyframe is not None else "(initial)"
