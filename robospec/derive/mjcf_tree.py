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
from robospec.description.mjcf_mujoco import MAIN_CLASS, Includes, Table, read_classes


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


def childclass(element: etree._Element) -> str:
    """The class ``element`` takes its defaults from: its own ``class``, else the nearest
    ``childclass`` of a body above it (the body's own for a body), else ``main``."""
    own = element.get("class")
    if own is not None:
        return own
    holders = [element] if element.tag == "body" else []
    for holder in (*holders, *element.iterancestors("body")):
        if holder.get("childclass") is not None:
            return str(holder.get("childclass"))
    return MAIN_CLASS


def effective(table: dict[str, Table], element: etree._Element) -> dict[str, str]:
    """``element``'s attributes over the defaults of its class for its tag."""
    defaults = table.get(childclass(element)) or table.get(MAIN_CLASS, {})
    merged = dict(defaults.get(str(element.tag), {}))
    merged.update(element.attrib)
    return merged


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
