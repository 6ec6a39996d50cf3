"""The few rotations composing needs beyond :mod:`robospec.description.mjcf_frames` (whose
quaternion algebra it uses): a spec's rotation as URDF's roll-pitch-yaw, URDF's rpy as a
quaternion, and numbers written back as text. Plain floats (this runs on the validate path)."""

from __future__ import annotations

import math

from robospec.description.mjcf_frames import Pose, Quaternion, Vector, compose, normalized

__all__ = ["Pose", "Quaternion", "Vector", "chain", "from_rpy", "number", "quaternion_to_rpy"]


def chain(outer: Pose, inner: Pose) -> Pose:
    """The pose ``inner`` (given in the frame ``outer`` places) in ``outer``'s parent frame."""
    return compose(outer, inner)


def quaternion_to_rpy(q: Quaternion) -> Vector:
    """Roll, pitch, yaw of R = Rz(yaw) Ry(pitch) Rx(roll) (URDF's convention) for the unit
    quaternion ``q`` (normalized here)."""
    w, x, y, z = normalized(q)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def from_rpy(roll: float, pitch: float, yaw: float) -> Quaternion:
    """The quaternion of URDF's roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    from robospec.resolve.poses import rpy_to_quaternion

    return rpy_to_quaternion(roll, pitch, yaw)


def number(value: float) -> str:
    """``value`` as the shortest text that reads back as the same float (``1`` for 1.0)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text
