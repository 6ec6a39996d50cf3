"""An MJCF model read the way MuJoCo reads it, for what ``robospec new`` takes from it that the
robot's facts leave out: the body frames and joint axes (which way a leg points, which way a
base joint slides) and the joints' own attributes (``damping``, ``actuatorfrcrange``).

MuJoCo's rules, not ManiSkill's: defaults inherit down nested ``<default>`` classes; an
element takes its ``class``, else the ``childclass`` of the nearest body above it, else the
top-level class. ``<include>`` is read where it stands at the top level (as the facts do).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from dataclasses import dataclass, field

from lxml import etree

from robospec.description.numbers import finite_numbers
from robospec.description.urdf import parse_xml, read_file_bytes
from robospec.kinematics.frames import (
    IDENTITY_ROTATION,
    Matrix,
    Transform,
    Vector,
    about_axis,
    from_axes,
    from_euler,
    from_quaternion,
    from_z_axis,
)

MAIN_CLASS = "main"


@dataclass(frozen=True)
class MjJoint:
    name: str
    type: str  # hinge, slide, ball or free
    attributes: dict[str, str]  # defaults merged in
    line: int


@dataclass
class MjBody:
    name: str
    pose: Transform  # relative to the parent body
    joints: list[MjJoint]
    children: list[MjBody]
    childclass: str
    element: etree._Element = field(repr=False)


@dataclass
class MjcfModel:
    path: str
    use_degrees: bool
    eulerseq: str
    classes: dict[str, dict[str, dict[str, str]]]  # class -> tag -> attribute -> value
    bodies: list[MjBody]  # the bodies of <worldbody>

    def joints(self) -> Iterator[tuple[MjJoint, MjBody]]:
        """Every joint of the model in MuJoCo's qpos order."""

        def walk(body: MjBody) -> Iterator[tuple[MjJoint, MjBody]]:
            for joint in body.joints:
                yield joint, body
            for child in body.children:
                yield from walk(child)

        for body in self.bodies:
            yield from walk(body)

    def angle(self, value: float) -> float:
        return math.radians(value) if self.use_degrees else value


def read_mjcf_model(text: bytes | str, path: str) -> MjcfModel | None:
    """The model, or None when the XML cannot be read (the facts already said why)."""
    root, _ = parse_xml(text, path)
    if root is None:
        return None
    top = [child for child in root if isinstance(child.tag, str)]
    for include in root.findall("include"):
        try:
            data = read_file_bytes(os.path.join(os.path.dirname(path), include.get("file", "")))
        except OSError:
            continue
        included, _ = parse_xml(data, path)
        if included is not None:
            top.extend(child for child in included if isinstance(child.tag, str))
    compiler = next((el for el in top if el.tag == "compiler"), None)
    use_degrees = compiler is None or compiler.get("angle", "degree").lower() == "degree"
    eulerseq = compiler.get("eulerseq", "xyz") if compiler is not None else "xyz"
    classes: dict[str, dict[str, dict[str, str]]] = {MAIN_CLASS: {}}
    for default in (el for el in top if el.tag == "default"):
        _read_default(default, {}, classes)
    model = MjcfModel(path, use_degrees, eulerseq, classes, [])
    for worldbody in (el for el in top if el.tag == "worldbody"):
        model.bodies.extend(_read_body(b, MAIN_CLASS, model) for b in worldbody.findall("body"))
    return model


def _read_default(
    node: etree._Element, inherited: dict[str, dict[str, str]], classes: dict
) -> None:
    name = node.get("class", MAIN_CLASS)
    table = {tag: dict(values) for tag, values in inherited.items()}
    for child in node:
        if isinstance(child.tag, str) and child.tag != "default":
            table.setdefault(child.tag, {}).update(child.attrib)
    classes[name] = table
    for child in node.findall("default"):
        _read_default(child, table, classes)


def attributes_of(
    model: MjcfModel, element: etree._Element, tag: str, childclass: str
) -> dict[str, str]:
    """``element``'s attributes over its class's defaults for ``tag``."""
    name = element.get("class", childclass)
    merged = dict(model.classes.get(name, model.classes[MAIN_CLASS]).get(tag, {}))
    merged.update(element.attrib)
    return merged


def _read_body(element: etree._Element, childclass: str, model: MjcfModel) -> MjBody:
    childclass = element.get("childclass", childclass)
    joints = []
    for child in element:
        if child.tag == "freejoint":
            joints.append(MjJoint(child.get("name", ""), "free", dict(child.attrib), _line(child)))
        elif child.tag == "joint":
            attributes = attributes_of(model, child, "joint", childclass)
            kind = attributes.get("type", "hinge")
            joints.append(MjJoint(attributes.get("name", ""), kind, attributes, _line(child)))
    return MjBody(
        name=element.get("name", ""),
        pose=Transform(orientation(model, element.attrib), vector(element.get("pos"), 3)),
        joints=joints,
        children=[_read_body(b, childclass, model) for b in element.findall("body")],
        childclass=childclass,
        element=element,
    )


def orientation(model: MjcfModel, attributes: dict[str, str]) -> Matrix:
    """A frame's rotation from whichever of MuJoCo's orientation attributes it has."""
    if "quat" in attributes:
        w, x, y, z = finite_numbers(attributes["quat"], 4) or (1.0, 0.0, 0.0, 0.0)
        return from_quaternion(w, x, y, z)
    if "axisangle" in attributes:
        values = finite_numbers(attributes["axisangle"], 4)
        if values:
            return about_axis(values[:3], model.angle(values[3]))  # type: ignore[arg-type]
    if "euler" in attributes:
        values = finite_numbers(attributes["euler"], 3)
        if values:
            angles = tuple(model.angle(v) for v in values)
            return from_euler(angles, model.eulerseq)  # type: ignore[arg-type]
    if "xyaxes" in attributes:
        values = finite_numbers(attributes["xyaxes"], 6)
        if values:
            return from_axes(values[:3], values[3:])  # type: ignore[arg-type]
    if "zaxis" in attributes:
        values = finite_numbers(attributes["zaxis"], 3)
        if values:
            return from_z_axis(values)  # type: ignore[arg-type]
    return IDENTITY_ROTATION


def vector(text: str | None, count: int = 3) -> Vector:
    values = finite_numbers(text, count)
    return values if values is not None else (0.0, 0.0, 0.0)  # type: ignore[return-value]


def _line(element: etree._Element) -> int:
    line = element.sourceline
    return line if isinstance(line, int) and line > 0 else 1
