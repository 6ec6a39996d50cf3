"""The joints ``robospec new``'s probe moves, and where they lie in the kinematic tree: the active
joints in qpos order with their limits, the mimic couplings that move followers with their
leaders, and the joints between two links (those a contact between them can be undone by).
The rest-pose search (:mod:`.pose_search`) and the collision exemptions (:mod:`.exemptions`)
both ask it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from robospec.kinematics.tree import KinematicTree

FULL_TURN = 2 * math.pi
# links this many active joints apart or fewer are neighbours: a contact between them in every
# pose is their shapes overlapping at the joint (a housing, a motor inside the body)
NEIGHBOURS = 2

Limits = tuple[float | None, float | None]
# (follower, leader, multiplier, offset), by index into the joints
MimicIndex = tuple[int, int, float, float]


class JointSpace:
    def __init__(
        self,
        tree: KinematicTree,
        joints: Sequence[str],
        limits: Sequence[Limits],
        mimic: Iterable[MimicIndex] = (),
    ) -> None:
        self.tree = tree
        self.joints = tuple(joints)
        self.limits = tuple(limits)
        self.mimic = tuple(mimic)
        self.index = {name: i for i, name in enumerate(self.joints)}
        self.followers = {follower for follower, _, _, _ in self.mimic}

    def follow(self, qpos: Sequence[float]) -> list[float]:
        """Mimic followers set from their leaders, every joint inside its limits."""
        out = [self.clamp(i, v) for i, v in enumerate(qpos)]
        for follower, leader, multiplier, offset in self.mimic:
            out[follower] = self.clamp(follower, out[leader] * multiplier + offset)
        return out

    def clamp(self, index: int, value: float) -> float:
        low, high = self.limits[index]
        if low is not None:
            value = max(value, low)
        if high is not None:
            value = min(value, high)
        return value

    def span(self, index: int) -> float:
        """How far joint ``index`` moves: its range, a full turn at most (or when unbounded)."""
        low, high = self.limits[index]
        if low is None or high is None:
            return FULL_TURN
        return min(high - low, FULL_TURN)

    def movable(self, pairs: Iterable[tuple[str, str]]) -> list[int]:
        """The joints (by index) between the links of each pair, leaders only."""
        found: set[int] = set()
        for a, b in pairs:
            for joint in self.tree.joints_between(a, b):
                if joint.name in self.index and self.index[joint.name] not in self.followers:
                    found.add(self.index[joint.name])
        return sorted(found)

    def nearest_first(self, a: str, b: str) -> list[int]:
        """The joints (leaders, by index) between links ``a`` and ``b``, those nearest either
        link first: the forearm's elbow and shoulder turn before the torso that carries the
        whole arm (and the head, and the other arm) leans."""
        path_a = [joint.name for joint in reversed(self.tree.root_path(a))]
        path_b = [joint.name for joint in reversed(self.tree.root_path(b))]
        between = set(path_a) ^ set(path_b)
        # how far up from its link each joint lies (each joint between them lies on one path);
        # of two as far up (a left and a right wrist), the first in qpos order
        height = {joint: i for path in (path_a, path_b) for i, joint in enumerate(path)}
        last = len(self.joints)
        order = sorted(between, key=lambda j: (height[j], self.index.get(j, last)))
        return [
            self.index[j] for j in order if j in self.index and self.index[j] not in self.followers
        ]

    def apart(self, a: str, b: str) -> int:
        """How many active joints lie between links ``a`` and ``b``."""
        return self.tree.joints_apart(a, b)

    def driven_by(self, link: str) -> str | None:
        """The active joint nearest above ``link`` (None for the root's welded body)."""
        while link in self.tree.up:
            joint = self.tree.up[link]
            if joint.name in self.index:
                return joint.name
            link = joint.parent
        return None
