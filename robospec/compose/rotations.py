"""The few rotations composing needs: a spec's pose as URDF's roll-pitch-yaw and as MJCF's
quaternion, and poses chained. Plain floats, no numpy (this runs on the validate path)."""

from __future__ import annotations

import math

Vector = tuple[float, float, float]
Quaternion = tuple[float, float, float, float]  # w, x, y, z


def quaternion_to_rpy(q: Quaternion) -> Vector:
    """Roll, pitch, yaw of R = Rz(yaw) Ry(pitch) Rx(roll) (URDF's convention) for the unit
    quaternion ``q`` (normalized here)."""
    w, x, y, z = _normalized(q)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    sin_pitch = max(-1.0, min(1.0, 2 * (w * y - z * x)))
    pitch = math.asin(sin_pitch)
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    """The rotation ``a`` then, in its frame, ``b`` (Hamilton product ``a * b``)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def rotate(q: Quaternion, v: Vector) -> Vector:
    """``v`` rotated by the unit quaternion ``q``."""
    w, x, y, z = q
    vw, vx, vy, vz = multiply(multiply((w, x, y, z), (0.0, *v)), (w, -x, -y, -z))
    del vw
    return vx, vy, vz


def chain(
    outer: tuple[Vector, Quaternion], inner: tuple[Vector, Quaternion]
) -> tuple[Vector, Quaternion]:
    """The pose ``inner`` (given in the frame ``outer`` places) in ``outer``'s parent frame."""
    (p1, q1), (p2, q2) = outer, inner
    moved = rotate(q1, p2)
    return (p1[0] + moved[0], p1[1] + moved[1], p1[2] + moved[2]), multiply(q1, q2)


def _normalized(q: Quaternion) -> Quaternion:
    norm = math.sqrt(sum(c * c for c in q)) or 1.0
    w, x, y, z = (c / norm for c in q)
    return w, x, y, z


def number(value: float) -> str:
    """``value`` as the shortest text that reads back as the same float (``1`` for 1.0)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def from_rpy(roll: float, pitch: float, yaw: float) -> Quaternion:
    """The quaternion of URDF's roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    from robospec.resolve.poses import rpy_to_quaternion

    return rpy_to_quaternion(roll, pitch, yaw)
