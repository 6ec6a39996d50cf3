"""The kinematic tree of a parsed description: children per link, depth-first rows, root paths.

Children keep the description's joint order (which is SAPIEN's breadth-first order), so every
walk here is deterministic. The tree includes the nameless fixed joints ManiSkill's MJCF loader
makes for bodies without joints (``RobotDescription.unnamed_joints``): without them an MJCF
robot's tree stops at its root.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from robospec.description import Joint, RobotDescription


@dataclass(frozen=True)
class TreeRow:
    depth: int
    link: str
    joint: Joint | None  # the joint attaching ``link`` to its parent; None for the root


class KinematicTree:
    """A description's links indexed both ways, built once: the group guesser asks for the root
    path of every joint, and rebuilding the maps per question made it quadratic."""

    def __init__(self, description: RobotDescription) -> None:
        self._join(description.root_link, description.link_names, description.tree_joints)

    @classmethod
    def of(cls, root: str, joints: Iterable[Joint]) -> KinematicTree:
        """The tree ``joints`` make under the link ``root`` (its links: the root and each
        joint's child), for a tree with no description at hand: the one ``robospec new``'s
        probe child is sent, or one a test makes up."""
        tree = cls.__new__(cls)
        listed = tuple(joints)
        tree._join(root, (root, *(joint.child for joint in listed)), listed)
        return tree

    def _join(self, root: str, links: Iterable[str], joints: tuple[Joint, ...]) -> None:
        self.root = root
        self.below: dict[str, list[Joint]] = {link: [] for link in links}
        for joint in joints:
            self.below.setdefault(joint.parent, []).append(joint)
        # link -> the joint that attaches it to its parent (every link but the root)
        self.up: dict[str, Joint] = {joint.child: joint for joint in joints}

    def rows(self) -> list[TreeRow]:
        """Every link once, depth first from the root, each with the joint that attaches it."""
        rows: list[TreeRow] = []
        stack: list[tuple[int, str, Joint | None]] = [(0, self.root, None)]
        seen: set[str] = set()
        while stack:
            depth, link, joint = stack.pop()
            if link in seen:  # the parser rejects cycles; this only guards the walk
                continue
            seen.add(link)
            rows.append(TreeRow(depth, link, joint))
            for child in reversed(self.below.get(link, [])):
                stack.append((depth + 1, child.child, child))
        return rows

    def root_path(self, link: str) -> list[Joint]:
        """The joints from the root down to ``link``, in that order."""
        path: list[Joint] = []
        while link in self.up and len(path) <= len(self.up):
            joint = self.up[link]
            path.append(joint)
            link = joint.parent
        return path[::-1]

    def joints_between(self, a: str, b: str) -> set[Joint]:
        """The joints on the tree's path from link ``a`` to link ``b``: those above one of
        them and not above the other."""
        return set(self.root_path(a)) ^ set(self.root_path(b))

    def joints_apart(self, a: str, b: str) -> int:
        """How many active joints lie between links ``a`` and ``b``."""
        return sum(1 for joint in self.joints_between(a, b) if joint.is_active)

    def leaves(self) -> list[str]:
        return [row.link for row in self.rows() if not self.below.get(row.link)]
