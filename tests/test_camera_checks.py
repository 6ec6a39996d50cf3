"""The camera warnings judged from made-up segmentation pictures, no renderer: which label counts
as the robot, its mount, or something seen, and where a wrist camera's tcp lands.

tests/test_pictures.py draws real pictures and judges them end to end (slow); here each
threshold and label of :func:`robospec.pictures.camera_checks.judge` is reached with numbers
chosen on both sides of it.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from robospec.diagnostics.codes import (
    CAMERA_COVERED_BY_MOUNT,
    CAMERA_COVERED_BY_ROBOT,
    CAMERA_LOOKS_AWAY,
    CAMERA_SEES_NOTHING,
)
from robospec.pictures.camera_checks import Finding, Limits, judge
from robospec.pictures.renderer import CUBE, GROUND, NOTHING, TABLE
from robospec.pictures.views import View

LIMITS = Limits(
    max_mount_fraction=0.5, max_robot_fraction=0.5, min_seen_fraction=0.2, tcp_in_view=True
)
# the robot's shapes, by label: 0 and 1 on the camera's mount, 2 on the arm
ROBOT = SimpleNamespace(shapes=tuple(SimpleNamespace(link=k) for k in ("mount", "bracket", "arm")))
MOUNT = frozenset({"mount", "bracket"})


def _picture(**counts: int) -> np.ndarray:
    """A 10 x 10 picture with ``counts`` pixels of each label (the rest nothing)."""
    labels = {"shape0": 0, "shape1": 1, "shape2": 2, "ground": GROUND, "table": TABLE}
    labels["cube"] = CUBE
    pixels = [labels[name] for name, n in counts.items() for _ in range(n)]
    pixels += [NOTHING] * (100 - len(pixels))
    return np.array(pixels).reshape(10, 10)


def _view(width: int = 10, height: int = 10) -> View:
    """At the origin looking along x, 90° of view, near 0.01 m and far 2 m."""
    return View("wrist", width, height, np.eye(4), 5.0, 5.0, 5.0, 5.0, 0.01, 2.0)


def _judge(
    alone: np.ndarray,
    table: np.ndarray | None = None,
    tcp: tuple[str, np.ndarray] | None = None,
    limits: Limits = LIMITS,
    robot: object = ROBOT,
) -> list[Finding]:
    seen = table if table is not None else _picture(table=100)
    return judge(_view(), alone, seen, robot, MOUNT, tcp, limits, "alone.png", "table.png")  # type: ignore[arg-type]


def _codes(
    alone: np.ndarray,
    table: np.ndarray | None = None,
    tcp: tuple[str, np.ndarray] | None = None,
) -> list[str]:
    return [f.code for f in _judge(alone, table, tcp)]


def test_every_shape_label_counts_as_the_robot_and_no_scene_label_does() -> None:
    # 60 pixels of the first shape (label 0), on the arm: past max_robot_fraction 0.5
    arm_first = SimpleNamespace(shapes=(SimpleNamespace(link="arm"),))
    (found,) = _judge(_picture(shape0=60), robot=arm_first)
    assert found.code == CAMERA_COVERED_BY_ROBOT and "covers 60%" in found.message
    # 40 of the arm's pixels and 60 of ground, table and nothing: the robot covers 40%
    assert _codes(_picture(shape2=40, ground=20, table=20)) == []
    assert _codes(_picture(shape2=51)) == [CAMERA_COVERED_BY_ROBOT]
    assert _codes(_picture(shape2=50)) == []  # at the limit: not more than it


def test_the_mount_and_the_links_fixed_to_it_covering_the_picture_is_rs560_alone() -> None:
    # 30 + 30 pixels of the mount and its bracket: 60% > 0.5, said once (not RS561 too)
    assert _codes(_picture(shape0=30, shape1=30)) == [CAMERA_COVERED_BY_MOUNT]
    assert _codes(_picture(shape0=25, shape1=25)) == []
    # the mount's 30% and the arm's 30%: the robot covers 60%
    assert _codes(_picture(shape0=30, shape2=30)) == [CAMERA_COVERED_BY_ROBOT]


def test_a_picture_at_the_table_with_too_little_within_far_is_rs562() -> None:
    empty = _picture(shape2=10)
    assert _codes(empty, _picture(table=19)) == [CAMERA_SEES_NOTHING]
    assert _codes(empty, _picture(table=10, ground=5, cube=5)) == []  # 20%: the limit
    assert _codes(empty, _picture(shape2=20)) == []  # the robot is something seen


@pytest.mark.parametrize(
    ("point", "where"),
    [
        ((-1.0, 0.0, 0.0), "behind the camera"),
        ((3.0, 0.0, 0.0), "past far (3.00 m away)"),
        ((0.005, 0.0, 0.0), "nearer than near"),
        ((1.0, 2.0, 0.0), "outside the 10x10 picture"),
    ],
)
def test_a_wrist_camera_that_does_not_see_its_tcp_says_where_it_is(
    point: tuple[float, float, float], where: str
) -> None:
    alone = _picture(shape2=10)
    (found,) = _judge(alone, tcp=("tcp", np.array(point)))
    assert found.code == CAMERA_LOOKS_AWAY
    assert where in found.message and "'tcp'" in found.message
    # one metre ahead, in the middle of the picture: seen
    assert _codes(alone, tcp=("tcp", np.array([1.0, 0.0, 0.0]))) == []
    # a tcp out of view is no concern where checks.camera_views.tcp_in_view is false
    quiet = Limits(0.5, 0.5, 0.2, tcp_in_view=False)
    assert _judge(alone, tcp=("tcp", np.array(point)), limits=quiet) == []
