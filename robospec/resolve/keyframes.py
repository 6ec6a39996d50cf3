"""Keyframes: joint values written by joint or group name become arrays in qpos order.

Only a keyframe whose values cover every active joint exactly gets an array; what is wrong with
the others (a value short, a joint set twice, a value past a limit) is the checks' to say
(RS303, RS313, RS304), from the bindings recorded here.
"""

from __future__ import annotations

from typing import Any

from robospec.diagnostics.codes import NOT_DOWNLOADED
from robospec.load.source_map import KeyPath
from robospec.model.frozen import Keyframe
from robospec.resolve.carried import keyframe_values
from robospec.resolve.context import ResolveContext
from robospec.resolve.poses import position_and_quaternion
from robospec.resolve.resolved import ResolvedKeyframe
from robospec.resolve.root_pose import root_link_pose
from robospec.resolve.selection import select_joints

NEEDS_DOWNLOAD = (
    "this needs the robot description, which is not downloaded",
    "write the values as one full list in qpos order, or download the robot's assets",
)


def resolve_keyframe(context: ResolveContext, name: str, frame: Keyframe) -> ResolvedKeyframe:
    path: KeyPath = ("keyframes", name)
    # an MJCF robot's keyframe pose is its root body's, as in MuJoCo (see root_pose)
    given = position_and_quaternion(frame.pose) if "pose" in frame.model_fields_set else None
    p, q = root_link_pose(context.description, given)
    return ResolvedKeyframe(
        name=name,
        p=p,
        q=q,
        qpos=joint_values(context, frame.qpos, (*path, "qpos")),
        qvel=joint_values(context, frame.qvel, (*path, "qvel")),
    )


def joint_values(context: ResolveContext, values: Any, path: KeyPath) -> tuple[float, ...] | None:
    """One value per active joint, in qpos order; None when they do not cover each exactly."""
    if values is None:
        return None
    active = context.description.active_joint_names
    if context.assumed:
        # the joint order is the description's, which is not here: only a full list works
        if isinstance(values, list):
            return tuple(values)
        context.err(path, NOT_DOWNLOADED, *NEEDS_DOWNLOAD)
        return None
    if isinstance(values, list):
        return tuple(values) if len(values) == len(active) else None
    by_joint: dict[str, float] = {}
    for key, item in values.items():
        joints = select_joints(context, key, (*path, key))
        items = item if isinstance(item, list) else [item] * len(joints)
        if len(items) == len(joints):
            by_joint.update(zip(joints, items, strict=True))
    if context.composed is not None and path[0] == "keyframes":
        # merged by joint: the parts' joints the spec leaves out take the parts' values
        for joint, value in keyframe_values(context, str(path[1]), str(path[-1])).items():
            by_joint.setdefault(joint, value)
    if any(joint not in by_joint for joint in active):
        return None
    return tuple(by_joint[joint] for joint in active)
