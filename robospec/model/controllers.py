"""One model per ManiSkill controller-config type, field for field.

Field names and defaults follow ``mani_skill.agents.controllers`` (3.0.1) exactly, so a field a
user leaves out means what it means in ManiSkill. ``joints`` replaces ``joint_names`` and takes a
joint selection; per-joint values may be given by joint or group name. What each type is
beyond its fields (its config class, its action, the drive targets it sets) is its record in
:mod:`robospec.model.controller_kinds`.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Field

from robospec.model.common import JointSelection, Number, PerJoint, StrictModel
from robospec.model.refs import JointName, LinkName

DriveMode = Literal["force", "acceleration"]
Bound = PerJoint | None


def _type(name: str, what: str) -> Any:
    return Field(description=f"`{name}`: {what}", examples=[name])


def _drive_mode() -> Any:
    return Field(
        default="force",
        description="How the PD drive acts: `force` (a spring-damper force, the usual choice) or "
        "`acceleration` (independent of the links' mass); one for all joints or one per joint.",
        examples=["force"],
    )


def _normalize() -> Any:
    return Field(
        default=True,
        description="Take actions in [-1, 1] and scale them to [lower, upper]; false: an action is "
        "the target itself. Keep true for most learning setups.",
        examples=[True],
    )


def _use_delta() -> Any:
    return Field(
        default=False,
        description="Actions are changes to the current position (delta control) instead of "
        "absolute targets.",
        examples=[True],
    )


def _use_target() -> Any:
    return Field(
        default=False,
        description="With use_delta: add the action to the last target instead of the current "
        "position, so small errors do not accumulate.",
        examples=[True],
    )


def _interpolate() -> Any:
    return Field(
        default=False,
        description="Move the drive target linearly over the simulation steps of one control step "
        "instead of setting it at once.",
        examples=[False],
    )


def _force_limit() -> Any:
    return Field(
        default=1e10,
        description="The largest force (N) or torque (N·m) the drive may apply to each joint.",
        examples=[100],
    )


def _friction() -> Any:
    return Field(
        default=0.0, description="Friction of each joint, set on the joint.", examples=[0.05]
    )


class _Controller(StrictModel):
    joints: JointSelection = Field(
        description="The joints this controller drives, in action order: a joint, a group, a "
        "glob over active joints, or a list of them.",
        examples=["arm", "panda_joint[1-7]", ["panda_finger_joint1", "panda_finger_joint2"]],
    )


class _Drive(_Controller):
    damping: PerJoint = Field(
        description="Drive damping (the D gain) of each joint: one number for all, a list "
        "with one per joint, or a mapping by joint or group name.",
        examples=[1e2, {"arm": 1e2, "gripper": 1e2}],
    )
    force_limit: PerJoint = _force_limit()
    friction: PerJoint = _friction()


class PassiveConfig(_Drive):
    """A passive controller (`passive`): it takes no action and leaves its joints to physics,
    with the given damping and friction (e.g. the wheels of a caster)."""

    type: Literal["passive"] = _type("passive", "no action; the joints only feel damping.")


class PDJointVelConfig(_Drive):
    """Joint velocity targets (`pd_joint_vel`): each action is a target velocity per joint."""

    type: Literal["pd_joint_vel"] = _type("pd_joint_vel", "a velocity target per joint.")
    lower: Bound = Field(
        description="The lowest velocity target of each joint, in rad/s (or m/s); null: no bound.",
        examples=[-1.0],
    )
    upper: Bound = Field(
        description="The highest velocity target of each joint, in rad/s (or m/s); null: no bound.",
        examples=[1.0],
    )
    normalize_action: bool = _normalize()
    drive_mode: DriveMode | list[DriveMode] = _drive_mode()


class PDBaseVelConfig(PDJointVelConfig):
    """Mobile-base velocity in the world frame (`pd_base_vel`): x, y and yaw velocity targets
    for the base's three joints."""

    type: Literal["pd_base_vel"] = _type(  # type: ignore[assignment]
        "pd_base_vel", "x, y and yaw velocity of a mobile base, in the world frame."
    )


class PDBaseForwardVelConfig(PDJointVelConfig):
    """Mobile-base forward and turning velocity, ego-centric (`pd_base_forward_vel`): a
    2-D action (forward speed, turn rate) for the base's x, y and yaw joints."""

    type: Literal["pd_base_forward_vel"] = _type(  # type: ignore[assignment]
        "pd_base_forward_vel", "forward speed and turn rate of a mobile base."
    )


class PDJointPosConfig(_Drive):
    """Joint position targets (`pd_joint_pos`): absolute positions, or changes to them with
    `use_delta`."""

    type: Literal["pd_joint_pos"] = _type("pd_joint_pos", "a position target per joint.")
    lower: Bound = Field(
        description="The lowest target (rad or m; the lowest change with use_delta) of each "
        "joint; null: the joint's own lower limit.",
        examples=[-0.1, None],
    )
    upper: Bound = Field(
        description="The highest target (rad or m; the highest change with use_delta) of each "
        "joint; null: the joint's own upper limit.",
        examples=[0.1, None],
    )
    stiffness: PerJoint = Field(
        description="Drive stiffness (the P gain) of each joint: one number for all, a list "
        "with one per joint, or a mapping by joint or group name.",
        examples=[1e3, {"arm": 1e3, "gripper": 1e3}],
    )
    use_delta: bool = _use_delta()
    use_target: bool = _use_target()
    interpolate: bool = _interpolate()
    normalize_action: bool = _normalize()
    drive_mode: DriveMode | list[DriveMode] = _drive_mode()


class MimicTarget(StrictModel):
    """The joint a mimicking joint follows, with a scale and an offset:
    q = q_joint * multiplier + offset."""

    joint: JointName = Field(
        description="The controlling joint, which the action drives.",
        examples=["panda_finger_joint1"],
    )
    multiplier: Number = Field(
        default=1.0,
        description="How far the mimicking joint moves per unit of the controlling joint.",
        examples=[-1.0],
    )
    offset: Number = Field(
        default=0.0,
        description="Added to the mimicking joint's position, in rad (or m).",
        examples=[0.0],
    )


class PDJointPosMimicConfig(PDJointPosConfig):
    """Joint positions where some joints follow others (`pd_joint_pos_mimic`): only the
    controlling joints take actions, e.g. one action for a two-finger gripper."""

    type: Literal["pd_joint_pos_mimic"] = _type(  # type: ignore[assignment]
        "pd_joint_pos_mimic", "position targets where some joints copy others."
    )
    mimic: dict[
        JointName,
        Annotated[
            JointName | MimicTarget,
            Field(
                description="The joint it follows, or {joint, multiplier, offset}.",
                examples=["panda_finger_joint1"],
            ),
        ],
    ] = Field(
        default_factory=dict,
        description="Mimicking joint -> the joint it follows (or {joint, multiplier, offset}); "
        "every joint of the controller appears on one side.",
        examples=[{"panda_finger_joint2": "panda_finger_joint1"}],
    )


class PDJointPosVelConfig(PDJointPosConfig):
    """Joint position and velocity targets (`pd_joint_pos_vel`): each action holds a position
    target and then a velocity target per joint."""

    type: Literal["pd_joint_pos_vel"] = _type(  # type: ignore[assignment]
        "pd_joint_pos_vel", "a position and a velocity target per joint."
    )
    vel_lower: Bound = Field(
        default=-1.0,
        description="The lowest velocity target of each joint, in rad/s (or m/s).",
        examples=[-1.0],
    )
    vel_upper: Bound = Field(
        default=1.0,
        description="The highest velocity target of each joint, in rad/s (or m/s).",
        examples=[1.0],
    )


class DeltaSolver(StrictModel):
    """How inverse kinematics turns an end-effector change into joint changes."""

    type: Literal["levenberg_marquardt", "pseudo_inverse"] = Field(
        default="levenberg_marquardt",
        description="The solver: `levenberg_marquardt` (faster and more accurate, recommended) "
        "or `pseudo_inverse`.",
        examples=["levenberg_marquardt"],
    )
    alpha: Number = Field(
        default=1.0,
        description="Scale applied to the joint changes the solver returns.",
        examples=[1.0],
    )


class PDEEPosConfig(_Controller):
    """End-effector position through inverse kinematics (`pd_ee_pos`): actions move a link in
    x, y, z and the arm's joints follow."""

    type: Literal["pd_ee_pos"] = _type("pd_ee_pos", "the position of an end-effector link.")
    pos_lower: Number | list[Number] = Field(
        description="The lowest position (or change with use_delta) along x, y, z in metres: "
        "one number for all three or a list of three.",
        examples=[-0.1],
    )
    pos_upper: Number | list[Number] = Field(
        description="The highest position (or change with use_delta) along x, y, z in metres: "
        "one number for all three or a list of three.",
        examples=[0.1],
    )
    stiffness: PerJoint = Field(
        description="Drive stiffness (the P gain) of each arm joint.", examples=[1e3]
    )
    damping: PerJoint = Field(
        description="Drive damping (the D gain) of each arm joint.", examples=[1e2]
    )
    force_limit: PerJoint = _force_limit()
    friction: PerJoint = _friction()
    ee_link: LinkName = Field(
        description="The link to control; it need not be the last link of the arm.",
        examples=["panda_hand_tcp"],
    )
    urdf_path: str | None = Field(
        default=None,
        description="A URDF for the inverse-kinematics chain, relative to this spec; default: "
        "the robot's own description.",
        examples=["{maniskill_assets}/robots/panda/panda_v2.urdf"],
    )
    frame: Literal["body_translation", "root_translation"] = Field(
        default="root_translation",
        description="The frame actions move the link in: the robot's root (`root_translation`) "
        "or the link itself (`body_translation`, CPU simulation only).",
        examples=["root_translation"],
    )
    root_link_name: LinkName | None = Field(
        default=None,
        description="Another link to use as the root for root-frame control (e.g. when the "
        "arm sits on a moving base); default: the robot's root link.",
        examples=["torso_lift_link"],
    )
    use_delta: bool = Field(
        default=True,
        description="Actions are changes to the link's pose; false: absolute poses in the "
        "root frame.",
        examples=[True],
    )
    use_target: bool = Field(
        default=False,
        description="With use_delta: change the last target pose instead of the link's "
        "current pose.",
        examples=[True],
    )
    interpolate: bool = _interpolate()
    normalize_action: bool = _normalize()
    delta_solver_config: DeltaSolver | None = Field(
        default=None,
        description="Settings of the inverse-kinematics solver; default: ManiSkill's "
        "(levenberg_marquardt, alpha 1).",
        examples=[{"type": "levenberg_marquardt", "alpha": 1.0}],
    )
    drive_mode: DriveMode | list[DriveMode] = _drive_mode()


class PDEEPoseConfig(PDEEPosConfig):
    """End-effector position and orientation through inverse kinematics (`pd_ee_pose`):
    actions move and turn a link and the arm's joints follow."""

    type: Literal["pd_ee_pose"] = _type(  # type: ignore[assignment]
        "pd_ee_pose", "the position and orientation of an end-effector link."
    )
    rot_lower: Number | list[Number] = Field(
        default=-2 * math.pi,
        description="The lowest rotation (axis-angle, radians) per action: one number for all "
        "three axes or a list of three.",
        examples=[-0.1],
    )
    rot_upper: Number | list[Number] = Field(
        default=2 * math.pi,
        description="The highest rotation (axis-angle, radians) per action: one number for all "
        "three axes or a list of three.",
        examples=[0.1],
    )
    frame: Literal[
        "body_translation:root_aligned_body_rotation",
        "root_translation:root_aligned_body_rotation",
        "body_translation:body_aligned_body_rotation",
        "root_translation:body_aligned_body_rotation",
    ] = Field(  # type: ignore[assignment]  # the pose's frames add rotation's: a field retyped
        default="root_translation:root_aligned_body_rotation",
        description="The frames actions move and turn the link in, as translation:rotation; "
        "only the default works in GPU simulation.",
        examples=["root_translation:root_aligned_body_rotation"],
    )


ControllerConfig = Annotated[
    PDJointPosConfig
    | PDJointPosMimicConfig
    | PDJointVelConfig
    | PDJointPosVelConfig
    | PDEEPosConfig
    | PDEEPoseConfig
    | PDBaseVelConfig
    | PDBaseForwardVelConfig
    | PassiveConfig,
    Field(discriminator="type"),
]
