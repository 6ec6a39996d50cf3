"""How far a loaded robot reaches: what ``check --task`` (RS526) and ``solve`` measure a task's
objects against, as the task placed the robot."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from mani_skill.utils.structs import Articulation, Link


def chain_reach(robot: Articulation, base: str | None = None) -> float | None:
    """The length of the robot's longest chain of links: from the root (or from the link
    ``base``, over the links it carries), each link's distance from its parent link (joint
    frames and link origins), summed; plus the farthest point of the last link's collision
    shapes."""
    lengths: dict[str, float | None] = {}
    links = {link.name: link for link in robot.links}
    pose = {name: link.pose.p[0].cpu().numpy() for name, link in links.items()}

    def length(name: str) -> float | None:
        """From ``base`` to the link, along the tree; None for a link ``base`` does not carry."""
        if name in lengths:
            return lengths[name]
        link = links[name]
        parent = link.joint.parent_link if link.joint is not None else None
        if name == base or (parent is None and base is None):
            lengths[name] = 0.0
        elif parent is None:
            lengths[name] = None
        else:
            above = length(parent.name)
            step = float(np.linalg.norm(pose[name] - pose[parent.name]))
            lengths[name] = None if above is None else above + step
        return lengths[name]

    best = 0.0
    for name, link in links.items():
        along = length(name)
        if along is None:
            continue
        extent = 0.0
        body = link._objs[0]
        if body.collision_shapes:
            low, high = body.compute_global_aabb_tight()
            corners = np.array([low, high], dtype=np.float64)
            extent = float(np.max(np.linalg.norm(corners - pose[name], axis=1)))
        best = max(best, along + extent)
    return best


def chain_up(link: Link) -> list[Link]:
    """``link`` (a loaded robot's link) and the links above it, to the root: the one walk up
    the tree that the reach, the solver's gripper facts and the arm's base take."""
    chain = [link]
    while link.joint is not None and link.joint.parent_link is not None:
        link = link.joint.parent_link
        chain.append(link)
    return chain


def moving_joints_above(link: Link) -> set[str]:
    """The names of the moving joints between the root and ``link``."""
    return {
        below.joint.name
        for below in chain_up(link)[:-1]  # the root has no joint above it
        if below.joint.active_index is not None
    }


def arm_base(link: Link) -> Link:
    """The link an arm hangs from: above ``link`` (its tcp), the parent of the first moving
    joint of the chain from the root (the root itself for an arm on it; one arm's own base,
    welded to the root beside another's, for a robot of two)."""
    base = link
    for below in chain_up(link)[:-1]:  # from the tcp up: the last moving joint's parent wins
        if below.joint.active_index is not None:
            parent = below.joint.parent_link
            assert parent is not None  # (chain_up's links below the root hang from one)
            base = parent
    return base
