"""The kinematic tree of a parsed description: children per link, depth-first rows, root paths.

Children keep the description's joint order (which is SAPIEN's breadth-first order), so every
walk here is deterministic.
"""

from __future__ import annotations

from dataclasses import dataclass

from robospec.description import Joint, RobotDescription


@dataclass(frozen=True)
class TreeRow:
    depth: int
    link: str
    joint: Joint | None  # the joint attaching ``link`` to its parent; None for the root


def children(description: RobotDescription) -> dict[str, list[Joint]]:
    out: dict[str, list[Joint]] = {link.name: [] for link in description.links}
    for joint in description.joints:
        out.setdefault(joint.parent, []).append(joint)
    return out


def tree_rows(description: RobotDescription) -> list[TreeRow]:
    """Every link once, depth first from the root, each with the joint that attaches it."""
    below = children(description)
    rows: list[TreeRow] = []
    stack: list[tuple[int, str, Joint | None]] = [(0, description.root_link, None)]
    seen: set[str] = set()
    while stack:
        depth, link, joint = stack.pop()
        if link in seen:  # the parser rejects cycles; this only guards the walk
            continue
        seen.add(link)
        rows.append(TreeRow(depth, link, joint))
        for child in reversed(below.get(link, [])):
            stack.append((depth + 1, child.child, child))
    return rows


def parent_joints(description: RobotDescription) -> dict[str, Joint]:
    """link -> the joint that attaches it to its parent (every link but the root)."""
    return {joint.child: joint for joint in description.joints}


def root_path(description: RobotDescription, link: str) -> list[Joint]:
    """The joints from the root down to ``link``, in that order."""
    up = parent_joints(description)
    path: list[Joint] = []
    while link in up and len(path) <= len(up):
        joint = up[link]
        path.append(joint)
        link = joint.parent
    return path[::-1]


def leaves(description: RobotDescription) -> list[str]:
    below = children(description)
    return [row.link for row in tree_rows(description) if not below.get(row.link)]
