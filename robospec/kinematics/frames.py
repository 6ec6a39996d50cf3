"""Rigid transforms in plain Python, for the little forward kinematics ``robospec new`` does
(where a robot's legs are, which way its joints turn).

No numpy: the core install has none, and a few dozen 3x3 products per robot do not need it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

Vector = tuple[float, float, float]
Matrix = tuple[Vector, Vector, Vector]  # rows

IDENTITY_ROTATION: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
ZERO: Vector = (0.0, 0.0, 0.0)


def _matmul(a: Matrix, b: Matrix) -> Matrix:
    return tuple(  # type: ignore[return-value]
        tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3)
    )


def _apply(r: Matrix, v: Vector) -> Vector:
    return (
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    )


def _transpose(r: Matrix) -> Matrix:
    return tuple(tuple(r[j][i] for j in range(3)) for i in range(3))  # type: ignore[return-value]


def normalized(v: Vector) -> Vector:
    norm = math.sqrt(sum(c * c for c in v))
    if norm < 1e-12:
        return (1.0, 0.0, 0.0)
    return (v[0] / norm, v[1] / norm, v[2] / norm)


def cross(a: Vector, b: Vector) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@dataclass(frozen=True)
class Transform:
    """``x -> rotation @ x + translation``."""

    rotation: Matrix = IDENTITY_ROTATION
    translation: Vector = ZERO

    def __matmul__(self, other: Transform) -> Transform:
        moved = _apply(self.rotation, other.translation)
        return Transform(
            _matmul(self.rotation, other.rotation),
            (
                moved[0] + self.translation[0],
                moved[1] + self.translation[1],
                moved[2] + self.translation[2],
            ),
        )

    def point(self, v: Vector) -> Vector:
        moved = _apply(self.rotation, v)
        return (
            moved[0] + self.translation[0],
            moved[1] + self.translation[1],
            moved[2] + self.translation[2],
        )

    def direction(self, v: Vector) -> Vector:
        return _apply(self.rotation, v)

    def inverse(self) -> Transform:
        back = _transpose(self.rotation)
        t = _apply(back, self.translation)
        return Transform(back, (-t[0], -t[1], -t[2]))

    def quaternion(self) -> tuple[float, float, float, float]:
        """The rotation as a unit quaternion (w, x, y, z), w >= 0."""
        r = self.rotation
        trace = r[0][0] + r[1][1] + r[2][2]
        if trace > 0:
            s = math.sqrt(trace + 1.0) * 2
            q = (
                0.25 * s,
                (r[2][1] - r[1][2]) / s,
                (r[0][2] - r[2][0]) / s,
                (r[1][0] - r[0][1]) / s,
            )
        elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
            s = math.sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2
            q = (
                (r[2][1] - r[1][2]) / s,
                0.25 * s,
                (r[0][1] + r[1][0]) / s,
                (r[0][2] + r[2][0]) / s,
            )
        elif r[1][1] > r[2][2]:
            s = math.sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2
            q = (
                (r[0][2] - r[2][0]) / s,
                (r[0][1] + r[1][0]) / s,
                0.25 * s,
                (r[1][2] + r[2][1]) / s,
            )
        else:
            s = math.sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2
            q = (
                (r[1][0] - r[0][1]) / s,
                (r[0][2] + r[2][0]) / s,
                (r[1][2] + r[2][1]) / s,
                0.25 * s,
            )
        return q if q[0] >= 0 else (-q[0], -q[1], -q[2], -q[3])


def translation(v: Vector) -> Transform:
    return Transform(IDENTITY_ROTATION, v)


def from_quaternion(w: float, x: float, y: float, z: float) -> Matrix:
    norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )


def about_axis(axis: Vector, angle: float) -> Matrix:
    """Rotation by ``angle`` (radians) about the unit vector ``axis``."""
    x, y, z = normalized(axis)
    half = angle / 2
    s = math.sin(half)
    return from_quaternion(math.cos(half), x * s, y * s, z * s)


def from_rpy(roll: float, pitch: float, yaw: float) -> Matrix:
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return _matmul(
        about_axis((0, 0, 1), yaw),
        _matmul(about_axis((0, 1, 0), pitch), about_axis((1, 0, 0), roll)),
    )


def from_euler(angles: Vector, sequence: str) -> Matrix:
    """MJCF's ``euler`` with ``<compiler eulerseq>``: lower-case letters rotate about the moving
    axes (intrinsic), upper-case about the fixed ones (extrinsic)."""
    rotation = IDENTITY_ROTATION
    unit = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
    for letter, angle in zip(sequence, angles, strict=False):
        step = about_axis(unit[letter.lower()], angle)
        rotation = _matmul(rotation, step) if letter.islower() else _matmul(step, rotation)
    return rotation


def from_axes(x_axis: Vector, y_axis: Vector) -> Matrix:
    """The rotation whose first two columns are ``x_axis`` and ``y_axis`` (made orthonormal)."""
    x = normalized(x_axis)
    dot = sum(a * b for a, b in zip(x, y_axis, strict=True))
    y = normalized(tuple(b - dot * a for a, b in zip(x, y_axis, strict=True)))  # type: ignore[arg-type]
    z = cross(x, y)
    return _transpose((x, y, z))


def from_z_axis(z_axis: Vector) -> Matrix:
    """MuJoCo's ``zaxis``: the shortest rotation taking (0, 0, 1) to ``z_axis``."""
    z = normalized(z_axis)
    axis = cross((0.0, 0.0, 1.0), z)
    sine = math.sqrt(sum(c * c for c in axis))
    if sine < 1e-12:
        return IDENTITY_ROTATION if z[2] > 0 else about_axis((1.0, 0.0, 0.0), math.pi)
    return about_axis(axis, math.atan2(sine, z[2]))
