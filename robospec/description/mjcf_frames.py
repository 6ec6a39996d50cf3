"""MJCF frame orientations two ways: as MuJoCo reads them, and as ManiSkill 3.0.1's MJCF loader
(``_parse_orientation`` in mani_skill/utils/building/_mjcf_loader.py) reads them.

The two disagree, measured against MuJoCo 4.0 (``MjModel.body_quat``):

* ``euler``: ManiSkill ignores ``<compiler eulerseq>`` and computes
  ``transforms3d.euler.euler2quat(a, -b, c)`` (static x, y, z with the middle angle negated);
  MuJoCo's default sequence ``xyz`` turns about the moving axes. Equal when the middle angle is
  0 and at most one of the others is not.
* ``xyaxes``: ManiSkill takes the given y axis for the frame's z axis: never the same frame.
* ``zaxis``: ManiSkill builds x as world z × zaxis, so the frame's z is right but it is turned
  about it, unlike MuJoCo's smallest rotation; and a zaxis along ±z divides by zero
  (``LinAlgError: Eigenvalues did not converge``, the dm_control walker's floor).
* ``quat`` and ``axisangle`` agree.

Plain Python (no numpy): this runs on ``validate``'s fast path. Quaternions are (w, x, y, z).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Union

from robospec.geometry import (
    IDENTITY,
    Degenerate,
    Pose,
    Quaternion,
    Vector,
    about_axis,
    cross,
    dot,
    multiply,
    normalized,
    quaternion_from_matrix,
    rotate,
    transpose,
    unit,
    z_towards,
)

if TYPE_CHECKING:
    from lxml import etree

Attributes = Union[Mapping[str, str], "etree._Attrib"]
"""An element's attributes: lxml's (``element.attrib``, not a Mapping to a type checker) or a
plain mapping of them."""

ORIENTATION_ATTRIBUTES = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_AXES: dict[str, Vector] = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


# An orientation attribute that is not the numbers it should be, or numbers that are no
# rotation (a zero quaternion or axis): one error for both, as callers treat them alike.
Unparsable = Degenerate


def numbers(text: str, count: int) -> tuple[float, ...]:
    try:
        values = tuple(float(part) for part in text.split())
    except ValueError:
        raise Unparsable(text) from None
    if len(values) < count or not all(math.isfinite(v) for v in values[:count]):
        raise Unparsable(text)
    return values[:count]


def orientation_attribute(attributes: Attributes) -> str | None:
    """The orientation attribute MuJoCo uses (it allows only one); None: no rotation."""
    return next((name for name in ORIENTATION_ATTRIBUTES if name in attributes), None)


def mujoco_rotation(attributes: Attributes, degrees: bool, eulerseq: str) -> Quaternion:
    """The frame's rotation as MuJoCo computes it (identity when none is given)."""
    name = orientation_attribute(attributes)
    if name is None:
        return IDENTITY
    text = attributes[name]
    if name == "quat":
        return normalized(numbers(text, 4))  # type: ignore[arg-type]
    if name == "axisangle":
        *axis, angle = numbers(text, 4)
        return about_axis(tuple(axis), math.radians(angle) if degrees else angle)  # type: ignore[arg-type]
    if name == "euler":
        angles = numbers(text, 3)
        if len(eulerseq) != 3 or any(letter.lower() not in _AXES for letter in eulerseq):
            raise Unparsable(eulerseq)  # MuJoCo refuses it too
        q = IDENTITY
        for letter, angle in zip(eulerseq, angles, strict=False):
            turn = about_axis(_AXES[letter.lower()], math.radians(angle) if degrees else angle)
            # lower case: about the moving frame's axis; upper case: about the fixed one
            q = multiply(q, turn) if letter.islower() else multiply(turn, q)
        return normalized(q)
    if name == "xyaxes":
        values = numbers(text, 6)
        x = unit(values[:3])  # type: ignore[arg-type]
        y_given: Vector = values[3:]  # type: ignore[assignment]
        along = dot(x, y_given)
        y = unit((y_given[0] - along * x[0], y_given[1] - along * x[1], y_given[2] - along * x[2]))
        return quaternion_from_matrix(transpose((x, y, cross(x, y))))
    z = unit(numbers(text, 3))  # type: ignore[arg-type]
    return z_towards(z)


def maniskill_rotation(attributes: Attributes, degrees: bool) -> Quaternion | None:
    """The frame's rotation as ManiSkill's loader computes it; None where it fails
    (``zaxis`` along ±z)."""
    name = orientation_attribute(attributes)
    if name is None:
        return IDENTITY
    text = attributes[name]
    if name in ("quat", "axisangle"):
        return mujoco_rotation(attributes, degrees, "xyz")
    if name == "euler":
        a, b, c = (math.radians(v) if degrees else v for v in numbers(text, 3))
        # transforms3d's euler2quat(a, -b, c) with its default static 'sxyz' axes
        turns = (about_axis(_AXES["z"], c), about_axis(_AXES["y"], -b), about_axis(_AXES["x"], a))
        return normalized(multiply(multiply(turns[0], turns[1]), turns[2]))
    if name == "xyaxes":
        values = numbers(text, 6)
        x_norm = math.sqrt(dot(values[:3], values[:3]))  # type: ignore[arg-type]
        if x_norm < 1e-12:
            raise Unparsable(text)
        x: Vector = tuple(v / x_norm for v in values[:3])  # type: ignore[assignment]
        z: Vector = tuple(v / x_norm for v in values[3:])  # type: ignore[assignment]
        y = unit(cross(z, x))
        return quaternion_from_matrix(transpose((x, y, unit(z))))
    z = unit(numbers(text, 3))  # type: ignore[arg-type]
    x_raw = cross((0.0, 0.0, 1.0), z)
    if math.sqrt(dot(x_raw, x_raw)) < 1e-12:
        return None
    x = unit(x_raw)
    return quaternion_from_matrix(transpose((x, unit(cross(z, x)), z)))


def body_pose(attributes: Attributes, degrees: bool, eulerseq: str) -> Pose:
    """A body's pose in its parent's frame as MuJoCo reads it (``pos`` and orientation)."""
    position = numbers(attributes.get("pos", "0 0 0"), 3)
    rotation = mujoco_rotation(attributes, degrees, eulerseq)
    return ((position[0], position[1], position[2]), rotation)


def same_rotation(a: Quaternion, b: Quaternion, tolerance: float = 1e-4) -> bool:
    return abs(sum(p * q for p, q in zip(a, b, strict=True))) > 1 - tolerance


def same_axis(a: Quaternion, b: Quaternion, tolerance: float = 1e-4) -> bool:
    """Whether both rotations take the z axis to the same direction (all a capsule,
    cylinder or any shape round about its z axis depends on)."""
    za = rotate(a, (0.0, 0.0, 1.0))
    zb = rotate(b, (0.0, 0.0, 1.0))
    return dot(za, zb) > 1 - tolerance
