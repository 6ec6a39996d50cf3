"""What a camera of the robot sees, judged from a segmentation picture of its view.

Each camera is pictured at every keyframe from its mount (:mod:`robospec.pictures.album`), once
with the robot alone and once at the table scene; the segmentation picture says which link, if
any, each pixel shows. A warning, at the camera in the spec, with the picture's path:

- RS560 — its own mount link (and the links fixed to it) covers more of the picture than
  ``checks.camera_views.max_mount_fraction``: the camera is inside or behind its housing;
- RS561 — the robot covers more of the picture than ``max_robot_fraction``: it looks into the
  robot;
- RS562 — less of the table scene's picture than ``min_seen_fraction`` shows anything within
  ``far``: the camera looks at the sky, or ``far`` is too short;
- RS563 — a camera that moves with the tcp (its mount is the tcp's link or fixed to it: a wrist
  camera, named after the tcp it watches) does not see the tcp: it is not in the picture, or is
  behind the camera or past ``far`` (``tcp_in_view``).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from robospec.description.facts import RobotDescription
from robospec.diagnostics.codes import (
    CAMERA_COVERED_BY_MOUNT,
    CAMERA_COVERED_BY_ROBOT,
    CAMERA_LOOKS_AWAY,
    CAMERA_SEES_NOTHING,
)
from robospec.pictures.posed import PosedRobot
from robospec.pictures.renderer import NOTHING
from robospec.pictures.views import View


@dataclass(frozen=True)
class Finding:
    code: str
    message: str
    hint: str


@dataclass(frozen=True)
class Limits:
    max_mount_fraction: float
    max_robot_fraction: float
    min_seen_fraction: float
    tcp_in_view: bool


def rigid_links(description: RobotDescription, link: str) -> frozenset[str]:
    """``link`` and every link joined to it by fixed joints only (they move as one body)."""
    neighbours: dict[str, set[str]] = {}
    for joint in description.tree_joints:
        if joint.type == "fixed" and joint.parent and joint.child:
            neighbours.setdefault(joint.parent, set()).add(joint.child)
            neighbours.setdefault(joint.child, set()).add(joint.parent)
    found, queue = {link}, [link]
    while queue:
        for other in neighbours.get(queue.pop(), ()):
            if other not in found:
                found.add(other)
                queue.append(other)
    return frozenset(found)


def shares(labels: np.ndarray, robot: PosedRobot, links: Iterable[str]) -> tuple[float, float]:
    """(the fraction of pixels showing ``links``, the fraction showing the robot)."""
    total = labels.size or 1
    wanted = set(links)
    indices = [i for i, shape in enumerate(robot.shapes) if shape.link in wanted]
    mount = np.isin(labels, indices).sum() if indices else 0
    return float(mount) / total, float((labels >= 0).sum()) / total


def judge(
    view: View,
    alone: np.ndarray,
    table: np.ndarray,
    robot: PosedRobot,
    mount_links: frozenset[str],
    tcp: tuple[str, np.ndarray] | None,
    limits: Limits,
    picture: str,
    table_picture: str,
) -> list[Finding]:
    """The findings about one camera at one keyframe; ``alone`` and ``table`` are the labels
    of its two pictures, ``tcp`` the name and world position of the tcp it should see (None:
    the camera does not move with the tcp)."""
    findings = []
    mount, robot_share = shares(alone, robot, mount_links)
    if mount > limits.max_mount_fraction:
        findings.append(
            Finding(
                CAMERA_COVERED_BY_MOUNT,
                f"its own mount covers {mount:.0%} of the picture (more than "
                f"{limits.max_mount_fraction:.0%}): {picture}",
                "move the camera out of its housing (pose.p) or turn it outward (pose.q); "
                "checks.camera_views.max_mount_fraction sets the limit",
            )
        )
    elif robot_share > limits.max_robot_fraction:
        findings.append(
            Finding(
                CAMERA_COVERED_BY_ROBOT,
                f"the robot covers {robot_share:.0%} of the picture (more than "
                f"{limits.max_robot_fraction:.0%}): {picture}",
                "turn the camera away from the robot (pose.q); "
                "checks.camera_views.max_robot_fraction sets the limit",
            )
        )
    seen = float((table != NOTHING).sum()) / (table.size or 1)
    if seen < limits.min_seen_fraction:
        findings.append(
            Finding(
                CAMERA_SEES_NOTHING,
                f"sees nothing within far ({view.far:g} m) in {1 - seen:.0%} of the picture "
                f"at the table: {table_picture}",
                "turn the camera toward the scene (pose.q) or raise far; "
                "checks.camera_views.min_seen_fraction sets the limit",
            )
        )
    if tcp is not None and limits.tcp_in_view:
        name, point = tcp
        if not view.sees(point):
            u, v, depth = view.project(point)
            where = (
                "it is behind the camera"
                if depth <= 0
                else f"it is past far ({depth:.2f} m away)"
                if depth > view.far
                else f"it is nearer than near ({depth:.3f} m away)"
                if depth < view.near
                else f"it lands at pixel ({u:.0f}, {v:.0f}), outside the "
                f"{view.width}x{view.height} picture"
            )
            findings.append(
                Finding(
                    CAMERA_LOOKS_AWAY,
                    f"moves with the tcp '{name}' but looks away from it ({where}): {picture}",
                    "turn the camera toward the tcp (pose.q: the camera looks along its x "
                    "axis, z up); checks.camera_views.tcp_in_view: false if it is meant",
                )
            )
    return findings
