"""Mend class ``axes: mujoco`` (RS724, MJCF): joints that write no axis.

MuJoCo turns a hinge or slide joint that neither writes an ``axis`` nor takes one from its
class about z (``0 0 1``); ManiSkill's loader, finding no axis in its own reading of the
defaults, turns it about x (RS095; robospec.description.mjcf_axes): every link below it stands
elsewhere once it moves. Each such joint gets ``axis=`` written on it, the axis MuJoCo reads:
MuJoCo reads the model as before, and ManiSkill turns the joint as MuJoCo does.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import classes, robot_body, whole
from robospec.description.mjcf_axes import unaxed_joints
from robospec.description.mjcf_loaded import loader_classes
from robospec.diagnostics.codes import MENDED_AXES, MJCF_UNAXED_JOINT

NAME = "axes"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_AXES
FIXES = (MJCF_UNAXED_JOINT,)
WHY = "joints write no axis: MuJoCo turns them about z, ManiSkill's loader about x"


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    robot = robot_body(root)
    if robot is None:
        return  # no robot: the description's parse says so
    loaded, _lines = loader_classes(child for child in root if child.tag == "default")
    for item in list(unaxed_joints(robot, loaded, classes(root, document.source.path))):
        joint = item.joint
        source = f"class '{item.holder}'" if item.holder else "MuJoCo's default"
        document.changed(
            joint,
            f"joint '{joint.get('name')}'" if joint.get("name") else "<joint>",
            f'no axis (ManiSkill: "1 0 0"; {source}: "{item.axis}")',
            f'axis="{item.axis}"',
        )
        joint.set("axis", item.axis)


def suggest(document: Document) -> str | None:
    return "mujoco" if document.would_change(apply, "mujoco") else None
