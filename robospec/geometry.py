"""Rigid-body geometry in one place: vectors, wxyz quaternions, poses (a position and a
quaternion) and URDF's roll-pitch-yaw, as ManiSkill and SAPIEN write them.

Plain Python floats (no numpy: the light core has none, and this runs on ``validate``'s path).
Quaternions are (w, x, y, z) and rotate by ``q v q*``; a pose ``(p, q)`` maps ``x`` to
``rotate(q, x) + p``.
"""

from __future__ import annotations

import math

Vector = tuple[float, float, float]
Quaternion = tuple[float, float, float, float]
Pose = tuple[Vector, Quaternion]

IDENTITY: Quaternion = (1.0, 0.0, 0.0, 0.0)
IDENTITY_POSE: Pose = ((0.0, 0.0, 0.0), IDENTITY)


class Degenerate(ValueError):
    """A zero vector or quaternion where a direction or a rotation is needed."""


def multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def conjugate(q: Quaternion) -> Quaternion:
    return (q[0], -q[1], -q[2], -q[3])


def normalized(q: Quaternion) -> Quaternion:
    norm = math.sqrt(sum(c * c for c in q))
    if norm < 1e-12:
        raise Degenerate("zero quaternion")
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


def rotate(q: Quaternion, v: Vector) -> Vector:
    _, x, y, z = multiply(multiply(q, (0.0, *v)), conjugate(q))
    return (x, y, z)


def compose(a: Pose, b: Pose) -> Pose:
    """``a * b``: the pose ``b`` (given in ``a``'s frame) in ``a``'s parent frame."""
    moved = rotate(a[1], b[0])
    return (
        (a[0][0] + moved[0], a[0][1] + moved[1], a[0][2] + moved[2]),
        multiply(a[1], b[1]),
    )


def inverse(pose: Pose) -> Pose:
    back = conjugate(pose[1])
    p = rotate(back, pose[0])
    return ((-p[0], -p[1], -p[2]), back)


def about_axis(axis: Vector, angle: float) -> Quaternion:
    norm = math.sqrt(sum(c * c for c in axis))
    if norm < 1e-12:
        raise Degenerate("zero axis")
    s = math.sin(angle / 2) / norm
    return (math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s)


def from_columns(x: Vector, y: Vector, z: Vector) -> Quaternion:
    """The quaternion of the rotation matrix with columns x, y, z (orthonormal)."""
    m00, m11, m22 = x[0], y[1], z[2]
    trace = m00 + m11 + m22
    if trace > 0:
        s = 2 * math.sqrt(trace + 1)
        q = (s / 4, (y[2] - z[1]) / s, (z[0] - x[2]) / s, (x[1] - y[0]) / s)
    elif m00 > m11 and m00 > m22:
        s = 2 * math.sqrt(1 + m00 - m11 - m22)
        q = ((y[2] - z[1]) / s, s / 4, (y[0] + x[1]) / s, (z[0] + x[2]) / s)
    elif m11 > m22:
        s = 2 * math.sqrt(1 + m11 - m00 - m22)
        q = ((z[0] - x[2]) / s, (y[0] + x[1]) / s, s / 4, (z[1] + y[2]) / s)
    else:
        s = 2 * math.sqrt(1 + m22 - m00 - m11)
        q = ((x[1] - y[0]) / s, (z[0] + x[2]) / s, (z[1] + y[2]) / s, s / 4)
    return normalized(q)


def from_rpy(roll: float, pitch: float, yaw: float) -> Quaternion:
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


def to_rpy(q: Quaternion) -> Vector:
    """Roll, pitch, yaw of R = Rz(yaw) Ry(pitch) Rx(roll) (URDF's convention) for the unit
    quaternion ``q`` (normalized here)."""
    w, x, y, z = normalized(q)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


Matrix = tuple[Vector, Vector, Vector]  # a 3x3 matrix's rows


def rotation_matrix(q: Quaternion) -> Matrix:
    """The rows of the rotation matrix of the unit quaternion ``q`` (``R v == rotate(q, v)``)."""
    w, x, y, z = q
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )
