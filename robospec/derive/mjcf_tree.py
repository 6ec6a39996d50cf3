"""The MJCF model as the MJCF mends read it: whole (includes written in place), its default
classes by MuJoCo's rules, and the body ManiSkill's loader takes for the robot.

A mend that looks at assets or defaults must see those an included file holds: the model is
made whole first, silently (a derived MJCF is carried with its includes in place anyway, see
:mod:`robospec.derive.mjcf_files`), and each element keeps the file and line it was written on.
"""

from __future__ import annotations

import os

from lxml import etree

from robospec.derive.document import Document
from robospec.description.mjcf_mujoco import (  # noqa: F401 (childclass, effective: here too)
    Includes,
    Table,
    childclass,
    effective,
    read_classes,
)


def whole(document: Document) -> etree._Element:
    """The model's root, every ``<include>`` written in place (the lines they came from kept)."""
    if next(document.tree.iter("include"), None) is not None:
        from robospec.derive.includes import inline_all

        inline_all(document, note=False)
    return document.tree


def classes(root: etree._Element, path: str) -> dict[str, Table]:
    """Every default class's table (MuJoCo's inheritance) of a whole model."""
    top = [child for child in root if isinstance(child.tag, str)]
    return read_classes(top, Includes(path, _no_file, {}))


def _no_file(path: str) -> bytes:
    raise OSError(path)  # a whole model includes nothing more


def in_model(element: etree._Element) -> bool:
    """Whether ``element`` is part of the model (not a ``<default>``'s template)."""
    return not any(a.tag == "default" for a in element.iterancestors())


def assets(root: etree._Element, tag: str) -> list[etree._Element]:
    """The ``<asset>`` elements of one kind (``mesh``, ``texture``...), in file order."""
    return [e for section in root.iterfind("asset") for e in section.iterfind(tag)]


def mujoco_mesh_name(mesh: etree._Element) -> str:
    """A mesh's name as MuJoCo gives it: its own, else its file's name without extension."""
    name = mesh.get("name")
    if name:
        return name
    return os.path.splitext(os.path.basename(mesh.get("file", "")))[0]


def robot_body(root: etree._Element) -> etree._Element | None:
    """The ``<worldbody>`` body ManiSkill's loader takes for the robot: the first with a
    joint (or free joint) somewhere below it."""
    worldbody = root.find("worldbody")
    if worldbody is None:
        return None
    for body in worldbody.iterfind("body"):
        if body.find("freejoint") is not None or next(body.iter("joint"), None) is not None:
            return body
    return None


def degrees(root: etree._Element) -> tuple[bool, str]:
    """Whether the model's angles are in degrees, and its euler sequence."""
    compiler = root.find("compiler")
    if compiler is None:
        return True, "xyz"
    return compiler.get("angle", "degree").lower() == "degree", compiler.get("eulerseq", "xyz")
