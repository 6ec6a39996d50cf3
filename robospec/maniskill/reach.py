"""How far a loaded robot reaches: what ``check --task`` (RS526) and ``solve`` measure a task's
objects against, as the task placed the robot."""

from __future__ import annotations

from typing import Any

import numpy as np


def chain_reach(robot: Any) -> float | None:
    """The length of the robot's longest chain of links: from the root, each link's distance
    from its parent link (joint frames and link origins), summed; plus the farthest point of
    the last link's collision shapes."""
    lengths: dict[str, float] = {}
    links = {link.name: link for link in robot.links}
    pose = {name: link.pose.p[0].cpu().numpy() for name, link in links.items()}

    def length(name: str) -> float:
        if name in lengths:
            return lengths[name]
        link = links[name]
        parent = link.joint.parent_link if link.joint is not None else None
        if parent is None:
            lengths[name] = 0.0
        else:
            step = float(np.linalg.norm(pose[name] - pose[parent.name]))
            lengths[name] = length(parent.name) + step
        return lengths[name]

    best = 0.0
    for name, link in links.items():
        extent = 0.0
        body = link._objs[0]
        if body.collision_shapes:
            low, high = body.compute_global_aabb_tight()
            corners = np.array([low, high], dtype=np.float64)
            extent = float(np.max(np.linalg.norm(corners - pose[name], axis=1)))
        best = max(best, length(name) + extent)
    return best
