"""One model per ManiSkill controller-config type, field for field.

Field names and defaults follow ``mani_skill.agents.controllers`` (3.0.1) exactly, so a field a
user leaves out means what it means in ManiSkill. ``joints`` replaces ``joint_names`` and takes a
joint selection; per-joint values may be given by joint or group name.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field

from robospec.model.common import JointSelection, Number, PerJoint, StrictModel
from robospec.model.refs import JointName, JointPattern, LinkName

DriveMode = Literal["force", "acceleration"]
Bound = Number | list[Number] | dict[JointPattern, Number] | None


class _Controller(StrictModel):
    joints: JointSelection = Field(description="the joints this controller drives, in order")


class _Drive(_Controller):
    damping: PerJoint = Field(description="drive damping per joint")
    force_limit: PerJoint = Field(default=1e10, description="drive force limit per joint")
    friction: PerJoint = Field(default=0.0, description="joint friction per joint")


class PassiveConfig(_Drive):
    """No action: the joints are left to physics with the given damping (``passive``)."""

    type: Literal["passive"]


class PDJointVelConfig(_Drive):
    """Joint velocity targets (``pd_joint_vel``)."""

    type: Literal["pd_joint_vel"]
    lower: Bound = Field(description="lower velocity bound per joint")
    upper: Bound = Field(description="upper velocity bound per joint")
    normalize_action: bool = True
    drive_mode: DriveMode | list[DriveMode] = "force"


class PDBaseVelConfig(PDJointVelConfig):
    """Mobile-base velocity in the world frame (``pd_base_vel``)."""

    type: Literal["pd_base_vel"]  # type: ignore[assignment]


class PDBaseForwardVelConfig(PDJointVelConfig):
    """Mobile-base forward and turning velocity, ego-centric (``pd_base_forward_vel``)."""

    type: Literal["pd_base_forward_vel"]  # type: ignore[assignment]


class PDJointPosConfig(_Drive):
    """Joint position targets, absolute or delta (``pd_joint_pos``)."""

    type: Literal["pd_joint_pos"]
    lower: Bound = Field(description="lower bound per joint; null for none")
    upper: Bound = Field(description="upper bound per joint; null for none")
    stiffness: PerJoint = Field(description="drive stiffness per joint")
    use_delta: bool = False
    use_target: bool = False
    interpolate: bool = False
    normalize_action: bool = True
    drive_mode: DriveMode | list[DriveMode] = "force"


class MimicTarget(StrictModel):
    joint: JointName = Field(description="the controlling joint")
    multiplier: Number = 1.0
    offset: Number = 0.0


class PDJointPosMimicConfig(PDJointPosConfig):
    """Joint positions where some joints follow others: q = q_joint * multiplier + offset."""

    type: Literal["pd_joint_pos_mimic"]  # type: ignore[assignment]
    mimic: dict[JointName, JointName | MimicTarget] = Field(
        default_factory=dict,
        description="mimicking joint -> controlling joint (or {joint, multiplier, offset})",
    )


class PDJointPosVelConfig(PDJointPosConfig):
    """Joint position and velocity targets (``pd_joint_pos_vel``)."""

    type: Literal["pd_joint_pos_vel"]  # type: ignore[assignment]
    vel_lower: Bound = -1.0
    vel_upper: Bound = 1.0


class DeltaSolver(StrictModel):
    type: Literal["levenberg_marquardt", "pseudo_inverse"] = "levenberg_marquardt"
    alpha: Number = 1.0


class PDEEPosConfig(_Controller):
    """End-effector position through inverse kinematics (``pd_ee_pos``)."""

    type: Literal["pd_ee_pos"]
    pos_lower: Number | list[Number]
    pos_upper: Number | list[Number]
    stiffness: PerJoint
    damping: PerJoint
    force_limit: PerJoint = 1e10
    friction: PerJoint = 0.0
    ee_link: LinkName = Field(description="the link to control")
    urdf_path: str | None = Field(
        default=None, description="URDF for the IK chain; default: the robot's own description"
    )
    frame: Literal["body_translation", "root_translation"] = "root_translation"
    root_link_name: LinkName | None = None
    use_delta: bool = True
    use_target: bool = False
    interpolate: bool = False
    normalize_action: bool = True
    delta_solver_config: DeltaSolver | None = None
    drive_mode: DriveMode | list[DriveMode] = "force"


class PDEEPoseConfig(PDEEPosConfig):
    """End-effector position and orientation through inverse kinematics (``pd_ee_pose``)."""

    type: Literal["pd_ee_pose"]  # type: ignore[assignment]
    rot_lower: Number | list[Number] = -2 * math.pi
    rot_upper: Number | list[Number] = 2 * math.pi
    stiffness: PerJoint | None = None  # type: ignore[assignment]
    damping: PerJoint | None = None  # type: ignore[assignment]
    frame: Literal[  # type: ignore[assignment]
        "body_translation:root_aligned_body_rotation",
        "root_translation:root_aligned_body_rotation",
        "body_translation:body_aligned_body_rotation",
        "root_translation:body_aligned_body_rotation",
    ] = "root_translation:root_aligned_body_rotation"


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

CONTROLLER_TYPES: tuple[str, ...] = (
    "pd_joint_pos",
    "pd_joint_pos_mimic",
    "pd_joint_vel",
    "pd_joint_pos_vel",
    "pd_ee_pos",
    "pd_ee_pose",
    "pd_base_vel",
    "pd_base_forward_vel",
    "passive",
)
