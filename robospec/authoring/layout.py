"""The action layout of every control mode, computed from the compiled robot alone (no
ManiSkill import): which action index drives which joint or dimension, its bounds, and whether
the action is normalized to [-1, 1] (then ``low``/``high`` are what -1 and 1 mean).

It follows each controller kind's action parts (:mod:`robospec.model.controller_kinds`), which
restate how ManiSkill's controllers build their action spaces (``_initialize_action_space`` and
``normalize_action`` of each config class); a maniskill-marked test proves it equal to what
:mod:`robospec.physics.action_layout` reads from live controllers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from robospec.description import RobotDescription
from robospec.model.controller_kinds import ActionPart
from robospec.resolve.resolved import ResolvedController, ResolvedMode, ResolvedRobot


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
    # a passive controller has no normalize_action (and no action)
    return bool(kwargs.get("normalize_action", controller.kind.defaults.get("normalize_action")))


def _broadcast(value: Any, n: int) -> list[float]:
    if isinstance(value, Sequence) and not isinstance(value, str):
        values = [float(v) for v in value]
        return values if len(values) == n else values[:1] * n
    return [float(value)] * n


def _joint_limits(
    joints: Sequence[str], description: RobotDescription, lower: Any, upper: Any
) -> tuple[list[float], list[float]]:
    """The articulation's qlimits, overridden by the config's ``lower``/``upper`` when given."""
    lows, highs = [], []
    for name in joints:
        joint = description.joint(name)
        low = joint.lower if joint is not None else None
        high = joint.upper if joint is not None else None
        lows.append(-math.inf if low is None else low)
        highs.append(math.inf if high is None else high)
    if lower is not None:
        lows = _broadcast(lower, len(joints))
    if upper is not None:
        highs = _broadcast(upper, len(joints))
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
    """(target, low, high) per action dimension, part by part of the kind's action."""
    kind = controller.kind
    kwargs = dict(controller.kwargs)
    joints = list(kwargs.get("joint_names", ()))
    rows: list[tuple[str, float, float]] = []
    for part in kind.action:
        lower = kwargs.get(part.lower, kind.defaults.get(part.lower))
        upper = kwargs.get(part.upper, kind.defaults.get(part.upper))
        if part.over == "axes":
            lows, highs = _broadcast(lower, len(part.axes)), _broadcast(upper, len(part.axes))
            rows += zip([f"{group}.{axis}" for axis in part.axes], lows, highs, strict=True)
            continue
        # bounds broadcast over every joint of the controller, then the part's joints picked
        if part.null_is_joint_limit:
            lows, highs = _joint_limits(joints, description, lower, upper)
        else:
            lows, highs = _broadcast(lower, len(joints)), _broadcast(upper, len(joints))
        picked = _control_joints(joints, kwargs) if part.over == "control_joints" else joints
        index = {joint: i for i, joint in enumerate(joints)}
        targets = _joint_targets(part, picked, group)
        rows += [
            (target, lows[index[joint]], highs[index[joint]])
            for target, joint in zip(targets, picked, strict=True)
        ]
    return rows


def _joint_targets(part: ActionPart, joints: list[str], group: str) -> list[str]:
    """What a part's dimensions over joints stand for: the joints (with the part's suffix), or
    the part's axes where there are as many joints (a base's vx, vy, wz)."""
    if part.axes and len(part.axes) == len(joints):
        return [f"{group}.{axis}" for axis in part.axes]
    return [joint + part.suffix for joint in joints]
