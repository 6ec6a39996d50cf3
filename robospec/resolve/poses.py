"""Poses as ManiSkill takes them: a position and a wxyz quaternion."""

from __future__ import annotations

import math

from robospec.model.frozen import Pose

Position = tuple[float, float, float]
Quaternion = tuple[float, float, float, float]


def position_and_quaternion(pose: Pose) -> tuple[Position, Quaternion]:
    """A spec's pose (``q``, ``rpy`` or no rotation) as ``(p, q)``."""
    p = (pose.p[0], pose.p[1], pose.p[2])
    if pose.q is not None:
        q = (pose.q[0], pose.q[1], pose.q[2], pose.q[3])
    elif pose.rpy is not None:
        q = rpy_to_quaternion(*pose.rpy)
    else:
        q = (1.0, 0.0, 0.0, 0.0)
    return p, q


def rpy_to_quaternion(roll: float, pitch: float, yaw: float) -> Quaternion:
    """wxyz quaternion of R = Rz(yaw) Ry(pitch) Rx(roll), URDF's and SAPIEN's convention."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )
