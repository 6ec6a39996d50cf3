"""Mend class ``spherical: hinges`` (RS711): ball joints SAPIEN's URDF loader has no type for.

pybullet's URDFs write ball joints as ``type="spherical"`` (the DeepMimic humanoid has eight);
SAPIEN knows only revolute, continuous, prismatic, fixed and floating joints and stops at the
first (RS052). A ball joint is three rotations about orthogonal axes through one point, so it
is written as three continuous joints, about x, y and z of the joint's frame, chained by two
links without mass (how ManiSkill's MJCF loader builds a body with several joints):
``J`` becomes ``J_x``, ``J_y`` and ``J_z``, and links ``J_x_link`` and ``J_y_link``. Every
other link keeps its pose at zero, its mass and inertia.
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document, insert_after
from robospec.diagnostics.codes import INVALID_STRUCTURE, MENDED_SPHERICAL

NAME = "spherical"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_SPHERICAL
FIXES = (INVALID_STRUCTURE,)
WHY = "SAPIEN has no spherical joint: each is three continuous joints (x, y, z)"

BALL_TYPES = frozenset({"spherical", "ball"})
_AXES = (("x", "1 0 0"), ("y", "0 1 0"), ("z", "0 0 1"))


def apply(document: Document, policy: str) -> None:
    root = document.tree
    names = {e.get("name") for e in root if isinstance(e.tag, str) and e.get("name")}
    for joint in list(root.iterfind("joint")):
        if joint.get("type") not in BALL_TYPES:
            continue
        name = joint.get("name") or "ball"
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            continue  # the tree's own errors say what is missing
        joints = [_unique(f"{name}_{axis}", names) for axis, _ in _AXES]
        links = [_unique(f"{name}_{axis}_link", names) for axis, _ in _AXES[:2]]
        kind = joint.get("type")
        # the first rotation is the joint itself, renamed; the other two and their links
        # follow it on its last line, so every element keeps its line
        joint.set("name", joints[0])
        joint.set("type", "continuous")
        _set_axis(joint, _AXES[0][1])
        original_child = child.get("link", "")
        child.set("link", links[0])
        added: list[etree._Element] = []
        for i in (1, 2):
            added.append(etree.Element("link", name=links[i - 1]))
            extra = etree.Element("joint", name=joints[i], type="continuous")
            etree.SubElement(extra, "parent", link=links[i - 1])
            etree.SubElement(extra, "child", link=links[i] if i < 2 else original_child)
            etree.SubElement(extra, "axis", xyz=_AXES[i][1])
            added.append(extra)
        insert_after(joint, added)
        document.changed(
            joint, f"joint '{name}'", f'type="{kind}"', f"continuous joints {', '.join(joints)}"
        )


def _set_axis(joint: etree._Element, xyz: str) -> None:
    axis = joint.find("axis")
    if axis is None:
        axis = etree.SubElement(joint, "axis")
        if len(joint) > 1:
            axis.tail, joint[-2].tail = joint[-2].tail, " "
    axis.set("xyz", xyz)


def _unique(name: str, taken: set[str | None]) -> str:
    candidate, n = name, 1
    while candidate in taken:
        n += 1
        candidate = f"{name}{n}"
    taken.add(candidate)
    return candidate


def suggest(document: Document) -> str | None:
    return "hinges" if document.would_change(apply, "hinges") else None
