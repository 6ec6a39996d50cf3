"""``robospec check --render``: an image from every camera of the robot, at its first keyframe,
saved as PNG — the one physics-side output that needs a render device (a GPU machine).

Not a pass/fail check: it reports where each image went, so people can look at what the
robot's cameras see before training with them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics

NAME = "render"


def render_device_error() -> str | None:
    """Why images cannot be rendered here, or None when a render device exists."""
    import sapien

    try:
        sapien.render.RenderSystem()
    except RuntimeError as exc:
        return str(exc)
    return None


def check(run: CheckRun, out_dir: Path) -> list[Finding]:
    cameras = run.robot.cameras
    if not cameras:
        return [Finding(NAME, None, "-", Status.SKIP, "the robot has no cameras")]
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)
    from PIL import Image

    from robospec.physics.sim import set_keyframe

    env: Any = gym.make(
        "Empty-v1",
        robot_uids=run.uid,
        obs_mode="rgb",
        sim_backend=run.backend.sim_backend,
        num_envs=1,
    )
    try:
        env.reset(seed=0)
        base = env.unwrapped
        keyframe = run.keyframes[0]
        if keyframe is not None:
            set_keyframe(base.agent.robot, keyframe, 1)
        images = base.get_sensor_images()
        findings = []
        folder = out_dir / run.uid
        folder.mkdir(parents=True, exist_ok=True)
        for camera in cameras:
            rgb = images[camera.uid]["rgb"][0].cpu().numpy()
            path = folder / f"{camera.uid}.png"
            Image.fromarray(rgb).save(path)
            findings.append(
                Finding(
                    NAME,
                    None,
                    camera.uid,
                    Status.INFO,
                    f"{rgb.shape[1]}x{rgb.shape[0]} image: {path}",
                    metrics(path=str(path), width=int(rgb.shape[1]), height=int(rgb.shape[0])),
                )
            )
        return findings
    finally:
        env.close()
