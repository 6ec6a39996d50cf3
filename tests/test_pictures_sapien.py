"""The CPU preview (``robospec doc --images``) shows what SAPIEN's cameras show: where the tcp,
the fingers and the hands land in each camera's picture, and which pixels are the robot's, agree
between SAPIEN's renderer (``robospec check --render``) and the preview.

SAPIEN renders only with a render device (a GPU): without one these tests are skipped, saying
so — on SAPIEN's own word, not on robospec's ``render_device_error``, which a test here holds to
SAPIEN's (a broken detector fails, it does not skip); and never where
``ROBOSPEC_EXPECT_RENDER_DEVICE`` is set (a GPU machine: no device there is a failure). The
conversion they compare through (OpenCV's camera matrices, as SAPIEN gives them, against the
preview's camera model) is checked here without one.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from conftest import MANISKILL_SPECS

from robospec.pictures.views import View

pytestmark = pytest.mark.maniskill

WRISTCAM_SPEC = MANISKILL_SPECS / "panda_wristcam.yaml"
G1_HEAD_SPEC = MANISKILL_SPECS / "unitree_g1_simplified_upper_body_with_head_camera.yaml"
PIXELS = 3.0  # how far apart the two may put a point


def test_opencv_matrices_project_as_the_preview_camera_does() -> None:
    from robospec.physics.render import project_cv

    pose = np.eye(4)
    angle = 0.4  # turned about z, and placed off the origin
    pose[:3, :3] = [
        [math.cos(angle), -math.sin(angle), 0],
        [math.sin(angle), math.cos(angle), 0],
        [0, 0, 1],
    ]
    pose[:3, 3] = (0.3, -0.2, 1.0)
    view = View("cam", 128, 96, pose, 60.0, 60.0, 64.0, 48.0, 0.01, 10.0)
    # SAPIEN's camera frame (x forward, y left, z up) in OpenCV's (x right, y down, z forward)
    cv_from_sapien = np.array([[0, -1, 0], [0, 0, -1], [1, 0, 0]], dtype=float)
    rotation = cv_from_sapien @ pose[:3, :3].T
    extrinsic = np.hstack([rotation, (-rotation @ pose[:3, 3])[:, None]])
    intrinsic = np.array([[60.0, 0, 64.0], [0, 60.0, 48.0], [0, 0, 1]])
    for point in ([2.0, 0.5, 1.2], [1.0, -0.3, 0.4], [0.9, 0.6, 1.5]):
        u, v, _ = view.project(np.array(point))
        assert project_cv(intrinsic, extrinsic, np.array(point)) == pytest.approx((u, v))


EXPECT_DEVICE = "ROBOSPEC_EXPECT_RENDER_DEVICE"


def _sapiens_own_answer() -> str | None:
    """Why SAPIEN itself cannot render here (its render system refuses to start), or None."""
    import sapien

    try:
        sapien.render.RenderSystem()
    except RuntimeError as refusal:
        return str(refusal)
    return None


@pytest.fixture(scope="module")
def render_device() -> None:
    reason = _sapiens_own_answer()
    if reason is not None and not os.environ.get(EXPECT_DEVICE):
        pytest.skip(f"SAPIEN has no render device here ({reason}): run on a GPU machine")


def test_robospec_finds_a_render_device_where_sapien_has_one_and_only_there() -> None:
    from robospec.physics.render import render_device_error

    sapien_says = _sapiens_own_answer()
    assert (render_device_error() is None) == (sapien_says is None), sapien_says
    if os.environ.get(EXPECT_DEVICE):
        assert sapien_says is None, f"{EXPECT_DEVICE} is set and SAPIEN finds no device"


def _sapien_and_preview(spec: Path) -> tuple[object, object, object]:
    """SAPIEN's capture of the spec's first camera at its first keyframe, the preview's view of
    it, and the robot as the preview places it."""
    from robospec import register
    from robospec.physics.check_run import CheckRun
    from robospec.physics.render import capture
    from robospec.pictures.posed import keyframe_poses, posed_robots
    from robospec.pictures.views import camera_view
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    assert compiled.context is not None and compiled.robot is not None
    register(spec)
    run = CheckRun(compiled.robot.uid, compiled.context, compiled.context.spec.checks)
    shot = capture(run)[0]
    robot = compiled.robot
    posed, _ = posed_robots(robot, compiled.context.description, keyframe_poses(robot), ("visual",))
    camera = robot.cameras[0]
    view = camera_view(camera, posed[0].links[camera.mount], camera.uid)
    return shot, view, posed[0]


def _agree(shot: object, view: object, at_rest: object, links: list[str]) -> None:
    for link in links:
        sapien_uv = shot.pixel(shot.links[link])  # type: ignore[attr-defined]
        preview_u, preview_v, _ = view.project(at_rest.links[link][:3, 3])  # type: ignore[attr-defined]
        assert math.dist(sapien_uv, (preview_u, preview_v)) <= PIXELS, (link, sapien_uv)


def _robot_masks_overlap(shot: object, view: object, at_rest: object) -> float:
    from robospec.pictures.renderer import VISUAL, Renderer
    from robospec.pictures.stage import robot_stage, table_stage

    renderer = Renderer(at_rest, view.width, view.height)  # type: ignore[arg-type, attr-defined]
    try:
        renderer.place(at_rest, robot_stage(0.0), table_stage(at_rest.root, None, None))  # type: ignore[arg-type, attr-defined]
        preview = renderer.labels(view, (VISUAL,)) >= 0  # type: ignore[arg-type]
    finally:
        renderer.close()
    sapien = shot.robot_mask  # type: ignore[attr-defined]
    return float((preview & sapien).sum()) / max(1, int((preview | sapien).sum()))


@pytest.mark.slow
@pytest.mark.usefixtures("render_device")
def test_sapien_and_the_preview_see_the_panda_fingers_from_the_same_hand_camera() -> None:
    shot, view, at_rest = _sapien_and_preview(WRISTCAM_SPEC)
    assert shot.tcp_pixel is not None  # type: ignore[attr-defined]
    _agree(shot, view, at_rest, ["panda_hand_tcp"])  # between the fingers it sees
    assert _robot_masks_overlap(shot, view, at_rest) > 0.7


@pytest.mark.slow
@pytest.mark.usefixtures("render_device")
def test_sapien_and_the_preview_see_the_g1_hands_from_the_same_head_camera() -> None:
    shot, view, at_rest = _sapien_and_preview(G1_HEAD_SPEC)
    _agree(
        shot,
        view,
        at_rest,
        ["left_palm_link", "right_palm_link", "left_tcp_link", "right_tcp_link"],
    )
    assert _robot_masks_overlap(shot, view, at_rest) > 0.7
