"""Joints that write no axis: MuJoCo turns them about z, ManiSkill's MJCF loader about x.

MuJoCo gives a hinge or slide joint the ``axis`` of its class (its own ``class``, else the
nearest ``childclass`` above it, else ``main``), and ``0 0 1`` where no class gives one.
ManiSkill 3.0.1's ``_parse_body`` reads the axis from its own merge of the defaults
(:func:`robospec.description.mjcf_loaded.loader_joints`) and takes ``1 0 0`` where it finds
none: such a joint turns (or slides) about x, and every link below it stands elsewhere once it
moves (dm_control's Kinova Jaco: up to 424 mm from where MuJoCo puts them). Both readings are
compared here, for validate (RS095) and for the mend that writes MuJoCo's axis on the joint
(:mod:`robospec.derive.axes`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from lxml import etree

from robospec.description.mjcf_loaded import Defaults, LoadedMjcf, loader_joints
from robospec.description.mjcf_mujoco import Table, childclass, effective
from robospec.description.mjcf_structure import names
from robospec.description.numbers import finite_numbers
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import MJCF_UNAXED_JOINT

MUJOCO_AXIS = "0 0 1"  # MuJoCo's default joint axis
_MOVING = ("hinge", "slide")


@dataclass(frozen=True)
class UnaxedJoint:
    """A joint ManiSkill's loader turns about x (it reads no axis) that MuJoCo turns about
    ``axis`` (as written, from class ``holder``; None: MuJoCo's default)."""

    joint: etree._Element
    axis: str
    holder: str | None


def unaxed_joints(
    robot: etree._Element,
    loader_classes: Mapping[str, Defaults],
    mujoco_classes: dict[str, Table],
) -> Iterator[UnaxedJoint]:
    """Every hinge and slide joint the loader builds of the robot (its ``<worldbody>`` body
    ``robot``) that it reads no axis for (it falls back to x), whose axis in MuJoCo's reading
    is another."""
    for joint, loaded in loader_joints(robot, loader_classes):
        mujoco = effective(mujoco_classes, joint)
        if mujoco.get("type", "hinge") not in _MOVING or loaded.get("type", "hinge") not in _MOVING:
            continue
        theirs = finite_numbers(loaded.get("axis"), 3)
        if "axis" in loaded and theirs is None:
            continue  # an axis the loader cannot read: the model's parse says what is wrong
        if theirs is not None and math.hypot(*theirs) >= 1e-3:
            continue  # the loader reads an axis (compared with MuJoCo's elsewhere, if at all)
        holder = childclass(joint) if "axis" in mujoco else None
        axis = mujoco.get("axis", MUJOCO_AXIS)
        meant = finite_numbers(axis, 3)
        if meant is None or math.hypot(*meant) < 1e-12:
            continue  # MuJoCo refuses it: its compile says so
        norm = math.hypot(*meant)
        if all(abs(m / norm - x) < 1e-9 for m, x in zip(meant, (1.0, 0.0, 0.0), strict=True)):
            continue  # x is what MuJoCo reads too
        yield UnaxedJoint(joint, axis, holder)


def unaxed(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS095: one error at the first joint ManiSkill's loader turns about x where MuJoCo
    turns it about another axis, listing the others."""
    found = list(unaxed_joints(loaded.robot_element, loaded.classes, loaded.mujoco_classes))
    if not found:
        return
    first = found[0]
    listed = names([item.joint.get("name", "") or "<joint>" for item in found[1:]])
    source = f"from class '{first.holder}'" if first.holder else "MuJoCo's default"
    yield error(
        loaded.where(first.joint),
        MJCF_UNAXED_JOINT,
        f"joint '{first.joint.get('name', '')}' writes no axis= and ManiSkill's MJCF loader "
        f'finds none in its defaults: it turns the joint about x ("1 0 0"), where MuJoCo '
        f'turns it about "{first.axis}" ({source})'
        + (f"; so do {len(found) - 1} more joint(s) ({listed})" if len(found) > 1 else "")
        + ": the links below it stand elsewhere once it moves",
        f'write axis="{first.axis}" on each such joint: `description: {{mend: {{axes: mujoco}}}}` '
        "does it in a copy of the model, or `description: {mjcf: ..., loader: mujoco}` loads "
        "the model as MuJoCo compiles it",
    )
