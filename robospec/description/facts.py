"""Frozen facts about a robot description (URDF or MJCF), each with its source line.

This is everything robospec needs to know about a robot to check a spec: nothing after the
resolve stage touches the XML again.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

JointType = Literal[
    "revolute", "continuous", "prismatic", "fixed", "floating", "planar", "free", "ball"
]
# Joint types that add degrees of freedom SAPIEN exposes in qpos (one per joint).
ACTIVE_JOINT_TYPES: frozenset[str] = frozenset({"revolute", "continuous", "prismatic"})


@dataclass(frozen=True)
class Mimic:
    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class Link:
    name: str
    line: int


@dataclass(frozen=True)
class Joint:
    name: str
    type: JointType
    parent: str
    child: str
    line: int
    lower: float | None = None  # None: unbounded (continuous joints, free MJCF joints)
    upper: float | None = None
    mimic: Mimic | None = None
    # <limit velocity= effort=> (URDF); None when the description does not give them
    velocity: float | None = None
    effort: float | None = None

    @property
    def is_active(self) -> bool:
        return self.type in ACTIVE_JOINT_TYPES


@dataclass(frozen=True)
class RobotDescription:
    """A parsed robot description.

    ``active_joints`` lists the joints in exactly the order SAPIEN/ManiSkill uses for qpos,
    so a keyframe written by joint name can be turned into the ordered array ManiSkill expects.
    """

    kind: Literal["urdf", "mjcf"]
    path: str  # the file as the user's spec names it after expansion (for messages)
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    active_joint_names: tuple[str, ...]
    root_link: str
    # True when the root is attached to the world by a floating/free joint (MJCF freejoint).
    floating_root: bool = False
    # a stand-in built from the spec's own names: the real file is not downloaded yet
    assumed: bool = False
    # group-2 collision bits ManiSkill's loader sets by itself, each with the links that carry
    # it: an SRDF's "Default" disable_collisions pairs (URDF), every body with its parent body
    # (MJCF). Links sharing one of these bits never collide with each other.
    loader_collision_bits: tuple[tuple[int, tuple[str, ...]], ...] = ()
    _links_by_name: dict[str, Link] = field(default_factory=dict, repr=False, compare=False)
    _joints_by_name: dict[str, Joint] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._links_by_name.update({link.name: link for link in self.links})
        self._joints_by_name.update({joint.name: joint for joint in self.joints})

    def link(self, name: str) -> Link | None:
        return self._links_by_name.get(name)

    def joint(self, name: str) -> Joint | None:
        return self._joints_by_name.get(name)

    @property
    def link_names(self) -> tuple[str, ...]:
        return tuple(link.name for link in self.links)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(joint.name for joint in self.joints)

    def adjacent_pairs(self) -> frozenset[tuple[str, str]]:
        """Pairs of links (each sorted) joined by a joint: PhysX never collides a link with its
        parent in an articulation, whatever the collision groups say."""
        return frozenset(
            (min(j.parent, j.child), max(j.parent, j.child))
            for j in self.joints
            if j.parent and j.child and j.parent != j.child
        )

    @property
    def active_joints(self) -> tuple[Joint, ...]:
        return tuple(self._joints_by_name[name] for name in self.active_joint_names)
