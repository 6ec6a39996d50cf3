"""Where a part can be mounted on a robot, and where a robot mounts as a part: the frames a
description offers for ``parts:`` (``robospec inspect`` lists them, ``robospec new --attach``
takes the first when no link is given).

On an arm, a tool flange: an empty leaf frame fixed to the last link (``tool0``, ``ee_link``,
``flange``, ``link_eef``: ROS-Industrial and most vendors name one), an MJCF site made for
attaching (``attachment_site``, ``wristsite``), else the last link of the longest chain. On a
hand or a gripper, its root link: the part's frame that ``at`` and ``pose`` place. Each comes
with the pose to write: identity at a frame the description already puts where the part goes,
the site's pose in its body for an MJCF site.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from lxml import etree

from robospec.authoring.description_file import DescriptionFile
from robospec.description.facts import RobotDescription
from robospec.description.mjcf_frames import Unparsable, body_pose
from robospec.geometry import IDENTITY, IDENTITY_POSE, Pose

# names vendors give a tool flange or an attachment point (whole words of the name)
FLANGE_NAMES = re.compile(
    r"(^|_)(tool0|tool|flange|ee|eef|ee_link|end_effector|endeffector|tcp|attach\w*|mount\w*|"
    r"wrist\w*|hand_mount|gripper_mount)($|_|\d)",
    re.IGNORECASE,
)
MIN_ARM_JOINTS = 4  # a chain this long ends where an arm takes a tool (a finger's does not)


@dataclass(frozen=True)
class MountingFrame:
    """A place to mount a part: ``at`` (a link) and the ``pose`` there, and why it is one."""

    at: str
    pose: Pose
    why: str
    role: str  # "flange" (a part goes here) or "root" (this robot goes there as a part)

    def pose_yaml(self) -> dict[str, list[float]] | None:
        """The pose as a spec writes it, None for the identity."""
        if self.pose == IDENTITY_POSE:
            return None
        p, q = self.pose
        out: dict[str, list[float]] = {}
        if any(p):
            out["p"] = [round(v, 9) for v in p]
        if q != IDENTITY:
            out["q"] = [round(v, 9) for v in q]
        return out


def mounting_frames(source: DescriptionFile) -> list[MountingFrame]:
    """The description's mounting frames, the likeliest first: flanges, then its root."""
    description = source.description
    try:
        root = etree.fromstring(source.text) if source.text else None
    except etree.XMLSyntaxError:
        root = None
    frames = _urdf_flanges(description, root) if description.kind == "urdf" else _mjcf_sites(root)
    frames += _distal(description, {f.at for f in frames})
    frames.append(_root(description, root))
    return frames


def _urdf_flanges(
    description: RobotDescription, root: etree._Element | None
) -> list[MountingFrame]:
    if root is None:
        return []
    empty = {
        str(link.get("name"))
        for link in root.findall("link")
        if not any(child.tag in ("inertial", "visual", "collision") for child in link)
    }
    parents = {j.child: j for j in description.tree_joints}
    children = {j.parent for j in description.tree_joints}
    found = []
    for link in description.link_names:
        joint = parents.get(link)
        if link in empty and link not in children and joint is not None and joint.type == "fixed":
            named = bool(FLANGE_NAMES.search(link))
            why = f"an empty frame fixed to '{joint.parent}'" + (
                ", named as a tool flange" if named else ""
            )
            found.append((named, MountingFrame(link, IDENTITY_POSE, why, "flange")))
    flanges = [frame for is_named, frame in found if is_named]
    # an unnamed empty leaf is a flange only when it is the one there is (a hand's fingertip
    # frames are not)
    return flanges or ([found[0][1]] if len(found) == 1 else [])


def _mjcf_sites(root: etree._Element | None) -> list[MountingFrame]:
    if root is None:
        return []
    compiler = root.find("compiler")
    degrees = (compiler.get("angle", "degree") if compiler is not None else "degree") == "degree"
    eulerseq = compiler.get("eulerseq", "xyz") if compiler is not None else "xyz"
    found = []
    for site in root.iter("site"):
        body = site.getparent()
        name = site.get("name") or ""
        if (
            body is None
            or body.tag != "body"
            or not body.get("name")
            or not FLANGE_NAMES.search(name)
        ):
            continue
        try:
            pose = body_pose(dict(site.attrib), degrees, eulerseq or "xyz")
        except (Unparsable, ValueError):
            continue
        leaf = body.find("body") is None
        why = f"site '{name}' of body '{body.get('name')}'" + (", the last body" if leaf else "")
        found.append((not leaf, MountingFrame(str(body.get("name")), pose, why, "flange")))
    return [frame for _, frame in sorted(found, key=lambda item: item[0])]


def _distal(description: RobotDescription, taken: set[str]) -> list[MountingFrame]:
    """The link at the end of the longest chain of moving joints (an arm's last link)."""
    parents = {j.child: j for j in description.tree_joints}
    best, depth = None, 0
    for link in description.link_names:
        moving, current, seen = 0, link, set()
        while current in parents and current not in seen:
            seen.add(current)
            joint = parents[current]
            moving += joint.is_active
            current = joint.parent
        if moving > depth:
            best, depth = link, moving
    if best is None or best in taken or depth < MIN_ARM_JOINTS:
        return []
    return [
        MountingFrame(best, IDENTITY_POSE, f"the last link of a chain of {depth} joints", "flange")
    ]


def _root(description: RobotDescription, root: etree._Element | None) -> MountingFrame:
    link = description.root_link
    if description.kind == "mjcf":  # ManiSkill's dummy root holds the model's root body
        link = next((j.child for j in description.tree_joints if j.parent == link), link)
    why = "its root link, where it is fixed when it is a part of another robot"
    if root is not None and description.kind == "urdf":
        element = next((e for e in root.findall("link") if e.get("name") == link), None)
        below = [j for j in description.tree_joints if j.parent == link]
        if (
            element is not None
            and not any(c.tag in ("inertial", "visual", "collision") for c in element)
            and len(below) == 1
            and below[0].type == "fixed"
        ):
            why += f" (an empty frame over '{below[0].child}': fold_frames leaves it out)"
    return MountingFrame(link, IDENTITY_POSE, why, "root")
