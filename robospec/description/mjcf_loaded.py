"""The MJCF robot as ManiSkill's loader builds it, body by body: what the reports of what that
loader drops or reads differently (:mod:`robospec.description.mjcf_gaps`) look at.

:mod:`robospec.description.mjcf` makes these records while it mirrors the loader's parse, so the
reports see exactly the bodies, defaults and geoms the loader does.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from robospec.description.mjcf_mujoco import Includes, Table
from robospec.diagnostics import Location

# ManiSkill's MJCFLoader(ignore_classes=["motor"]): bodies whose childclass, and geoms whose
# class, re.match() one of these are not loaded.
IGNORE_CLASSES: tuple[str, ...] = ("motor",)

# A defaults table as ManiSkill keeps it: tag -> attribute -> value (classes nest no further).
Defaults = dict[str, Any]


def merge(base: Mapping[str, Any], *incoming: Mapping[str, Any]) -> dict[str, Any]:
    """ManiSkill's ``_merge_attrib``: a deep-copied ``base`` updated by each mapping in turn."""

    def merge_into(a: dict[str, Any], b: Mapping[str, Any]) -> None:
        for key, value in b.items():
            if key in a and isinstance(a[key], dict) and isinstance(value, dict):
                merge_into(a[key], value)
            else:
                a[key] = value

    result = _copy(base)
    for mapping in incoming:
        merge_into(result, mapping)
    return result


def _copy(table: Mapping[str, Any]) -> dict[str, Any]:
    """A deep copy of a defaults table (nested dicts of strings: copy.deepcopy's generality made
    validating a 60-body MJCF ten times slower)."""
    return {key: _copy(value) if isinstance(value, dict) else value for key, value in table.items()}


def is_ignored_class(name: str) -> bool:
    return any(re.match(pattern, name) for pattern in IGNORE_CLASSES)


@dataclass(frozen=True)
class LoadedBody:
    """One ``<body>`` of the robot and the links ManiSkill makes of it."""

    element: etree._Element
    link: str  # the link that carries the body's geoms: named after the body
    parent_link: str  # the link above the body's first joint (the parent body's, or the root)
    parent: LoadedBody | None  # None for the robot's first body
    defaults: Defaults  # ManiSkill's active defaults in this body
    joints: tuple[etree._Element, ...]  # its <joint> elements (hinge and slide)
    bit: int  # the bit of collision group 2 the loader gives it and its parent body

    @property
    def name(self) -> str:
        return self.link

    @property
    def moves(self) -> bool:
        return bool(self.joints)


@dataclass(frozen=True)
class LoadedGeom:
    element: etree._Element
    body: LoadedBody
    attributes: dict[str, str]  # as ManiSkill merges them (defaults, class, own)

    @property
    def type(self) -> str:
        """ManiSkill's reading: ``mesh=`` makes any geom a mesh."""
        return "mesh" if "mesh" in self.attributes else self.attributes.get("type", "sphere")

    def int_attribute(self, name: str, default: int) -> int:
        try:
            return int(self.attributes.get(name, default))
        except ValueError:
            return default

    @property
    def collides(self) -> bool:
        """ManiSkill gives a geom a collision shape unless its contype is 0."""
        return self.int_attribute("contype", 1) != 0 and self.type in COLLISION_TYPES


# geom types ManiSkill turns into SAPIEN shapes; "plane" and "ellipsoid" it skips with a log
# line, "hfield" and "sdf" raise NotImplementedError
COLLISION_TYPES = frozenset({"sphere", "capsule", "cylinder", "box", "mesh"})


@dataclass
class LoadedMjcf:
    """Everything the loader reads, as it reads it."""

    path: str
    top: list[etree._Element]  # <mujoco>'s children and those of the files it includes
    classes: dict[str, Defaults]  # ManiSkill's default tables
    degrees: bool
    eulerseq: str
    worldbody: etree._Element
    robot_element: etree._Element  # the <worldbody> child that is the robot
    robot: list[LoadedBody]  # in the loader's order (depth first): body k gets bit k
    root_link: str
    where: Callable[[etree._Element], Location]
    includes: Includes  # MuJoCo's reading of <include>, anywhere
    mujoco_classes: dict[str, Table]
    _geoms: list[LoadedGeom] | None = field(default=None, repr=False)
    _parsed: list[tuple[etree._Element, dict[str, str]]] | None = field(default=None, repr=False)

    def geoms(self) -> list[LoadedGeom]:
        """The robot's geoms the loader builds (not those of an ignored class); merged once,
        since every report reads them."""
        if self._geoms is None:
            self._geoms = []
            for body in self.robot:
                for element in body.element.findall("geom"):
                    attributes = geom_attributes(element, body.defaults, self.classes)
                    if attributes is not None:
                        self._geoms.append(LoadedGeom(element, body, attributes))
        return self._geoms

    def sections(self, tag: str) -> list[etree._Element]:
        """The top-level ``<tag>`` sections MuJoCo reads (includes anywhere)."""
        found = []
        for element in self.top:
            if element.tag == tag:
                found.append(element)
        return found


def geom_attributes(
    geom: etree._Element, defaults: Defaults, classes: Mapping[str, Defaults]
) -> dict[str, str] | None:
    """ManiSkill's ``_build_geom`` merge; None for a geom of an ignored class."""
    geom_defaults = defaults
    geom_class = geom.get("class")
    if geom_class is not None:
        if is_ignored_class(geom_class):
            return None
        if geom_class in classes:
            geom_defaults = merge(defaults, classes[geom_class])
    if "geom" in geom_defaults:
        return merge(geom_defaults["geom"], dict(geom.attrib))
    return dict(geom.attrib)


def parsed_elements(loaded: LoadedMjcf) -> list[tuple[etree._Element, dict[str, str]]]:
    """Every ``<body>`` and ``<geom>`` the loader's parse reads, robot or not, with the
    attributes it reads them with: where it raises, loading the robot fails too, since the
    whole file is parsed before the robot is built. Merged once per model."""
    if loaded._parsed is None:
        loaded._parsed = list(_parsed_elements(loaded))
    return loaded._parsed


def _parsed_elements(loaded: LoadedMjcf) -> Iterator[tuple[etree._Element, dict[str, str]]]:
    return loader_elements(loaded.worldbody, loaded.classes)


def loader_elements(
    worldbody: etree._Element, classes: Mapping[str, Defaults]
) -> Iterator[tuple[etree._Element, dict[str, str]]]:
    """The ``<body>`` and ``<geom>`` elements ManiSkill's parse reads below ``worldbody``, with
    the attributes it reads them with, given its default ``classes`` (:func:`loader_classes`)."""
    root_defaults: Defaults = classes.get("__root__", {})

    def geoms(body: etree._Element, defaults: Defaults) -> Iterator[Any]:
        for geom in body.findall("geom"):
            attributes = geom_attributes(geom, defaults, classes)
            if attributes is not None:
                yield geom, attributes

    for body in worldbody.findall("body"):
        if _articulated(body):
            for member, defaults in articulation_bodies(body, classes):
                yield member, merge(defaults.get("body", {}), dict(member.attrib))
                yield from geoms(member, defaults)
        else:
            # a static or free actor: the loader reads the geoms down the first-child chain
            current: etree._Element | None = body
            while current is not None:
                yield from geoms(current, root_defaults)
                current = current.find("body")
    yield from geoms(worldbody, root_defaults)


def _articulated(body: etree._Element) -> bool:
    """Whether the loader builds a ``<worldbody>`` body as an articulation (a joint below it)."""
    return body.find("freejoint") is not None or next(body.iter("joint"), None) is not None


def articulation_bodies(
    body: etree._Element, classes: Mapping[str, Defaults]
) -> Iterator[tuple[etree._Element, Defaults]]:
    """The bodies ManiSkill's ``_parse_body`` builds of the articulated ``<worldbody>`` body
    ``body``, depth first, each with the defaults active in it (the root table merged with
    each ``childclass`` down the tree); a wrapper holding only one body is skipped, and a
    body of an ignored or unknown childclass is not built, nor anything below it."""
    tags = [child.tag for child in body if isinstance(child.tag, str)]
    if tags.count("body") == 1 and "geom" not in tags and "joint" not in tags:
        body = next(body.iterchildren("body"))  # the one counted

    def walk(member: etree._Element, defaults: Defaults) -> Iterator[tuple[Any, Defaults]]:
        childclass = member.get("childclass")
        if childclass is not None:
            if is_ignored_class(childclass) or childclass not in classes:
                return
            defaults = merge(defaults, classes[childclass])
        yield member, defaults
        for child in member.findall("body"):
            yield from walk(child, defaults)

    yield from walk(body, classes.get("__root__", {}))


def loader_joints(
    robot: etree._Element, classes: Mapping[str, Defaults]
) -> Iterator[tuple[etree._Element, dict[str, str]]]:
    """Every ``<joint>`` ManiSkill's loader builds of the robot (its ``<worldbody>`` body
    ``robot``), with the attributes ``_parse_body`` merges for it: the body's active ``joint``
    defaults, then the joint's own class's, then its own (a class without a joint table, on
    which the loader raises, is left out)."""
    for body, defaults in articulation_bodies(robot, classes):
        for joint in body.findall("joint"):
            incoming: list[Mapping[str, Any]] = []
            if "joint" in defaults:
                incoming.append(defaults["joint"])
            own_class = joint.get("class")
            if own_class is not None:
                table = classes.get(own_class, {}).get("joint")
                if table is None:
                    continue
                incoming.append(table)
            incoming.append(dict(joint.attrib))
            yield joint, merge({}, *incoming)


def loader_classes(
    defaults: Iterable[etree._Element],
) -> tuple[dict[str, Defaults], dict[str, int]]:
    """ManiSkill's ``_parse_default`` of the top-level ``<default>`` elements, quirks included:
    the default tables by class (the unnamed top-level one as ``__root__``; a top-level
    ``class="main"``, MuJoCo's name for that same root, as a class of its own) and the line of
    each class.

    A class starts from a copy of its parent's table only when the parent <default> has a
    class name; classes nested directly in the unnamed top-level <default> start empty (they
    get the root defaults later, merged at each body).
    """
    classes: dict[str, Defaults] = {}
    lines: dict[str, int] = {}

    def read(node: etree._Element, parent: etree._Element | None) -> None:
        class_name = node.get("class", "__root__")
        if parent is not None and parent.get("class") is not None:
            classes[class_name] = _copy(classes.get(str(parent.get("class")), {}))
        else:
            classes[class_name] = {}
        lines[class_name] = node.sourceline if isinstance(node.sourceline, int) else 1
        table = classes[class_name]
        for child in node:
            if not isinstance(child.tag, str):
                continue
            if child.tag == "default":
                read(child, node)
            elif child.tag in table:
                table[child.tag] = merge(table[child.tag], dict(child.attrib))
            else:
                table[child.tag] = dict(child.attrib)

    for default in defaults:
        read(default, None)
    return classes, lines
