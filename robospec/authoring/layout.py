"""The action layout of every control mode, computed from the compiled robot alone (no
ManiSkill import): which action index drives which joint or dimension, its bounds, and whether
the action is normalized to [-1, 1] (then ``low``/``high`` are what -1 and 1 mean).

It restates how ManiSkill's controllers build their action spaces (``_initialize_action_space``
and ``normalize_action`` of each config class); a maniskill-marked test proves it equal to what
:mod:`robospec.physics.action_layout` reads from live controllers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from robospec.description import RobotDescription
from robospec.resolve.resolved import ResolvedController, ResolvedMode, ResolvedRobot

# ManiSkill's default of normalize_action per config type (passive has no action)
NORMALIZE_DEFAULT = {
    "pd_joint_pos": True,
    "pd_joint_pos_mimic": True,
    "pd_joint_vel": True,
    "pd_joint_pos_vel": True,
    "pd_ee_pos": True,
    "pd_ee_pose": True,
    "pd_base_vel": True,
    "pd_base_forward_vel": True,
    "passive": False,
}
# what the dimensions of controllers that do not drive one joint per dimension stand for
NAMED_DIMENSIONS = {
    "pd_ee_pos": ("x", "y", "z"),
    "pd_ee_pose": ("x", "y", "z", "rx", "ry", "rz"),
    "pd_base_vel": ("vx", "vy", "wz"),
    "pd_base_forward_vel": ("v", "wz"),
}
ROT_DEFAULT = 2 * math.pi  # PDEEPoseControllerConfig's rot_lower/rot_upper: -2π, 2π
VEL_DEFAULT = 1.0  # PDJointPosVelControllerConfig's vel_lower/vel_upper: -1, 1


@dataclass(frozen=True)
class ActionRow:
    index: int
    group: str  # the mode's group (the mode's name for a one-controller mode)
    controller: str  # the spec's controller name
    type: str
    target: str  # a joint, ``joint.vel``, or ``group.axis``
    low: float
    high: float
    normalized: bool


def mode_layout(
    robot: ResolvedRobot, description: RobotDescription, mode: ResolvedMode
) -> list[ActionRow]:
    controllers = {c.name: c for c in robot.controllers}
    parts = list(mode.groups) if mode.groups is not None else [(mode.name, mode.controller or "")]
    rows: list[ActionRow] = []
    for group, name in parts:
        controller = controllers[name]
        for target, low, high in _dimensions(controller, description, group):
            rows.append(
                ActionRow(
                    len(rows),
                    group,
                    name,
                    controller.type,
                    target,
                    low,
                    high,
                    _normalized(controller),
                )
            )
    return rows


def _normalized(controller: ResolvedController) -> bool:
    kwargs = dict(controller.kwargs)
    return bool(kwargs.get("normalize_action", NORMALIZE_DEFAULT.get(controller.type, False)))


def _broadcast(value: Any, n: int) -> list[float]:
    if isinstance(value, Sequence) and not isinstance(value, str):
        values = [float(v) for v in value]
        return values if len(values) == n else values[:1] * n
    return [float(value)] * n


def _joint_limits(
    joints: Sequence[str], description: RobotDescription, kwargs: dict[str, Any]
) -> tuple[list[float], list[float]]:
    """The articulation's qlimits, overridden by the config's lower/upper when given."""
    lows, highs = [], []
    for name in joints:
        joint = description.joint(name)
        lower = joint.lower if joint is not None else None
        upper = joint.upper if joint is not None else None
        lows.append(-math.inf if lower is None else lower)
        highs.append(math.inf if upper is None else upper)
    if kwargs.get("lower") is not None:
        lows = _broadcast(kwargs["lower"], len(joints))
    if kwargs.get("upper") is not None:
        highs = _broadcast(kwargs["upper"], len(joints))
    return lows, highs


def _control_joints(joints: list[str], kwargs: dict[str, Any]) -> list[str]:
    """A mimic controller acts on the joints others mimic, in its own joint order."""
    mimic = kwargs.get("mimic") or {}
    if not mimic:
        return joints[:1]
    leaders = {entry["joint"] if isinstance(entry, dict) else entry for entry in mimic.values()}
    return [j for j in joints if j in leaders]


def _dimensions(
    controller: ResolvedController, description: RobotDescription, group: str
) -> list[tuple[str, float, float]]:
    kwargs = dict(controller.kwargs)
    joints = list(kwargs.get("joint_names", ()))
    kind = controller.type
    if kind == "passive":
        return []
    if kind in ("pd_joint_pos", "pd_joint_pos_vel"):
        lows, highs = _joint_limits(joints, description, kwargs)
        rows = list(zip(joints, lows, highs, strict=True))
        if kind == "pd_joint_pos_vel":
            vel_low = _broadcast(kwargs.get("vel_lower", -VEL_DEFAULT), len(joints))
            vel_high = _broadcast(kwargs.get("vel_upper", VEL_DEFAULT), len(joints))
            names = [f"{j}.vel" for j in joints]
            rows += list(zip(names, vel_low, vel_high, strict=True))
        return rows
    if kind == "pd_joint_pos_mimic":
        lows, highs = _joint_limits(joints, description, kwargs)
        limits = dict(zip(joints, zip(lows, highs, strict=True), strict=True))
        return [(j, *limits[j]) for j in _control_joints(joints, kwargs)]
    if kind in ("pd_ee_pos", "pd_ee_pose"):
        lows = _broadcast(kwargs["pos_lower"], 3)
        highs = _broadcast(kwargs["pos_upper"], 3)
        if kind == "pd_ee_pose":
            lows += _broadcast(kwargs.get("rot_lower", -ROT_DEFAULT), 3)
            highs += _broadcast(kwargs.get("rot_upper", ROT_DEFAULT), 3)
        axes = [f"{group}.{axis}" for axis in NAMED_DIMENSIONS[kind]]
        return list(zip(axes, lows, highs, strict=True))
    # joint velocities: pd_joint_vel, and the base controllers built on it
    width = 2 if kind == "pd_base_forward_vel" else len(joints)
    lows = _broadcast(kwargs["lower"], width)
    highs = _broadcast(kwargs["upper"], width)
    named = NAMED_DIMENSIONS.get(kind)
    if named is not None and len(named) == width:
        targets = [f"{group}.{axis}" for axis in named]
    elif len(joints) == width:
        targets = joints
    else:
        targets = [f"{group}[{i}]" for i in range(width)]
    return list(zip(targets, lows, highs, strict=True))
