"""``robospec check --render``: each camera's picture from SAPIEN's renderer at every keyframe,
saved as PNG beside the names ``robospec doc --images`` gives the CPU preview, and compared
with that preview — the one physics-side output that needs a render device (a GPU machine).

``DIR/<uid>/<keyframe>/<camera>.camera.png`` is what the policy sees (ManiSkill's Empty-v1
scene: the robot on its ground). Where the robot's tcp lands in SAPIEN's picture (the camera's
own pose and intrinsic matrix, the tcp link where SAPIEN put it) is compared with where the CPU
preview puts it (robospec's kinematics and camera model, :mod:`robospec.pictures.views`): more
than :data:`TOLERANCE_PX` apart is RS564, a warning at the camera — the preview would not show
what the policy sees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from robospec.diagnostics import warning
from robospec.diagnostics.codes import CAMERA_PREVIEW_DISAGREES
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics

if TYPE_CHECKING:
    from mani_skill.envs.sapien_env import BaseEnv
    from mani_skill.utils.structs import Articulation

NAME = "render"
TOLERANCE_PX = 3.0


def render_device_error() -> str | None:
    """Why images cannot be rendered here, or None when a render device exists."""
    import sapien

    try:
        sapien.render.RenderSystem()
    except RuntimeError as exc:
        return str(exc)
    return None


def project_cv(
    intrinsic: np.ndarray, extrinsic: np.ndarray, point: np.ndarray
) -> tuple[float, float]:
    """Where ``point`` (world) lands in a camera given as OpenCV matrices, as SAPIEN gives them:
    ``extrinsic`` (3x4) takes the world into the camera's frame (x right, y down, z forward),
    ``intrinsic`` (3x3) onto pixels (u right, v down, from the top-left corner)."""
    camera = extrinsic[:3, :3] @ np.asarray(point, dtype=np.float64) + extrinsic[:3, 3]
    if camera[2] <= 1e-9:
        return math.inf, math.inf
    pixel = intrinsic @ (camera / camera[2])
    return float(pixel[0]), float(pixel[1])


@dataclass(frozen=True)
class Capture:
    """One camera at one keyframe, as SAPIEN rendered it."""

    keyframe: str
    camera: str
    rgb: np.ndarray  # (H, W, 3) uint8
    robot_mask: np.ndarray  # (H, W) bool: the pixels showing a link of the robot
    tcp_pixel: tuple[float, float] | None  # where the tcp lands; None: the spec names none
    intrinsic: np.ndarray  # the camera's, OpenCV's (3x3), as SAPIEN gives it
    extrinsic: np.ndarray  # world to camera, OpenCV's (3x4)
    links: dict[str, np.ndarray]  # every link's world position, as SAPIEN placed it

    def pixel(self, point: np.ndarray) -> tuple[float, float]:
        return project_cv(self.intrinsic, self.extrinsic, point)


def capture(run: CheckRun) -> list[Capture]:
    """Every camera's picture at every keyframe, from SAPIEN (needs a render device)."""
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    from robospec.physics.sim import set_keyframe

    env = gym.make(
        "Empty-v1",
        robot_uids=run.uid,
        obs_mode="rgb+segmentation",
        sim_backend=run.backend.sim_backend,
        num_envs=1,
    )
    try:
        env.reset(seed=0)
        base = cast("BaseEnv", env.unwrapped)
        robot = base.agent.robot
        link_ids = {int(link.per_scene_id[0]) for link in robot.links}
        captures = []
        for keyframe in run.keyframes:
            if keyframe is not None:
                set_keyframe(robot, keyframe, 1)
            base.scene.update_render()
            observation = base.get_obs()
            params = base.get_sensor_params()
            tcp = _tcp_position(run, robot)
            links = {
                name: link.pose.p[0].cpu().numpy().astype(np.float64)
                for name, link in robot.links_map.items()
            }
            for camera in run.robot.cameras:
                data = observation["sensor_data"][camera.uid]
                rgb = data["rgb"][0].cpu().numpy()[..., :3].astype(np.uint8)
                segmentation = data["segmentation"][0, ..., 0].cpu().numpy()
                intrinsic = params[camera.uid]["intrinsic_cv"][0].cpu().numpy().astype(float)
                extrinsic = params[camera.uid]["extrinsic_cv"][0].cpu().numpy().astype(float)
                captures.append(
                    Capture(
                        keyframe.name if keyframe is not None else "zero",
                        camera.uid,
                        rgb,
                        np.isin(segmentation, list(link_ids)),
                        None if tcp is None else project_cv(intrinsic, extrinsic, tcp),
                        intrinsic,
                        extrinsic,
                        links,
                    )
                )
        return captures
    finally:
        env.close()


def _tcp_position(run: CheckRun, robot: Articulation) -> np.ndarray | None:
    tcp = run.robot.tcp
    if tcp is None:
        return None
    links = robot.links_map
    names = [tcp.link] if tcp.link is not None else list(tcp.midpoint or ())
    if not names or any(name not in links for name in names):
        return None
    points = [links[name].pose.p[0].cpu().numpy().astype(np.float64) for name in names]
    return np.mean(points, axis=0)


def preview_tcp_pixels(run: CheckRun) -> dict[tuple[str, str], tuple[float, float]]:
    """Where the CPU preview (``doc --images``) puts the tcp in each camera at each keyframe."""
    from robospec.pictures.album import tcp_position
    from robospec.pictures.posed import keyframe_poses, posed_robots
    from robospec.pictures.views import camera_view

    robot, description = run.robot, run.context.description
    # the links' poses only: no shape is read
    posed, _ = posed_robots(robot, description, keyframe_poses(robot), ())
    pixels = {}
    for robot_at in posed:
        tcp = tcp_position(robot, robot_at)
        for camera in robot.cameras:
            mount = robot_at.links.get(camera.mount)
            if tcp is None or mount is None:
                continue
            u, v, _ = camera_view(camera, mount, camera.uid).project(tcp[1])
            pixels[(robot_at.keyframe, camera.uid)] = (u, v)
    return pixels


def check(run: CheckRun, out_dir: Path) -> list[Finding]:
    cameras = run.robot.cameras
    if not cameras:
        return [Finding(NAME, None, "-", Status.SKIP, "the robot has no cameras")]
    from PIL import Image

    captures = capture(run)
    from robospec.pictures.gl import RenderUnavailable

    try:
        preview = preview_tcp_pixels(run)
    except (ImportError, RenderUnavailable):  # an MJCF robot is placed by MuJoCo (render extra)
        preview = {}
    findings = []
    for shot in captures:
        path = out_dir / run.uid / shot.keyframe / f"{shot.camera}.camera.png"
        path.parent.mkdir(parents=True, exist_ok=True)
        Image.fromarray(shot.rgb).save(path)
        height, width = shot.rgb.shape[:2]
        subject = f"{shot.camera} at {shot.keyframe}"
        expected = preview.get((shot.keyframe, shot.camera))
        apart = (
            math.dist(expected, shot.tcp_pixel)
            if expected is not None and shot.tcp_pixel is not None
            else None
        )
        found: tuple[Any, ...] = ()
        status = Status.INFO
        if apart is not None and not apart <= TOLERANCE_PX:
            assert expected is not None and shot.tcp_pixel is not None
            found = (
                warning(
                    run.at(("cameras", shot.camera)),
                    CAMERA_PREVIEW_DISAGREES,
                    f"camera '{shot.camera}' at keyframe '{shot.keyframe}': SAPIEN puts the "
                    f"tcp at pixel ({shot.tcp_pixel[0]:.1f}, {shot.tcp_pixel[1]:.1f}), the CPU "
                    f"preview at ({expected[0]:.1f}, {expected[1]:.1f}): {apart:.1f} px apart",
                    "the preview (robospec doc --images) and SAPIEN read the camera "
                    "differently; please report it with the spec",
                ),
            )
        findings.append(
            Finding(
                NAME,
                None,
                subject,
                status,
                f"{width}x{height} image: {path}"
                + (f"; tcp {apart:.1f} px from the preview's" if apart is not None else ""),
                metrics(
                    path=str(path),
                    width=int(width),
                    height=int(height),
                    tcp_px_from_preview=None if apart is None else float(apart),
                ),
                found,
            )
        )
    return findings
