"""Thresholds for ``robospec check``, the headless physics checks, as spec data.

Every field has a default that ManiSkill's own robots pass; a spec sets a field only when its
robot needs another bound, and the reason belongs in a comment next to it.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from robospec.model.common import Number, StrictModel
from robospec.model.refs import ControllerName, ControlModeName
from robospec.model.rules import StepResponseBehaviour
from robospec.model.thresholds import MAX_JOINT_DRIFT, MIN_CONTACT_DEPTH, PRISMATIC_STEP, STEP

PositiveNumber = Annotated[Number, Field(gt=0)]
Fraction = Annotated[Number, Field(ge=0)]
Steps = Annotated[int, Field(ge=1, le=100_000)]


class KeyframeHold(StrictModel):
    """Hold each keyframe with a joint-position mode and measure how far the robot drifts."""

    steps: Steps = Field(
        default=50, description="Control steps to hold each keyframe for.", examples=[100]
    )
    max_joint_drift: PositiveNumber = Field(
        default=MAX_JOINT_DRIFT,
        description="The largest joint drift allowed, in rad (or m for prismatic joints).",
        examples=[0.1],
    )
    max_root_drift: PositiveNumber = Field(
        default=0.05,
        description="The largest drift of the root link's position allowed, in m.",
        examples=[0.1],
    )
    mode: ControlModeName | None = Field(
        default=None,
        description="The control mode to hold with; default: the first mode whose controllers "
        "all take absolute joint positions.",
        examples=["pd_joint_pos"],
    )
    pin_root: bool = Field(
        default=False,
        description="Hold a floating root in place, as on a stand, and measure only the "
        "joints: for free-standing robots that need a balance controller to stay up.",
        examples=[True],
    )


class RandomActions(StrictModel):
    """Send bounded random actions in every control mode; nothing may explode."""

    steps: Steps = Field(default=60, description="Control steps per mode.", examples=[100])
    seed: int = Field(default=0, description="Seed of the random actions.", examples=[1])
    joint_limit_tolerance: Fraction = Field(
        default=0.1,
        description="How far past a joint limit a joint may go before it counts as a "
        "violation, in rad (or m).",
        examples=[0.2],
    )
    max_joint_speed: PositiveNumber = Field(
        default=200.0,
        description="The joint speed counted as a runaway, in rad/s (or m/s).",
        examples=[100],
    )
    max_root_speed: PositiveNumber = Field(
        default=20.0,
        description="The speed of a floating robot's centre of mass counted as a runaway, in m/s.",
        examples=[10],
    )


class StepLimits(StrictModel):
    """How one controller's step response is judged; every field defaults to the spec-wide
    ``step_response`` value."""

    duration: PositiveNumber | None = Field(
        default=None,
        description="How long to watch, in seconds; default: the spec-wide value.",
        examples=[5],
    )
    max_rise_time: PositiveNumber | None = Field(
        default=None,
        description="The longest 10%-to-90% rise time allowed, in seconds; default: the "
        "spec-wide value.",
        examples=[3],
    )
    max_overshoot: Fraction | None = Field(
        default=None,
        description="The largest overshoot allowed, as a fraction of the step; default: the "
        "spec-wide value.",
        examples=[0.8],
    )
    max_steady_state_error: Fraction | None = Field(
        default=None,
        description="The largest error at the end of the window, as a fraction of the step; "
        "default: the spec-wide value.",
        examples=[0.3],
    )


class StepResponse(StrictModel, StepResponseBehaviour):
    """Command a small step to every position- or velocity-controlled group and time the
    response of each of its joints."""

    step: PositiveNumber = Field(
        default=STEP,
        description="The commanded step for revolute joints, in rad (or rad/s).",
        examples=[0.05],
    )
    prismatic_step: PositiveNumber = Field(
        default=PRISMATIC_STEP,
        description="The commanded step for prismatic joints, in m (or m/s).",
        examples=[0.005],
    )
    duration: PositiveNumber = Field(
        default=1.0, description="How long to watch, in seconds.", examples=[2]
    )
    max_rise_time: PositiveNumber = Field(
        default=0.5,
        description="The longest time from 10% to 90% of the step allowed, in seconds.",
        examples=[1],
    )
    max_overshoot: Fraction = Field(
        default=0.5,
        description="The largest overshoot allowed, as a fraction of the step.",
        examples=[0.3],
    )
    max_steady_state_error: Fraction = Field(
        default=0.2,
        description="The largest error at the end of the window allowed, as a fraction of "
        "the step.",
        examples=[0.1],
    )
    settling_band: Fraction = Field(
        default=0.1,
        description="The band around the target, as a fraction of the step, that counts as "
        "settled.",
        examples=[0.05],
    )
    controllers: dict[ControllerName, StepLimits] = Field(
        default_factory=dict,
        description="Other limits for some controllers, by controller name (e.g. a heavy body "
        "meant to move slowly).",
        examples=[{"stiff_body_pos": {"duration": 5, "max_rise_time": 3}}],
    )


class TuneLimits(StrictModel):
    """What ``robospec tune`` aims for with one controller; every field defaults to the
    spec-wide ``tune`` value."""

    max_overshoot: Fraction | None = Field(
        default=None,
        description="The largest overshoot to aim for, as a fraction of the step; default: "
        "the spec-wide value.",
        examples=[0.1],
    )
    max_settling_time: PositiveNumber | None = Field(
        default=None,
        description="The longest settling time to aim for, in seconds; default: the "
        "spec-wide value.",
        examples=[1.0],
    )
    max_steady_state_error: Fraction | None = Field(
        default=None,
        description="The largest steady-state error to aim for, as a fraction of the step; "
        "default: the spec-wide value.",
        examples=[0.05],
    )
    keep_force_limit: bool | None = Field(
        default=None,
        description="Never raise this controller's force_limit; default: the spec-wide value.",
        examples=[True],
    )


class Tune(StrictModel, StepResponseBehaviour):
    """What ``robospec tune`` aims for: each joint's response to the step of
    ``step_response`` (same step, duration and settling band), within these bounds."""

    max_overshoot: Fraction = Field(
        default=0.05,
        description="The largest overshoot to aim for, as a fraction of the step.",
        examples=[0.1],
    )
    max_settling_time: PositiveNumber = Field(
        default=0.5,
        description="The longest time to settle within `step_response.settling_band` of "
        "the target, in seconds.",
        examples=[1.0],
    )
    max_steady_state_error: Fraction = Field(
        default=0.02,
        description="The largest error at the end of the window, as a fraction of the step.",
        examples=[0.05],
    )
    keep_force_limit: bool = Field(
        default=False,
        description="Never raise a force_limit (a real motor's torque limit): a target that "
        "needs more torque is reported as not met instead.",
        examples=[True],
    )
    controllers: dict[ControllerName, TuneLimits] = Field(
        default_factory=dict,
        description="Other targets for some controllers, by controller name.",
        examples=[{"body_pos": {"max_settling_time": 1.0}}],
    )


class SelfContact(StrictModel):
    """At each keyframe, links of the robot that touch each other."""

    min_depth: Fraction = Field(
        default=MIN_CONTACT_DEPTH,
        description="The penetration depth below which a touch is not reported, in m.",
        examples=[0.002],
    )


class Loops(StrictModel):
    """The closed loops (``loops``): their two points together at rest, and while the robot
    moves."""

    max_gap_at_rest: Fraction = Field(
        default=0.005,
        description="The largest distance between a loop's two points at each keyframe (and "
        "as loaded), before anything moves, in m: farther, the points do not meet.",
        examples=[0.002],
    )
    max_gap: Fraction = Field(
        default=0.001,
        description="The largest distance between a loop's two points under random actions, "
        "in m: farther, the loop pulls apart.",
        examples=[0.002],
    )


class CameraViews(StrictModel):
    """What each camera sees in the pictures of ``robospec doc --images``: a segmentation
    picture from the camera's mount at every keyframe, of the robot alone and at a table."""

    max_mount_fraction: Fraction = Field(
        default=0.5,
        description="The largest fraction of a camera's picture its own mount link (and the "
        "links fixed to it) may cover.",
        examples=[0.7],
    )
    max_robot_fraction: Fraction = Field(
        default=0.9,
        description="The largest fraction of a camera's picture of the robot alone that the "
        "robot may cover.",
        examples=[0.95],
    )
    min_seen_fraction: Fraction = Field(
        default=0.02,
        description="The smallest fraction of a camera's picture at the table in which "
        "something (robot, table, cube, ground) lies within the camera's far plane.",
        examples=[0.1],
    )
    tcp_in_view: bool = Field(
        default=True,
        description="A camera that moves with the tcp (mounted on the tcp's link or on a "
        "link fixed to it) must see the tcp.",
        examples=[False],
    )
    table_height: Number | None = Field(
        default=None,
        description="The height of the table top in the cameras' table scene, in m; default: "
        "level with the robot's root link at the keyframe.",
        examples=[0.75],
    )


class Checks(StrictModel):
    """Thresholds of ``robospec check`` for this robot."""

    keyframe_hold: KeyframeHold = Field(
        default_factory=KeyframeHold,
        description="Hold each keyframe and measure the drift.",
        examples=[{"pin_root": True}],
    )
    random_actions: RandomActions = Field(
        default_factory=RandomActions,
        description="Random actions in every control mode.",
        examples=[{"steps": 100}],
    )
    step_response: StepResponse = Field(
        default_factory=StepResponse,
        description="Step responses of the position and velocity controllers.",
        examples=[{"controllers": {"stiff_body_pos": {"duration": 5, "max_rise_time": 3}}}],
    )
    self_contact: SelfContact = Field(
        default_factory=SelfContact,
        description="Links touching each other at the keyframes.",
        examples=[{"min_depth": 0.002}],
    )
    loops: Loops = Field(
        default_factory=Loops,
        description="Closed loops staying closed.",
        examples=[{"max_gap": 0.002}],
    )
    tune: Tune = Field(
        default_factory=Tune,
        description="What `robospec tune` aims for with each controller's step response.",
        examples=[{"max_overshoot": 0.1, "max_settling_time": 1.0}],
    )
    camera_views: CameraViews = Field(
        default_factory=CameraViews,
        description="What each camera must see in the pictures of `robospec doc --images`.",
        examples=[{"max_robot_fraction": 0.95, "table_height": 0.75}],
    )
