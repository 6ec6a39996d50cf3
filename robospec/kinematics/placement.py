"""A robot placed at some joint values: every link's pose and every moving joint's axis, in the
root link's frame (what :mod:`.forward`'s backends compute), and the rigid motions they are made
of. numpy is imported by the functions that need it."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from robospec.geometry import Quaternion, about_axis, matrix_from_quaternion

if TYPE_CHECKING:
    import numpy as np

MOVING = ("revolute", "continuous", "prismatic")  # the joints that have an axis


@dataclass(frozen=True)
class Axis:
    """A moving joint's axis at a pose, in the root frame: its unit ``direction`` and a point
    it passes through (the pivot of a revolute joint)."""

    direction: np.ndarray
    anchor: np.ndarray


@dataclass(frozen=True)
class Placement:
    """The robot at one set of joint values: every link's pose and every moving joint's axis,
    in the root frame."""

    links: Mapping[str, np.ndarray]
    axes: Mapping[str, Axis]


# joint values by name (0 for a joint they leave out) -> the robot placed there
Poser = Callable[[Mapping[str, float]], Placement]


def pose_matrix(p: tuple[float, ...], q: Quaternion | tuple[float, ...]) -> np.ndarray:
    """A 4x4 transform from a position and a wxyz quaternion (normalized here)."""
    import numpy as np

    matrix = np.eye(4)
    norm = sum(c * c for c in q) ** 0.5 or 1.0
    matrix[:3, :3] = matrix_from_quaternion(tuple(c / norm for c in q))  # type: ignore[arg-type]
    matrix[:3, 3] = p
    return matrix


def motion(kind: str, axis: Axis, value: float) -> np.ndarray:
    """The rigid motion (4x4, root frame) by which a joint at ``value`` moves everything
    beyond it from where it hangs at 0: a turn about the axis through its anchor, or a slide
    along it."""
    import numpy as np

    moved = np.eye(4)
    if kind == "prismatic":
        moved[:3, 3] = axis.direction * value
    elif kind in ("revolute", "continuous") and value != 0.0:
        x, y, z = (float(c) for c in axis.direction)
        turn = np.array(matrix_from_quaternion(about_axis((x, y, z), value)))
        moved[:3, :3] = turn
        moved[:3, 3] = axis.anchor - turn @ axis.anchor
    return moved
