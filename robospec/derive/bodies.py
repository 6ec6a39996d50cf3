"""Mend class ``bodies: merge`` (RS720, MJCF): bodies without joints merged into their parents.

ManiSkill's MJCF loader gives the k-th body of the robot bit k of collision group 2: from the
31st body on, bit 30 is the ground's in ManiSkill's scenes (those links fall through the floor),
and a 33rd body's bit does not fit SAPIEN's 32-bit groups: the load fails (RS081; dm_control's
dog and rodent). A body without a joint is welded to its parent: MuJoCo simulates the two as one
rigid body. Each such body below the robot's root is merged into its parent, as MuJoCo's
compiler fuses them (``<compiler fusestatic>``): its geoms, sites, cameras and child bodies move
up, posed in the parent's frame as they were (written as ``pos`` and ``quat``), its default
class kept; its ``<inertial>`` is combined with the parent's (parallel axes); references to it by
name (contact exclusions, equality constraints, sensors) name the parent. Every remaining link
keeps its pose; the parent's mass and centre of mass become the two bodies'.
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import childclass, classes, degrees, effective, robot_body, whole
from robospec.description.mjcf_frames import (
    ORIENTATION_ATTRIBUTES,
    Unparsable,
    body_pose,
    mujoco_rotation,
    numbers,
)
from robospec.description.mjcf_mujoco import Table
from robospec.description.mjcf_references import REFERENCES
from robospec.diagnostics.codes import CANNOT_MEND, MENDED_BODIES, MJCF_COLLISION_BITS
from robospec.geometry import (
    IDENTITY,
    IDENTITY_POSE,
    Matrix,
    Pose,
    Vector,
    compose,
    matrix_from_quaternion,
    shifted,
    turned,
)
from robospec.maniskill.scenes import GROUND_BITS

NAME = "bodies"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_BODIES
FIXES = (MJCF_COLLISION_BITS,)
WHY = "too many bodies for ManiSkill's loader's collision bits: those without joints are merged"

POSED = ("geom", "site", "camera", "light", "body", "frame")  # moved up, their pose composed
# what a merged body may hold besides those (and its inertial): anything else keeps it apart
_MOVABLE = frozenset({*POSED, "inertial"})


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    robot = robot_body(root)
    if robot is None:
        return
    document.track_lines()  # elements move up: each keeps the line it was written on
    top = _loaded_root(robot)
    table = classes(root, document.source.path)
    use_degrees, eulerseq = degrees(root)
    kept: set[etree._Element] = set()  # bodies refused: not tried again
    while True:
        body = next(
            (b for b in top.iter("body") if b is not top and b not in kept and _jointless(b)),
            None,
        )
        if body is None:
            return
        parent = body.getparent()
        blocking = sorted({str(c.tag) for c in body if isinstance(c.tag, str)} - _MOVABLE)
        if parent is None or blocking:
            document.refuse(
                body,
                CANNOT_MEND,
                f"mend 'bodies: merge' cannot merge body '{body.get('name', '')}' into its "
                f"parent: it holds {', '.join(f'<{t}>' for t in blocking)}, which robospec "
                "does not move",
                "give it a joint, or merge it by hand in a copy of the model",
            )
            kept.add(body)
            continue
        try:
            pose = body_pose(body.attrib, use_degrees, eulerseq)
            _merge(body, parent, pose, table, use_degrees, eulerseq)
        except Unparsable as bad:
            document.refuse(
                body,
                CANNOT_MEND,
                f"mend 'bodies: merge' cannot read the pose of body '{body.get('name', '')}' "
                f"or of what it holds: {bad}",
                "the model's parse says what is wrong with it",
            )
            kept.add(body)
            continue
        _rename_references(root, body.get("name", ""), parent.get("name", ""))
        document.changed(
            body,
            f"body '{body.get('name', '')}'",
            f"welded to body '{parent.get('name', '')}' without a joint",
            f"merged into '{parent.get('name', '')}'",
        )
        document.remove(body)


def _loaded_root(robot: etree._Element) -> etree._Element:
    """The body the loader makes the robot's first link: a wrapper holding one body and no
    geom or joint is skipped for that body."""
    tags = [c.tag for c in robot if isinstance(c.tag, str)]
    inner = robot.find("body")
    if tags.count("body") == 1 and "geom" not in tags and "joint" not in tags and inner is not None:
        return inner
    return robot


def _jointless(body: etree._Element) -> bool:
    return body.find("joint") is None and body.find("freejoint") is None


def _merge(
    body: etree._Element,
    parent: etree._Element,
    pose: Pose,
    table: dict[str, Table],
    use_degrees: bool,
    eulerseq: str,
) -> None:
    """Move what ``body`` holds into ``parent`` (pose composed, default class kept)."""
    kept_class = childclass(body) if body.get("childclass") is not None else None
    parent_class = childclass(parent)
    for child in [c for c in body if isinstance(c.tag, str)]:
        if child.tag == "inertial":
            _combine_inertial(parent, child, pose, use_degrees, eulerseq)
            continue
        attributes = effective(table, child) if child.tag != "body" else dict(child.attrib)
        if child.tag == "body":
            if kept_class and child.get("childclass") is None and kept_class != parent_class:
                child.set("childclass", kept_class)
        elif kept_class and child.get("class") is None and kept_class != parent_class:
            child.set("class", kept_class)
        _place(child, attributes, pose, use_degrees, eulerseq)
        child.tail = body.tail
        body.addprevious(child)


def _place(
    element: etree._Element,
    attributes: dict[str, str],
    pose: Pose,
    use_degrees: bool,
    eulerseq: str,
) -> None:
    """Write ``element``'s pose in the frame ``pose`` is given in."""
    fromto = attributes.get("fromto")
    if fromto is not None and element.tag == "geom":
        values = numbers(fromto, 6)
        a = compose(pose, ((values[0], values[1], values[2]), IDENTITY))[0]
        b = compose(pose, ((values[3], values[4], values[5]), IDENTITY))[0]
        element.set("fromto", _numbers((*a, *b)))
        return
    position = numbers(attributes.get("pos", "0 0 0"), 3)
    rotation = mujoco_rotation(attributes, use_degrees, eulerseq)
    moved = compose(pose, ((position[0], position[1], position[2]), rotation))
    for name in ORIENTATION_ATTRIBUTES:
        element.attrib.pop(name, None)
    element.set("pos", _numbers(moved[0]))
    element.set("quat", _numbers(moved[1]))


def _combine_inertial(
    parent: etree._Element,
    inertial: etree._Element,
    pose: Pose,
    use_degrees: bool,
    eulerseq: str,
) -> None:
    """The parent's ``<inertial>`` and the merged body's (posed by ``pose``) as one; the
    merged one alone where the parent has none and no geom (nothing MuJoCo would weigh)."""
    moved = _inertia_of(inertial, pose, use_degrees, eulerseq)
    existing = parent.find("inertial")
    if existing is None:
        if parent.find("geom") is not None:
            return  # MuJoCo weighs the parent's geoms; ManiSkill reads no <inertial> at all
        total = moved
    else:
        here = _inertia_of(existing, IDENTITY_POSE, use_degrees, eulerseq)
        total = _sum(here, moved)
        parent.remove(existing)
    mass, com, matrix = total
    written = etree.Element(
        "inertial",
        pos=_numbers(com),
        mass=f"{mass:.12g}",
        fullinertia=_numbers(
            (matrix[0][0], matrix[1][1], matrix[2][2], matrix[0][1], matrix[0][2], matrix[1][2])
        ),
    )
    parent.insert(0, written)
    written.tail = parent.text
    parent.text = " "


def _inertia_of(
    inertial: etree._Element, pose: Pose, use_degrees: bool, eulerseq: str
) -> tuple[float, Vector, Matrix]:
    """(mass, centre of mass, inertia matrix about it) of an ``<inertial>``, in the frame
    ``pose`` is given in."""
    mass = numbers(inertial.get("mass", "0"), 1)[0]
    position = numbers(inertial.get("pos", "0 0 0"), 3)
    if inertial.get("fullinertia") is not None:
        xx, yy, zz, xy, xz, yz = numbers(inertial.get("fullinertia", ""), 6)
        local: Matrix = ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
        rotation = IDENTITY
    else:
        diagonal = numbers(inertial.get("diaginertia", "0 0 0"), 3)
        local = ((diagonal[0], 0.0, 0.0), (0.0, diagonal[1], 0.0), (0.0, 0.0, diagonal[2]))
        rotation = mujoco_rotation(inertial.attrib, use_degrees, eulerseq)
    frame = compose(pose, ((position[0], position[1], position[2]), rotation))
    return mass, frame[0], turned(matrix_from_quaternion(frame[1]), local)


def _sum(
    a: tuple[float, Vector, Matrix],
    b: tuple[float, Vector, Matrix],
) -> tuple[float, Vector, Matrix]:
    """Two rigid bodies' masses, centres and inertias as one (the parallel axis theorem)."""
    mass = a[0] + b[0]
    if mass <= 0:
        return a
    com = tuple((a[0] * a[1][i] + b[0] * b[1][i]) / mass for i in range(3))
    rows = [[0.0] * 3 for _ in range(3)]
    for m, c, inertia in (a, b):
        about = shifted(inertia, m, (c[0] - com[0], c[1] - com[1], c[2] - com[2]))
        for i in range(3):
            for j in range(3):
                rows[i][j] += about[i][j]
    return mass, com, tuple(tuple(r) for r in rows)  # type: ignore[return-value]


def _rename_references(root: etree._Element, old: str, new: str) -> None:
    """Everything that names the merged body names its parent; an exclusion of the two goes."""
    if not old:
        return
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        for attribute in REFERENCES["body"]:
            if element.get(attribute) == old:
                element.set(attribute, new)
        # a sensor's object: the body's inertial frame (body) or its own frame (xbody)
        if element.get("objtype") in ("body", "xbody") and element.get("objname") == old:
            element.set("objname", new)
        if element.tag == "exclude" and element.get("body1") == element.get("body2"):
            parent = element.getparent()
            if parent is not None:
                parent.remove(element)


def _numbers(values: tuple[float, ...] | list[float]) -> str:
    return " ".join(f"{0.0 if abs(v) < 1e-15 else v:.12g}" for v in values)


def body_count(root: etree._Element) -> int:
    """How many bodies ManiSkill's loader makes links of: the robot's, wrapper skipped."""
    robot = robot_body(root)
    if robot is None:
        return 0
    return sum(1 for _ in _loaded_root(robot).iter("body"))


def suggest(document: Document) -> str | None:
    """Only where the loader's bits run out or reach the ground's (31 bodies or more)."""
    if body_count(whole(document.trial())) <= GROUND_BITS[0]:
        return None
    return "merge" if document.would_change(apply, "merge") else None
