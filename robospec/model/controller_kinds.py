"""Every controller ``type`` a spec can name, one record each: which ManiSkill config it is, the
fields that config takes, and what robospec's stages need to know of it (whether its drives
take position or velocity targets, whether it moves an end effector through IK or follows a
mimic map, how its action is laid out and bounded, which fields are gains).

This is the one place a controller kind is described: the emitter, the importer, the checks,
physics, tune and authoring read it instead of keeping tables of their own. A new kind is one
record here plus its pydantic model in :mod:`robospec.model.controllers` (the spec's fields,
their types and documentation). What a record says of ManiSkill (the config's class and
fields, its defaults, which drive targets its controller sets) is proved against the installed
ManiSkill by ``tests/test_controller_fields.py``.

Plain data, no pydantic: ``robospec validate`` reads the names here without loading it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

# where the generated modules import every config class from (ManiSkill's public package)
CONFIG_MODULE = "mani_skill.agents.controllers"

# the drive properties a config sets on its joints, in the order ManiSkill's agents write them
GAINS = ("stiffness", "damping", "force_limit", "friction")
# fields that take one value per joint wherever a config has them (a scalar for all, a list in
# joint order, or a mapping by joint or group name), unless they bound named axes of the action
# (:meth:`ControllerKind.axes_bounded_by`)
PER_JOINT_FIELDS = (*GAINS, "lower", "upper", "vel_lower", "vel_upper", "drive_mode")
# the order robospec writes a config's arguments in, so generated configs read like ManiSkill's
# own agents: the joints, the bounds, the gains, the rest
FIELD_ORDER = (
    "joint_names",
    "lower",
    "upper",
    "pos_lower",
    "pos_upper",
    "rot_lower",
    "rot_upper",
    "vel_lower",
    "vel_upper",
    *GAINS,
    "ee_link",
    "urdf_path",
    "frame",
    "root_link_name",
    "use_delta",
    "use_target",
    "interpolate",
    "normalize_action",
    "delta_solver_config",
    "drive_mode",
    "mimic",
)


@dataclass(frozen=True)
class ActionPart:
    """A run of action dimensions and the two config fields that bound them, as the
    controller's ``_initialize_action_space`` lays them out."""

    lower: str
    upper: str
    # what the dimensions are: one per joint, one per control joint of a mimic map (the joints
    # others follow), or the named axes below
    over: Literal["joints", "control_joints", "axes"]
    # the dimensions' names for ``axes``; for joints, what they stand for when there are exactly
    # as many joints (a mobile base's x, y and yaw velocities)
    axes: tuple[str, ...] = ()
    # appended to a joint's name to name its dimension (``panda_joint1.vel``)
    suffix: str = ""
    # a null bound is the joint's own limit (ManiSkill's qlimits)
    null_is_joint_limit: bool = False


@dataclass(frozen=True, eq=False)  # one record per kind: compared by identity
class ControllerKind:
    """One controller ``type`` of the spec and the ManiSkill config it becomes."""

    name: str  # the spec's ``type``
    config_class: str  # ManiSkill's config dataclass, in CONFIG_MODULE
    # the config's fields but joint_names (in 3.0.1's order; the nightly's differs)
    fields: tuple[str, ...]
    # ManiSkill's defaults of the fields robospec reads when a spec leaves them out
    defaults: Mapping[str, object]
    # the drive targets its controller sets (ManiSkill's ``sets_target_qpos``/``_qvel``)
    sets_target_qpos: bool
    sets_target_qvel: bool
    action: tuple[ActionPart, ...]  # empty: the controller takes no action
    # how an imported controller's name ends when nothing better names it; ``{how}`` stands
    # for ``target_`` and ``delta_`` as the config sets use_target and use_delta
    short_name: str
    # the fewest joints its controller accepts (ManiSkill asserts it when building one); only
    # the mobile bases have a minimum: their x, y and yaw joints
    min_joints: int = 0

    @property
    def end_effector(self) -> bool:
        """Whether its action moves a link (``ee_link``) through inverse kinematics."""
        return "ee_link" in self.fields

    @property
    def mimic(self) -> bool:
        """Whether some of its joints follow others (a ``mimic`` map): only the control joints
        take actions."""
        return "mimic" in self.fields

    @property
    def joint_position_targets(self) -> bool:
        """Whether each action dimension is a position target of one of its joints (or a
        change of one, with use_delta): stiffness and damping in joint space, bounds that
        default to the joints' limits."""
        return self.sets_target_qpos and not self.end_effector

    @property
    def gains(self) -> tuple[str, ...]:
        """The drive properties it sets, in GAINS order."""
        return tuple(gain for gain in GAINS if gain in self.fields)

    @property
    def per_joint(self) -> tuple[str, ...]:
        """Its fields that take one value per joint, in PER_JOINT_FIELDS order."""
        return tuple(
            f for f in PER_JOINT_FIELDS if f in self.fields and not self.axes_bounded_by(f)
        )

    @property
    def axis_names(self) -> tuple[str, ...]:
        """What its action dimensions stand for where they are not joints (an end effector's
        x, y, z, ...) or where its joints stand for axes (a base's vx, vy, wz); empty
        otherwise."""
        return tuple(axis for part in self.action for axis in part.axes)

    def axes_bounded_by(self, field_name: str) -> tuple[str, ...]:
        """The action axes ``field_name`` bounds, one value each, when it is a field that
        elsewhere takes one value per joint (a forward-velocity base's lower and upper bound
        its forward speed and turn rate); empty otherwise."""
        if field_name not in PER_JOINT_FIELDS:
            return ()
        for part in self.action:
            if part.over == "axes" and field_name in (part.lower, part.upper):
                return part.axes
        return ()


def _defaults(**values: object) -> Mapping[str, object]:
    return MappingProxyType(values)


_JOINT_POSITION_FIELDS = (
    "lower",
    "upper",
    "stiffness",
    "damping",
    "force_limit",
    "friction",
    "use_delta",
    "use_target",
    "interpolate",
    "normalize_action",
    "drive_mode",
)
_JOINT_VELOCITY_FIELDS = (
    "lower",
    "upper",
    "damping",
    "force_limit",
    "friction",
    "normalize_action",
    "drive_mode",
)
_END_EFFECTOR_FIELDS = (
    "pos_lower",
    "pos_upper",
    "stiffness",
    "damping",
    "force_limit",
    "friction",
    "ee_link",
    "urdf_path",
    "frame",
    "root_link_name",
    "use_delta",
    "use_target",
    "interpolate",
    "normalize_action",
    "delta_solver_config",
    "drive_mode",
)
_NORMALIZED = _defaults(normalize_action=True)
_JOINT_POSITIONS = ActionPart("lower", "upper", "joints", null_is_joint_limit=True)
_JOINT_VELOCITIES = ActionPart("lower", "upper", "joints")
_POSITION = ActionPart("pos_lower", "pos_upper", "axes", ("x", "y", "z"))

CONTROLLER_KINDS: tuple[ControllerKind, ...] = (
    ControllerKind(
        name="pd_joint_pos",
        config_class="PDJointPosControllerConfig",
        fields=_JOINT_POSITION_FIELDS,
        defaults=_NORMALIZED,
        sets_target_qpos=True,
        sets_target_qvel=False,
        action=(_JOINT_POSITIONS,),
        short_name="{how}pos",
    ),
    ControllerKind(
        name="pd_joint_pos_mimic",
        config_class="PDJointPosMimicControllerConfig",
        fields=(*_JOINT_POSITION_FIELDS, "mimic"),
        defaults=_NORMALIZED,
        sets_target_qpos=True,
        sets_target_qvel=False,
        action=(ActionPart("lower", "upper", "control_joints", null_is_joint_limit=True),),
        short_name="{how}pos",
    ),
    ControllerKind(
        name="pd_joint_vel",
        config_class="PDJointVelControllerConfig",
        fields=_JOINT_VELOCITY_FIELDS,
        defaults=_NORMALIZED,
        sets_target_qpos=False,
        sets_target_qvel=True,
        action=(_JOINT_VELOCITIES,),
        short_name="vel",
    ),
    ControllerKind(
        name="pd_joint_pos_vel",
        config_class="PDJointPosVelControllerConfig",
        fields=(*_JOINT_POSITION_FIELDS, "vel_lower", "vel_upper"),
        defaults=_defaults(normalize_action=True, vel_lower=-1.0, vel_upper=1.0),
        sets_target_qpos=True,
        sets_target_qvel=True,
        action=(_JOINT_POSITIONS, ActionPart("vel_lower", "vel_upper", "joints", suffix=".vel")),
        short_name="{how}pos_vel",
    ),
    ControllerKind(
        name="pd_ee_pos",
        config_class="PDEEPosControllerConfig",
        fields=_END_EFFECTOR_FIELDS,
        defaults=_NORMALIZED,
        sets_target_qpos=True,
        sets_target_qvel=False,
        action=(_POSITION,),
        short_name="ee_{how}pos",
    ),
    ControllerKind(
        name="pd_ee_pose",
        config_class="PDEEPoseControllerConfig",
        fields=(*_END_EFFECTOR_FIELDS, "rot_lower", "rot_upper"),
        defaults=_defaults(normalize_action=True, rot_lower=-2 * math.pi, rot_upper=2 * math.pi),
        sets_target_qpos=True,
        sets_target_qvel=False,
        action=(_POSITION, ActionPart("rot_lower", "rot_upper", "axes", ("rx", "ry", "rz"))),
        short_name="ee_{how}pose",
    ),
    ControllerKind(
        name="pd_base_vel",
        config_class="PDBaseVelControllerConfig",
        fields=_JOINT_VELOCITY_FIELDS,
        defaults=_NORMALIZED,
        sets_target_qpos=False,
        sets_target_qvel=True,
        action=(ActionPart("lower", "upper", "joints", ("vx", "vy", "wz")),),
        short_name="vel",
        min_joints=3,  # x, y and yaw
    ),
    ControllerKind(
        name="pd_base_forward_vel",
        config_class="PDBaseForwardVelControllerConfig",
        fields=_JOINT_VELOCITY_FIELDS,
        defaults=_NORMALIZED,
        sets_target_qpos=False,
        sets_target_qvel=True,
        # a 2-D action (forward speed, turn rate) for the base's x, y and yaw joints
        action=(ActionPart("lower", "upper", "axes", ("v", "wz")),),
        short_name="vel",
        min_joints=3,
    ),
    ControllerKind(
        name="passive",
        config_class="PassiveControllerConfig",
        fields=("damping", "force_limit", "friction"),
        defaults=_defaults(),  # no normalize_action: there is no action
        sets_target_qpos=False,
        sets_target_qvel=False,
        action=(),
        short_name="passive",
    ),
)
"""Every kind, in the order the docs and hints list them (the spec model's union's order)."""

CONTROLLER_TYPES: tuple[str, ...] = tuple(kind.name for kind in CONTROLLER_KINDS)
"""Every controller ``type``, in CONTROLLER_KINDS' order."""

_BY_NAME = {kind.name: kind for kind in CONTROLLER_KINDS}
_BY_CONFIG_CLASS = {kind.config_class: kind for kind in CONTROLLER_KINDS}


def controller_kind(type_name: str) -> ControllerKind:
    """The kind a spec's ``type`` names (one the spec model accepted)."""
    return _BY_NAME[type_name]


def kind_of_config(config_class: str) -> ControllerKind | None:
    """The kind whose ManiSkill config class is named ``config_class``, or None."""
    return _BY_CONFIG_CLASS.get(config_class)
