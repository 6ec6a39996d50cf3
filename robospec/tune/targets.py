"""What a controller is tuned for: the spec's ``checks.tune``, with its per-controller
overrides (``checks.tune.controllers``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from robospec.tune.results import Targets

if TYPE_CHECKING:
    from robospec.model.frozen import Checks


def targets_for(checks: Checks, controller: str) -> Targets:
    """``checks`` is the spec's ``checks`` section (a frozen-model record)."""
    tune = checks.tune.for_controller(controller)
    step = checks.step_response.for_controller(controller)
    return Targets(
        max_overshoot=float(tune.max_overshoot),
        max_settling_time=float(tune.max_settling_time),
        max_steady_state_error=float(tune.max_steady_state_error),
        keep_force_limit=bool(tune.keep_force_limit),
        settling_band=float(step.settling_band),
    )
