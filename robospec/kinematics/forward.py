"""Forward kinematics of a robot description, in plain Python: where each link is at a pose,
relative to the root link, and which way each joint moves.

``robospec new`` asks it where the legs are (front or rear, left or right) and whether the
first joints of the tree slide along x and y and turn about z (a planar mobile base). The
links are ManiSkill's (an MJCF body with two joints is two links, the first named
``{body}_dummy_0``, as :mod:`robospec.description.mjcf` documents), so the names agree with the
robot's facts.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from lxml import etree

from robospec.description.numbers import finite_numbers
from robospec.description.urdf import parse_xml
from robospec.kinematics.frames import (
    ZERO,
    Transform,
    Vector,
    about_axis,
    from_rpy,
    normalized,
    translation,
)
from robospec.kinematics.mjcf_model import MjBody, MjcfModel, vector


@dataclass(frozen=True)
class MovingJoint:
    """A joint as forward kinematics needs it: ``child = parent @ origin @ motion(q)``, the
    motion turning about (or sliding along) ``axis`` through ``pivot``, both in the joint's
    frame."""

    name: str
    type: str  # revolute, continuous, prismatic, or fixed for everything that does not move
    parent: str
    child: str
    origin: Transform
    axis: Vector = (1.0, 0.0, 0.0)
    pivot: Vector = ZERO

    def motion(self, q: float) -> Transform:
        if self.type == "prismatic":
            return translation((self.axis[0] * q, self.axis[1] * q, self.axis[2] * q))
        if self.type in ("revolute", "continuous") and q != 0.0:
            p = self.pivot
            turn = Transform(about_axis(self.axis, q))
            return translation(p) @ turn @ translation((-p[0], -p[1], -p[2]))
        return Transform()


@dataclass(frozen=True)
class KinematicModel:
    root: str
    joints: tuple[MovingJoint, ...]  # parents before children

    def link_poses(self, qpos: Mapping[str, float] | None = None) -> dict[str, Transform]:
        """Every link's pose relative to the root link, with the joints at ``qpos`` (by name;
        0 for joints it does not name)."""
        qpos = qpos or {}
        poses = {self.root: Transform()}
        for joint in self.joints:
            parent = poses.get(joint.parent)
            if parent is None:
                continue
            poses[joint.child] = parent @ joint.origin @ joint.motion(qpos.get(joint.name, 0.0))
        return poses

    def joint(self, name: str) -> MovingJoint | None:
        return next((j for j in self.joints if j.name == name), None)

    def axis_in_root(self, name: str, poses: Mapping[str, Transform]) -> Vector | None:
        """Joint ``name``'s axis in the root frame, at the pose ``poses`` was made for."""
        joint = self.joint(name)
        if joint is None or joint.parent not in poses:
            return None
        return normalized((poses[joint.parent] @ joint.origin).direction(joint.axis))


def urdf_kinematics(text: bytes | str) -> KinematicModel | None:
    root, _ = parse_xml(text, "")
    if root is None:
        return None
    joints: list[MovingJoint] = []
    for element in root.findall("joint"):
        parent, child = element.find("parent"), element.find("child")
        if parent is None or child is None:
            continue
        origin = element.find("origin")
        rpy = vector(origin.get("rpy") if origin is not None else None)
        xyz = vector(origin.get("xyz") if origin is not None else None)
        axis_element = element.find("axis")
        axis = finite_numbers(axis_element.get("xyz") if axis_element is not None else None, 3)
        joints.append(
            MovingJoint(
                name=element.get("name", ""),
                type=element.get("type", "fixed"),
                parent=parent.get("link", ""),
                child=child.get("link", ""),
                origin=Transform(from_rpy(*rpy), xyz),
                axis=normalized(axis) if axis else (1.0, 0.0, 0.0),  # type: ignore[arg-type]
            )
        )
    children = {j.child for j in joints}
    links = [link.get("name", "") for link in root.findall("link")]
    roots = [name for name in links if name not in children]
    if not roots:
        return None
    return KinematicModel(roots[0], _parents_first(roots[0], joints))


def mjcf_kinematics(model: MjcfModel) -> KinematicModel | None:
    """The first articulated body tree under ``<worldbody>``, linked as ManiSkill links it."""
    for index, body in enumerate(model.bodies):
        if not _articulated(body):
            continue
        root = f"dummy_root_{index}"
        inner = body.children[0] if _wrapper(body) else body
        joints: list[MovingJoint] = []
        _link_body(model, inner, root, joints)
        return KinematicModel(root, tuple(joints))
    return None


def _articulated(body: MjBody) -> bool:
    return bool(body.joints) or any(_articulated(child) for child in body.children)


def _wrapper(body: MjBody) -> bool:
    """ManiSkill skips a body holding one body and no geom or joint."""
    tags = [child.tag for child in body.element if isinstance(child.tag, str)]
    return tags.count("body") == 1 and "geom" not in tags and "joint" not in tags


def _link_body(model: MjcfModel, body: MjBody, parent: str, out: list[MovingJoint]) -> None:
    moving = [j for j in body.joints if j.type in ("hinge", "slide")]
    if not moving:
        out.append(MovingJoint("", "fixed", parent, body.name, body.pose))
    for i, joint in enumerate(moving):
        child = body.name if i == len(moving) - 1 else f"{body.name}_dummy_{i}"
        limited = joint.attributes.get("limited", "auto")
        bounded = "range" in joint.attributes if limited == "auto" else limited == "true"
        kind = "prismatic" if joint.type == "slide" else "revolute" if bounded else "continuous"
        axis = finite_numbers(joint.attributes.get("axis"), 3) or (0.0, 0.0, 1.0)
        out.append(
            MovingJoint(
                name=joint.name,
                type=kind,
                parent=parent,
                child=child,
                origin=body.pose if i == 0 else Transform(),
                axis=normalized(axis),  # type: ignore[arg-type]
                pivot=vector(joint.attributes.get("pos")),
            )
        )
        parent = child
    for child_body in body.children:
        _link_body(model, child_body, body.name, out)


def _parents_first(root: str, joints: list[MovingJoint]) -> tuple[MovingJoint, ...]:
    below: dict[str, list[MovingJoint]] = {}
    for joint in joints:
        below.setdefault(joint.parent, []).append(joint)
    ordered: list[MovingJoint] = []
    queue, seen = [root], {root}
    while queue:
        link = queue.pop(0)
        for joint in below.get(link, []):
            if joint.child not in seen:
                seen.add(joint.child)
                ordered.append(joint)
                queue.append(joint.child)
    return tuple(ordered)


def element_name(element: etree._Element) -> str:
    return element.get("name", "")
