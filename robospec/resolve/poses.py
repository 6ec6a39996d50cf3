"""Poses as ManiSkill takes them: a position and a wxyz quaternion."""

from __future__ import annotations

from robospec.geometry import IDENTITY, Quaternion, Vector, quaternion_from_rpy
from robospec.model.frozen import Pose


def position_and_quaternion(pose: Pose) -> tuple[Vector, Quaternion]:
    """A spec's pose (``q``, ``rpy`` or no rotation) as ``(p, q)``."""
    p = (pose.p[0], pose.p[1], pose.p[2])
    if pose.q is not None:
        q = (pose.q[0], pose.q[1], pose.q[2], pose.q[3])
    elif pose.rpy is not None:
        q = quaternion_from_rpy(*pose.rpy)
    else:
        q = IDENTITY
    return p, q
