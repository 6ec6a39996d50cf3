"""Rigid-body geometry in one place: vectors, wxyz quaternions, poses (a position and a
quaternion), 3×3 rotation matrices and URDF's roll-pitch-yaw, as ManiSkill and SAPIEN write them.

Plain Python floats (no numpy: the light core has none, and this runs on ``validate``'s path);
tests/test_geometry.py proves each conversion against scipy.spatial.transform.Rotation.
Quaternions are (w, x, y, z) and rotate by ``q v q*``; a pose ``(p, q)`` maps ``x`` to
``rotate(q, x) + p``; a matrix is a tuple of rows and maps ``x`` to ``apply(m, x)``. URDF's
``rpy`` (roll, pitch, yaw) is R = Rz(yaw) Ry(pitch) Rx(roll): turns about the fixed x, y and z
axes in that order (scipy's extrinsic ``'xyz'``).

Code that writes these numbers (optimize's condensed URDF, derive's and compose's XML) compares
them bit for bit, so each function keeps the arithmetic order it was written with.
"""

from __future__ import annotations

import math
import sys

Vector = tuple[float, float, float]
Quaternion = tuple[float, float, float, float]
Pose = tuple[Vector, Quaternion]
Matrix = tuple[Vector, Vector, Vector]  # rows

ZERO: Vector = (0.0, 0.0, 0.0)
IDENTITY: Quaternion = (1.0, 0.0, 0.0, 0.0)
IDENTITY_POSE: Pose = (ZERO, IDENTITY)
IDENTITY_MATRIX: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
# below this length a vector, an axis or a quaternion gives no direction
_TINY = 1e-12
# below this cos(pitch), roll and yaw read off a quaternion's last row and first column may be
# rounding (errors of 1e-16 / cos(pitch) radians); two matrices this close are one rotation
_NEAR_LOCK = 1e-6
_SAME = 1e-12
# a cos(pitch) this small is rounding: the matrix is in gimbal lock (trimesh's bound, 4 ulp of 1)
_LOCKED = 4 * sys.float_info.epsilon


class Degenerate(ValueError):
    """A zero vector or quaternion where a direction or a rotation is needed."""


# -- vectors


def dot(a: Vector, b: Vector) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Vector, b: Vector) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(v: Vector) -> Vector:
    """``v`` scaled to length 1."""
    norm = math.sqrt(sum(c * c for c in v))
    if norm < _TINY:
        raise Degenerate("zero vector")
    return (v[0] / norm, v[1] / norm, v[2] / norm)


# -- quaternions


def multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    """The rotation ``b`` then ``a`` (the Hamilton product ``a b``)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def conjugate(q: Quaternion) -> Quaternion:
    """The inverse rotation of a unit quaternion."""
    return (q[0], -q[1], -q[2], -q[3])


def normalized(q: Quaternion) -> Quaternion:
    norm = math.sqrt(sum(c * c for c in q))
    if norm < _TINY:
        raise Degenerate("zero quaternion")
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


def rotate(q: Quaternion, v: Vector) -> Vector:
    _, x, y, z = multiply(multiply(q, (0.0, *v)), conjugate(q))
    return (x, y, z)


def about_axis(axis: Vector, angle: float) -> Quaternion:
    """The turn by ``angle`` (radians, right-handed) about ``axis`` (any length but zero)."""
    norm = math.sqrt(sum(c * c for c in axis))
    if norm < _TINY:
        raise Degenerate("zero axis")
    s = math.sin(angle / 2) / norm
    return (math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s)


def z_towards(z: Vector) -> Quaternion:
    """The smallest rotation taking (0, 0, 1) onto the unit vector ``z`` (MuJoCo's ``zaxis`` and
    ``fromto``); half a turn about x when ``z`` points down."""
    axis = cross((0.0, 0.0, 1.0), z)
    if math.sqrt(dot(axis, axis)) < _TINY:
        return IDENTITY if z[2] > 0 else (0.0, 1.0, 0.0, 0.0)
    return about_axis(axis, math.acos(max(-1.0, min(1.0, z[2]))))


def quaternion_from_rpy(roll: float, pitch: float, yaw: float) -> Quaternion:
    """The unit quaternion of URDF's roll, pitch, yaw."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )


def rpy_from_quaternion(q: Quaternion) -> Vector:
    """URDF's roll, pitch, yaw of the rotation ``q`` (normalized here); pitch in [-π/2, π/2].
    Near gimbal lock roll and yaw read off the quaternion are rounding, right only by luck (a
    quarter turn about y reads as (π, π/2, π)): where they are not that rotation, from its
    matrix (:func:`rpy_from_matrix`)."""
    w, x, y, z = normalized(q)
    yaw_sine, yaw_cosine = 2 * (w * z + x * y), 1 - 2 * (y * y + z * z)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(yaw_sine, yaw_cosine)
    if math.hypot(yaw_sine, yaw_cosine) >= _NEAR_LOCK:
        return roll, pitch, yaw
    matrix = matrix_from_quaternion((w, x, y, z))
    read = matrix_from_rpy(roll, pitch, yaw)
    if max(abs(read[i][j] - matrix[i][j]) for i in range(3) for j in range(3)) <= _SAME:
        return roll, pitch, yaw
    return rpy_from_matrix(matrix)


def quaternion_from_matrix(m: Matrix) -> Quaternion:
    """The unit quaternion of the rotation matrix ``m`` (orthonormal), by Shepperd's method:
    from the largest of the trace and the diagonal, so no division by a small number."""
    m00, m11, m22 = m[0][0], m[1][1], m[2][2]
    trace = m00 + m11 + m22
    if trace > 0:
        s = 2 * math.sqrt(trace + 1)
        q = (s / 4, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s)
    elif m00 > m11 and m00 > m22:
        s = 2 * math.sqrt(1 + m00 - m11 - m22)
        q = ((m[2][1] - m[1][2]) / s, s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s)
    elif m11 > m22:
        s = 2 * math.sqrt(1 + m11 - m00 - m22)
        q = ((m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s)
    else:
        s = 2 * math.sqrt(1 + m22 - m00 - m11)
        q = ((m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4)
    return normalized(q)


def matrix_from_quaternion(q: Quaternion) -> Matrix:
    """The rotation matrix of ``q`` (normalized here)."""
    w, x, y, z = normalized(q)
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )


# -- poses


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


# -- matrices


def matmul(a: Matrix, b: Matrix) -> Matrix:
    rows = tuple(
        tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in (0, 1, 2)
    )
    return rows  # type: ignore[return-value]


def transpose(m: Matrix) -> Matrix:
    """The inverse of a rotation matrix."""
    return tuple(tuple(m[i][j] for i in range(3)) for j in range(3))  # type: ignore[return-value]


def apply(m: Matrix, v: Vector) -> Vector:
    """``m @ v``."""
    return (
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    )


def turned(r: Matrix, tensor: Matrix) -> Matrix:
    """``r @ tensor @ r.T``: a tensor (an inertia) written in the axes ``r`` maps it into."""
    return matmul(matmul(r, tensor), transpose(r))


def shifted(inertia: Matrix, mass: float, offset: Vector) -> Matrix:
    """The parallel-axis theorem: a body's ``inertia`` about its centre of mass, taken about a
    point ``offset`` from that centre (either way round): ``I + m (|d|² E - d dᵀ)``."""
    square = offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]
    return tuple(  # type: ignore[return-value]
        tuple(
            inertia[i][j] + mass * ((square if i == j else 0.0) - offset[i] * offset[j])
            for j in range(3)
        )
        for i in range(3)
    )


def matrix_from_rpy(roll: float, pitch: float, yaw: float) -> Matrix:
    """The rotation matrix of URDF's roll, pitch, yaw."""
    sr, cr = math.sin(roll), math.cos(roll)
    sp, cp = math.sin(pitch), math.cos(pitch)
    sy, cy = math.sin(yaw), math.cos(yaw)
    return (
        (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        (-sp, cp * sr, cp * cr),
    )


def rpy_from_matrix(r: Matrix) -> Vector:
    """URDF's roll, pitch, yaw of a rotation matrix; pitch in [-π/2, π/2]. Yaw first, then pitch
    and roll from Rz(yaw)ᵀ R: unlike reading roll off the last row, this stays exact near pitch
    ±π/2. At it (gimbal lock, where only roll - yaw or roll + yaw is defined) yaw is 0, as in
    trimesh's ``euler_from_matrix``, rather than the angle of two rounding errors."""
    across = math.sqrt(r[0][0] * r[0][0] + r[1][0] * r[1][0])  # |cos(pitch)|
    if across <= _LOCKED:
        # + 0.0: a roll of -0.0 is 0
        return math.atan2(-r[1][2], r[1][1]) + 0.0, math.atan2(-r[2][0], across), 0.0
    yaw = math.atan2(r[1][0], r[0][0])
    sy, cy = math.sin(yaw), math.cos(yaw)
    pitch = math.atan2(-r[2][0], cy * r[0][0] + sy * r[1][0])
    roll = math.atan2(sy * r[0][2] - cy * r[1][2], cy * r[1][1] - sy * r[0][1])
    return roll, pitch, yaw
