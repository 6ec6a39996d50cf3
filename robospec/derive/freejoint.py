"""Mend class ``freejoint: root`` (RS718, MJCF): a floating root written as ``<joint type="free">``.

MuJoCo has two spellings of a free joint, ``<freejoint/>`` and ``<joint type="free"/>`` (also
through a default class); ManiSkill's loader reads only the first, on the robot's
``<worldbody>`` body, and makes that body's tree a floating articulation. A ``<joint
type="free">`` makes it fail (RS052). The free joint of the robot's root body (or of the one
body a wrapper body holds, which the loader skips) is written as a ``<freejoint>`` of that
``<worldbody>`` body, with its name. A free joint anywhere else joins a second floating body to
the robot, which no articulation can hold: refused.
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import classes, effective, in_model, robot_body, whole
from robospec.diagnostics.codes import CANNOT_MEND, INVALID_STRUCTURE, MENDED_FREEJOINT

NAME = "freejoint"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_FREEJOINT
FIXES = (INVALID_STRUCTURE,)
WHY = 'the robot floats on a <joint type="free">; ManiSkill\'s loader reads only <freejoint>'


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    table = classes(root, document.source.path)
    free = [
        j for j in root.iter("joint") if in_model(j) and effective(table, j).get("type") == "free"
    ]
    if not free:
        return
    robot = robot_body(root)
    for joint in free:
        body = joint.getparent()
        if robot is None or body is None or not _is_root(body, robot):
            where = f"body '{body.get('name', '')}'" if body is not None else "a body"
            document.refuse(
                joint,
                CANNOT_MEND,
                f"mend 'freejoint: root' cannot mend the free joint of {where}: only the "
                "robot's root may float in a ManiSkill articulation, and this body is not it",
                "make the body a separate <worldbody> body (an object, not part of the robot), "
                "or fix it to its parent by removing the joint",
            )
            continue
        if robot.find("freejoint") is not None:
            continue  # the root already floats: the model's parse says two free joints
        name = joint.get("name")
        written = etree.Element("freejoint", {"name": name} if name else {})
        _replace(joint, written, robot)
        document.changed(
            joint,
            f"joint '{name}'" if name else f"free joint of body '{body.get('name', '')}'",
            '<joint type="free"> (ManiSkill\'s loader fails on it)',
            f"<freejoint> of body '{robot.get('name', '')}'",
        )


def _is_root(body: etree._Element, robot: etree._Element) -> bool:
    """Whether ``body`` is the robot's root: its ``<worldbody>`` body, or the one body that
    holds when it holds nothing else (the loader skips such a wrapper)."""
    if body is robot:
        return True
    inner = [c for c in robot if isinstance(c.tag, str)]
    return len(inner) == 1 and inner[0] is body


def _replace(joint: etree._Element, written: etree._Element, robot: etree._Element) -> None:
    """``written`` in place of ``joint`` where it stands in ``robot``, else as robot's first
    element; either way on the joint's line when it can be, so later lines keep theirs."""
    written.tail = joint.tail
    parent = joint.getparent()
    if parent is robot:
        joint.addnext(written)
        parent.remove(joint)
        return
    previous = joint.getprevious()
    if previous is not None:
        previous.tail = (previous.tail or "") + (joint.tail or "")
    elif parent is not None:
        parent.text = (parent.text or "") + (joint.tail or "")
    if parent is not None:
        parent.remove(joint)
    written.tail = robot.text
    robot.text = " "
    robot.insert(0, written)


def suggest(document: Document) -> str | None:
    return "root" if document.would_change(apply, "root") else None
