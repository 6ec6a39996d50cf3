"""Link poses from SAPIEN: the robot as ManiSkill loads it, for the tools that already run
ManiSkill, and for what proves the light core's poses (:mod:`.forward`) against it.

The robot is loaded headless on the CPU (:func:`robospec.maniskill.headless.make_empty_env`:
no visual, no render device), its root put at a pose and its joints set with ``set_qpos``;
each link's ``pose`` is then SAPIEN's forward kinematics. ManiSkill and SAPIEN are imported
here only when asked.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

if TYPE_CHECKING:
    import numpy as np
    from mani_skill.envs.sapien_env import BaseEnv


@dataclass(frozen=True)
class Setting:
    """Where to put the robot: its root link's pose (position, wxyz quaternion) and every
    active joint's value, in ManiSkill's qpos order."""

    p: Sequence[float]
    q: Sequence[float]
    qpos: Sequence[float]


def simulated_link_poses(uid: str, settings: Iterable[Setting]) -> list[dict[str, np.ndarray]]:
    """For each setting, every link's world pose (4x4) as SAPIEN places the registered robot
    ``uid``."""
    import numpy as np
    import sapien
    import torch

    from robospec.kinematics.placement import pose_matrix
    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        env.reset(seed=0)
        robot = cast("BaseEnv", env.unwrapped).agent.robot
        found = []
        for setting in settings:
            robot.set_root_pose(sapien.Pose(list(setting.p), list(setting.q)))
            robot.set_qpos(torch.tensor([list(setting.qpos)], dtype=torch.float32))
            poses = {}
            for name, link in robot.links_map.items():
                p = link.pose.p[0].cpu().numpy().astype(np.float64)
                q = link.pose.q[0].cpu().numpy().astype(np.float64)
                poses[name] = pose_matrix(tuple(p), tuple(q))
            found.append(poses)
        return found
    finally:
        env.close()
