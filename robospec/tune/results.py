"""What ``robospec tune`` finds, as plain records that cross from its worker process (they
pickle) and that the report, the plots and ``--write`` read."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

from robospec.diagnostics import Diagnostic, has_errors
from robospec.maniskill.upstream_output import UpstreamMessage

if TYPE_CHECKING:
    from robospec.physics.step_response import StepTrace

Status = Literal["met", "tuned", "failed", "skipped"]


@dataclass(frozen=True)
class Targets:
    """What one controller's step response is held to (``checks.tune`` for it)."""

    max_overshoot: float
    max_settling_time: float
    max_steady_state_error: float
    keep_force_limit: bool = False
    settling_band: float = 0.1  # checks.step_response's: what counts as settled


@dataclass(frozen=True)
class Gains:
    """Drive gains, one value per joint of the controller, in its joint order."""

    stiffness: tuple[float, ...]
    damping: tuple[float, ...]
    force_limit: tuple[float, ...]


@dataclass(frozen=True)
class Timing:
    """One joint's step response (check's measurement): fractions of the step, seconds."""

    joint: str
    overshoot: float
    settling_time: float | None  # None: never settled
    steady_state_error: float
    rise_time: float | None


@dataclass
class ControllerTuning:
    """One controller: its gains and responses before and after, and whether it meets its
    targets (``met``: as it was; ``tuned``: with the new gains; ``failed``: no gains found,
    ``reasons`` say why per joint; ``skipped``: not a joint position or velocity drive)."""

    controller: str
    mode: str
    group: str
    kind: str  # "position", "velocity", or the kind that was skipped
    joints: tuple[str, ...]
    status: Status
    targets: Targets | None = None
    before: Gains | None = None
    after: Gains | None = None
    before_timings: tuple[Timing, ...] = ()
    after_timings: tuple[Timing, ...] = ()
    before_trace: StepTrace | None = None
    after_trace: StepTrace | None = None
    reasons: tuple[tuple[str, str], ...] = ()  # (joint, why it cannot meet the targets)
    # (joint, the force its drive asked for, its rating): joints whose gains need more force
    # than the description rates their motor for (the force limit stays at the rating)
    over_rating: tuple[tuple[str, float, float], ...] = ()
    simulations: int = 0
    seconds: float = 0.0

    @property
    def changed(self) -> bool:
        return self.status == "tuned" and self.after != self.before


@dataclass
class TuneReport:
    """Everything ``robospec tune`` found for one spec."""

    spec: str
    uid: str | None
    controllers: list[ControllerTuning] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    messages: list[UpstreamMessage] = field(default_factory=list)
    written: bool = False
    plots: list[str] = field(default_factory=list)

    @property
    def failed(self) -> bool:
        return has_errors(self.diagnostics) or any(c.status == "failed" for c in self.controllers)
