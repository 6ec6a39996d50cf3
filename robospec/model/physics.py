"""Thresholds for ``robospec check``, the headless physics checks, as spec data.

Every field has a default that ManiSkill's own robots pass; a spec sets a field only when its
robot needs another bound, and the reason belongs in a comment next to it.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from robospec.model.common import Number, StrictModel
from robospec.model.refs import ControllerName, ControlModeName

PositiveNumber = Annotated[Number, Field(gt=0)]
Fraction = Annotated[Number, Field(ge=0)]
Steps = Annotated[int, Field(ge=1, le=100_000)]


class KeyframeHold(StrictModel):
    """Hold each keyframe with a joint-position mode and measure how far the robot drifts."""

    steps: Steps = Field(default=50, description="control steps to hold each keyframe")
    max_joint_drift: PositiveNumber = Field(
        default=0.05, description="largest joint drift allowed, in rad (or m for prismatic joints)"
    )
    max_root_drift: PositiveNumber = Field(
        default=0.05, description="largest drift of the root link's position allowed, in m"
    )
    mode: ControlModeName | None = Field(
        default=None,
        description="the control mode to hold with; default: the first mode whose controllers "
        "all take absolute joint positions",
    )
    pin_root: bool = Field(
        default=False,
        description="hold a floating root in place, as on a stand, and measure only the "
        "joints: for free-standing robots that need a balance controller to stay up",
    )


class RandomActions(StrictModel):
    """Send bounded random actions in every control mode; nothing may explode."""

    steps: Steps = Field(default=60, description="control steps per mode")
    seed: int = Field(default=0, description="seed of the random actions")
    joint_limit_tolerance: Fraction = Field(
        default=0.1,
        description="how far past a joint limit a joint may go before it counts as a violation, "
        "in rad (or m)",
    )
    max_joint_speed: PositiveNumber = Field(
        default=200.0, description="joint speed counted as runaway, in rad/s (or m/s)"
    )
    max_root_speed: PositiveNumber = Field(
        default=20.0, description="root link speed counted as runaway, in m/s"
    )


class StepLimits(StrictModel):
    """How one controller's step response is judged; every field defaults to the spec-wide
    ``step_response`` value."""

    duration: PositiveNumber | None = None
    max_rise_time: PositiveNumber | None = None
    max_overshoot: Fraction | None = None
    max_steady_state_error: Fraction | None = None


class StepResponse(StrictModel):
    """Command a small step to every position- or velocity-controlled group and time the
    response of each of its joints."""

    step: PositiveNumber = Field(
        default=0.1, description="the commanded step for revolute joints, in rad (or rad/s)"
    )
    prismatic_step: PositiveNumber = Field(
        default=0.01, description="the commanded step for prismatic joints, in m (or m/s)"
    )
    duration: PositiveNumber = Field(default=1.0, description="how long to watch, in seconds")
    max_rise_time: PositiveNumber = Field(
        default=0.5, description="longest time from 10% to 90% of the step allowed, in seconds"
    )
    max_overshoot: Fraction = Field(
        default=0.5, description="largest overshoot allowed, as a fraction of the step"
    )
    max_steady_state_error: Fraction = Field(
        default=0.2,
        description="largest error at the end of the window allowed, as a fraction of the step",
    )
    settling_band: Fraction = Field(
        default=0.1, description="the band, as a fraction of the step, that counts as settled"
    )
    controllers: dict[ControllerName, StepLimits] = Field(
        default_factory=dict,
        description="other limits for some controllers, by name (e.g. a body meant to move slowly)",
    )

    def for_controller(self, name: str) -> StepResponse:
        """These settings with ``controllers[name]``'s fields in place of the spec-wide ones."""
        limits = self.controllers.get(name)
        if limits is None:
            return self
        return self.model_copy(update={k: getattr(limits, k) for k in limits.model_fields_set})


class SelfContact(StrictModel):
    """At each keyframe, links of the robot that touch each other."""

    min_depth: Fraction = Field(
        default=0.001,
        description="penetration depth below which a touch is not reported, in m",
    )


class Checks(StrictModel):
    """Thresholds of ``robospec check`` for this robot."""

    keyframe_hold: KeyframeHold = Field(default_factory=KeyframeHold)
    random_actions: RandomActions = Field(default_factory=RandomActions)
    step_response: StepResponse = Field(default_factory=StepResponse)
    self_contact: SelfContact = Field(default_factory=SelfContact)
