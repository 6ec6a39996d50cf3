"""An MJCF's bodies as written — their joints' and geoms' attributes, defaults merged, and
their ``<inertial>`` — for what ``robospec new`` takes from it that MuJoCo's compiled model
does not give (where the links are, MuJoCo itself says: :mod:`.mjcf_poses`):

* the masses ManiSkill's loader gives the links, which it computes from each geom's shape,
  size and ``density`` or ``mass`` as written (it ignores ``<inertial>``): MuJoCo's compiled
  model keeps its own masses (from ``<inertial>``, or its own integration of the geoms) and
  neither the densities nor the geoms' given masses;
* the joints' own ``damping``, ``armature`` and ``actuatorfrcrange`` as the actuators' gains
  read them (:mod:`robospec.authoring.new.gains`), by name.

MuJoCo's rules for defaults and ``<include>`` (:mod:`robospec.description.mjcf_mujoco`): an
element takes its ``class``, else the ``childclass`` of the nearest body above it, else the
top-level class.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from lxml import etree

from robospec.description.mjcf_frames import Unparsable, mujoco_rotation
from robospec.description.mjcf_mujoco import MAIN_CLASS, Includes, Table, attributes, read_classes
from robospec.description.urdf import parse_xml, read_file_bytes
from robospec.geometry import IDENTITY, Quaternion


@dataclass(frozen=True)
class MjJoint:
    name: str
    type: str  # hinge, slide, ball or free
    attributes: dict[str, str]  # defaults merged in


@dataclass(frozen=True)
class MjBody:
    name: str
    joints: tuple[MjJoint, ...]
    geoms: tuple[dict[str, str], ...]  # each geom's attributes, defaults merged in
    inertial: dict[str, str] | None  # the <inertial> element's attributes
    children: tuple[MjBody, ...]


@dataclass(frozen=True)
class MjcfModel:
    degrees: bool  # <compiler angle>
    eulerseq: str
    bodies: tuple[MjBody, ...]  # the bodies of <worldbody>

    def joints(self) -> Iterator[tuple[MjJoint, MjBody]]:
        """Every joint of the model in MuJoCo's qpos order."""
        for body in self.walk():
            for joint in body.joints:
                yield joint, body

    def walk(self) -> Iterator[MjBody]:
        """Every body, parents first, in the file's order."""

        def below(body: MjBody) -> Iterator[MjBody]:
            yield body
            for child in body.children:
                yield from below(child)

        for body in self.bodies:
            yield from below(body)

    def rotation(self, frame: dict[str, str]) -> Quaternion:
        """A geom's or an inertial's orientation as MuJoCo reads it (identity where it cannot
        be read: the description's own checks say why)."""
        try:
            return mujoco_rotation(frame, self.degrees, self.eulerseq)
        except Unparsable:
            return IDENTITY


def read_mjcf_model(text: bytes | str, path: str) -> MjcfModel | None:
    """The model, or None when the XML cannot be read (the facts already said why)."""
    root, _ = parse_xml(text, path)
    if root is None:
        return None
    includes = Includes(path, read_file_bytes, {})
    top = list(includes.children(root))
    compiler = next((el for el in top if el.tag == "compiler"), None)
    degrees = compiler is None or compiler.get("angle", "degree").lower() == "degree"
    eulerseq = compiler.get("eulerseq", "xyz") if compiler is not None else "xyz"
    classes = read_classes(top, includes)
    bodies = tuple(
        _read_body(body, MAIN_CLASS, classes, includes)
        for worldbody in top
        if worldbody.tag == "worldbody"
        for body in includes.find_all(worldbody, "body")
    )
    return MjcfModel(degrees, eulerseq, bodies)


def _read_body(
    element: etree._Element, childclass: str, classes: dict[str, Table], includes: Includes
) -> MjBody:
    childclass = element.get("childclass", childclass)
    joints, geoms, children = [], [], []
    inertial = None
    for child in includes.children(element):
        if child.tag == "freejoint":
            joints.append(MjJoint(child.get("name", ""), "free", dict(child.attrib)))
        elif child.tag == "joint":
            merged = attributes(classes, child, childclass)
            joints.append(MjJoint(merged.get("name", ""), merged.get("type", "hinge"), merged))
        elif child.tag == "geom":
            geoms.append(attributes(classes, child, childclass))
        elif child.tag == "inertial":
            inertial = dict(child.attrib)
        elif child.tag == "body":
            children.append(_read_body(child, childclass, classes, includes))
    return MjBody(element.get("name", ""), tuple(joints), tuple(geoms), inertial, tuple(children))
