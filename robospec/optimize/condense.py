"""Fixed-link merging: the same robot with fewer links (scikit-robot's algorithm, for URDF).

Every link costs a simulator a body, and a body on a fixed joint buys nothing but a frame. So a
fixed joint whose child link is not in ``keep`` (the links something names: a tcp, a camera
mount, a link rule) is removed and its child merged into its parent:

- the child's mass and inertia join the parent's (masses add; inertias combine about the combined
  centre of mass with the parallel-axis theorem, written in the parent's frame);
- the child's ``<visual>`` and ``<collision>`` elements move to the parent, their origins
  composed with the joint's;
- the child's own child joints hang from the parent, their origins composed with the joint's
  (an ``<axis>`` is in its joint's own frame, so it stays as written), and they take the
  removed joint's place in the document: SAPIEN orders links and joints depth-first following
  the order of ``<joint>`` elements, so the active joints keep the order ManiSkill loads them in.

Repeated until no such joint remains. The root link and every link in ``keep`` stay; so does a
fixed joint that a ``<mimic>`` names. Top-level elements that name a removed link or joint
(``<transmission>``, ``<gazebo reference=...>``, a ``<sensor>``'s parent) are dropped;
``<material>`` definitions and everything else stay as written. Numbers are written with
``repr`` (exact round trip), so the output is deterministic and loses no precision.

Plain Python (no numpy): robospec's core does not depend on it, and robospec.geometry's 3×3
matrices do.
"""

from __future__ import annotations

import copy
from collections.abc import Collection, Iterator
from dataclasses import dataclass

from lxml import etree

from robospec.description.inertia import EMPTY_LINK_MASS, INERTIA_ATTRIBUTES
from robospec.geometry import (
    IDENTITY_MATRIX,
    ZERO,
    Matrix,
    Vector,
    apply,
    matmul,
    matrix_from_rpy,
    rpy_from_matrix,
    shifted,
    turned,
)

# The top-level elements a condensed robot needs as they are; anything else that names a
# removed link or joint describes something that is gone.
_STRUCTURE = ("link", "joint", "material")


@dataclass(frozen=True)
class MergedLink:
    """One merge: ``link`` is gone, its body now part of ``into`` (the final survivor after
    repeated merges), joined to it by the fixed joint ``joint``, which is gone too."""

    link: str
    into: str
    joint: str


@dataclass(frozen=True)
class Condensed:
    """A new ``<robot>`` element (the input is not mutated) and the merges, in order."""

    robot: etree._Element
    merged: tuple[MergedLink, ...]


def condense(robot: etree._Element, keep: Collection[str]) -> Condensed:
    """``robot`` with every fixed joint whose child link is not in ``keep`` merged away.

    ``keep`` names links (a fixed joint's name in it keeps that joint and its child too)."""
    robot = copy.deepcopy(robot)
    kept = frozenset(keep) | _mimicked(robot)
    steps: list[tuple[str, str, str]] = []
    while (joint := _next_mergeable(robot, kept)) is not None:
        steps.append(_merge(robot, joint))
    _drop_references(robot, {name for step in steps for name in (step[0], step[2])})
    survivor = {link: parent for link, parent, _ in steps}
    merged = tuple(
        MergedLink(link=link, into=_final(parent, survivor), joint=joint)
        for link, parent, joint in steps
    )
    return Condensed(robot=robot, merged=merged)


def _mimicked(robot: etree._Element) -> frozenset[str]:
    # a mimic of a fixed joint is nonsense, but removing its target would leave it dangling
    return frozenset(
        mimic.get("joint", "") for mimic in robot.iterfind("joint/mimic") if mimic.get("joint")
    )


def _next_mergeable(robot: etree._Element, kept: frozenset[str]) -> etree._Element | None:
    """The first fixed joint, in document order, whose child may go."""
    for joint in robot.iterfind("joint"):
        if joint.get("type") != "fixed" or joint.get("name") in kept:
            continue
        child = _link_of(joint, "child")
        child_link, parent_link = (
            _find_link(robot, child),
            _find_link(robot, _link_of(joint, "parent")),
        )
        if (
            child not in kept
            and child_link is not None
            and parent_link is not None
            and not mass_from_shapes(child_link)
            and not mass_from_shapes(parent_link)
        ):
            return joint
    return None


def mass_from_shapes(link: etree._Element) -> bool:
    """SAPIEN computes this link's mass and inertia from its collision shapes (it has no usable
    ``<inertial>`` but has ``<collision>``s): a number robospec cannot reproduce without
    SAPIEN, and one an ``<inertial>`` written by a merge would replace, so the link stays."""
    return _read_body(link) is None and link.find("collision") is not None


def _final(link: str, survivor: dict[str, str]) -> str:
    while link in survivor:
        link = survivor[link]
    return link


def _merge(robot: etree._Element, joint: etree._Element) -> tuple[str, str, str]:
    """Merge the fixed joint's child into its parent; (child, parent, joint) names."""
    parent_name, child_name = _link_of(joint, "parent"), _link_of(joint, "child")
    parent, child = _find_link(robot, parent_name), _find_link(robot, child_name)
    if parent is None or child is None:
        raise ValueError(f"fixed joint '{joint.get('name')}' names a link that does not exist")
    offset = _read_origin(joint)
    _merge_inertial(parent, child, offset)
    for element in list(child):  # moved out of the child as we go
        if isinstance(element.tag, str) and element.tag in ("visual", "collision"):
            _set_origin(element, _compose(offset, _read_origin(element)))
            _append(parent, element)
    for grandchild in [j for j in robot.iterfind("joint") if _link_of(j, "parent") == child_name]:
        _link_element(grandchild, "parent").set("link", parent_name)
        _set_origin(grandchild, _compose(offset, _read_origin(grandchild)))
        _move_before(grandchild, joint)
    name = joint.get("name", "")
    _remove(joint)
    _remove(child)
    return child_name, parent_name, name


# -- the document


def _find_link(robot: etree._Element, name: str) -> etree._Element | None:
    return next((link for link in robot.iterfind("link") if link.get("name") == name), None)


def _link_element(joint: etree._Element, which: str) -> etree._Element:
    element = joint.find(which)
    if element is None:
        raise ValueError(f"joint '{joint.get('name')}' has no <{which}>")
    return element


def _link_of(joint: etree._Element, which: str) -> str:
    return _link_element(joint, which).get("link", "")


def _remove(element: etree._Element) -> None:
    """Remove ``element``; the whitespace before the next sibling (or the closing tag) stays
    as the document had it."""
    parent = element.getparent()
    assert parent is not None
    previous = element.getprevious()
    if element.getnext() is None:  # last child: its tail indents the parent's closing tag
        if previous is not None:
            previous.tail = element.tail
        else:
            parent.text = element.tail
    parent.remove(element)  # lxml removes the element's tail with it


def _move_before(element: etree._Element, anchor: etree._Element) -> None:
    """Move ``element`` just before ``anchor`` (a sibling), indented as ``anchor`` is."""
    if element.getnext() is anchor:
        return
    _remove(element)
    parent = anchor.getparent()
    assert parent is not None
    _add_child(parent, element, parent.index(anchor))


def _append(link: etree._Element, element: etree._Element) -> None:
    """Move ``element`` to the end of ``link``, indented as the link's children are."""
    if element.getparent() is not None:
        _remove(element)
    _add_child(link, element, len(link))


def _add_child(parent: etree._Element, element: etree._Element, index: int) -> None:
    """Insert ``element`` at ``index`` among ``parent``'s children, indented as they are (one
    level deeper than ``parent`` where it has none)."""
    outer = _indent_before(parent)
    inner = parent.text if len(parent) and _blank(parent.text) else outer + "  "
    if not len(parent):
        parent.text = inner
        element.tail = outer
    elif index >= len(parent):
        element.tail = parent[-1].tail
        parent[-1].tail = inner
    else:
        element.tail = inner
    parent.insert(index, element)


def _indent_before(element: etree._Element) -> str:
    """The whitespace before ``element`` (its line break and indentation)."""
    previous = element.getprevious()
    parent = element.getparent()
    before = previous.tail if previous is not None else parent.text if parent is not None else ""
    return before if before is not None and _blank(before) and "\n" in before else "\n"


def _blank(text: str | None) -> bool:
    return text is not None and text.strip() == ""


def _drop_references(robot: etree._Element, removed: set[str]) -> None:
    """Remove the top-level elements (other than links, joints and materials) that name a
    removed link or joint: a transmission, a gazebo block, a sensor mounted on it."""
    for element in list(robot):
        if not isinstance(element.tag, str) or element.tag in _STRUCTURE:
            continue
        if any(value in removed for value in _references(element)):
            _remove(element)


def _references(element: etree._Element) -> Iterator[str]:
    # an element's own name is not a reference (a transmission may be named like its joint's
    # link); names inside it are (<joint name=...>, <parent link=...>, reference=...)
    for key, value in element.attrib.items():
        if key != "name":
            yield value
    for inner in element.iterdescendants():
        if isinstance(inner.tag, str):
            yield from inner.attrib.values()


# -- frames: an origin is (rotation, translation), x_parent = R x_child + p


def _floats(text: str | None, count: int) -> tuple[float, ...]:
    values = tuple(float(part) for part in (text or "").split())
    if not values:
        return (0.0,) * count
    if len(values) != count:
        raise ValueError(f"expected {count} numbers, got {text!r}")
    return values


def _read_origin(element: etree._Element) -> tuple[Vector, Vector]:
    """(xyz, rpy) of an element's ``<origin>`` (zeros where absent)."""
    origin = element.find("origin")
    if origin is None:
        return ZERO, ZERO
    xyz = _floats(origin.get("xyz"), 3)
    rpy = _floats(origin.get("rpy"), 3)
    return (xyz[0], xyz[1], xyz[2]), (rpy[0], rpy[1], rpy[2])


def _compose(outer: tuple[Vector, Vector], inner: tuple[Vector, Vector]) -> tuple[Vector, Vector]:
    """The origin ``outer ∘ inner``. Where either rotation is none, the other's rpy is kept as
    written (no trip through a matrix, so no rounding)."""
    (p1, rpy1), (p2, rpy2) = outer, inner
    r1 = _rotation(rpy1)
    shifted = _add(p1, apply(r1, p2))
    if rpy2 == ZERO:
        return shifted, rpy1
    if rpy1 == ZERO:
        return shifted, rpy2
    return shifted, rpy_from_matrix(matmul(r1, _rotation(rpy2)))


def _set_origin(element: etree._Element, origin: tuple[Vector, Vector]) -> None:
    xyz, rpy = origin
    found = element.find("origin")
    if found is None:
        found = etree.Element("origin")
        element.insert(0, found)
        found.tail = element.text
    found.set("xyz", _numbers(xyz))
    found.set("rpy", _numbers(rpy))


def _numbers(values: Collection[float]) -> str:
    # repr round-trips exactly; + 0.0 turns -0.0 into 0.0
    return " ".join(repr(value + 0.0) for value in values)


def _rotation(rpy: Vector) -> Matrix:
    """The rotation of an origin's rpy; the identity itself for none, which :func:`_rotated`
    passes by."""
    return IDENTITY_MATRIX if rpy == ZERO else matrix_from_rpy(*rpy)


def _add(a: Vector, b: Vector) -> Vector:
    return a[0] + b[0], a[1] + b[1], a[2] + b[2]


def _scale(s: float, v: Vector) -> Vector:
    return s * v[0], s * v[1], s * v[2]


# -- mass and inertia


@dataclass(frozen=True)
class _Body:
    """A mass, its centre in a link's frame, and its inertia tensor about that centre, in
    the link's axes."""

    mass: float
    centre: Vector
    inertia: Matrix


# SAPIEN's body for a link without a usable <inertial> and without collision shapes (measured
# by tests/test_optimize_condense.py, which loads one): 1e-6 kg at the link's origin and
# 1e-6 kg·m² about each of its axes.
SAPIEN_EMPTY_LINK = _Body(
    EMPTY_LINK_MASS,
    ZERO,
    ((EMPTY_LINK_MASS, 0.0, 0.0), (0.0, EMPTY_LINK_MASS, 0.0), (0.0, 0.0, EMPTY_LINK_MASS)),
)


def _read_body(link: etree._Element) -> _Body | None:
    """The link's body as SAPIEN simulates it from its ``<inertial>``; None when SAPIEN ignores
    that (missing, zero mass or an all-zero tensor) and takes the mass from the link's
    collision shapes instead."""
    inertial = link.find("inertial")
    if inertial is None:
        return None
    mass_element = inertial.find("mass")
    mass = float(mass_element.get("value", "0")) if mass_element is not None else 0.0
    tensor = inertial.find("inertia")
    i = {
        key: float(tensor.get(key, "0")) if tensor is not None else 0.0
        for key in INERTIA_ATTRIBUTES
    }
    matrix: Matrix = (
        (i["ixx"], i["ixy"], i["ixz"]),
        (i["ixy"], i["iyy"], i["iyz"]),
        (i["ixz"], i["iyz"], i["izz"]),
    )
    if mass == 0.0 or all(value == 0.0 for value in i.values()):
        return None
    centre, rpy = _read_origin(inertial)
    return _Body(mass, centre, _rotated(_rotation(rpy), matrix))


def _simulated_body(link: etree._Element) -> _Body:
    """What SAPIEN simulates for a link that may be merged (one whose mass does not come from
    its shapes): its ``<inertial>``, or, with neither a usable one nor collision shapes,
    SAPIEN's stand-in body — not nothing: 1e-6 kg·m² about each axis is ten times a
    fingertip's own inertia (the Inspire hand's empty tip links), which merging must keep."""
    return _read_body(link) or SAPIEN_EMPTY_LINK


def _rotated(r: Matrix, inertia: Matrix) -> Matrix:
    """R I Rᵀ: an inertia tensor expressed in the axes ``r`` maps it into."""
    if r is IDENTITY_MATRIX:
        return inertia
    return turned(r, inertia)


def _moved(body: _Body, origin: tuple[Vector, Vector]) -> _Body:
    """``body`` seen from the frame that ``origin`` places its link in."""
    xyz, rpy = origin
    r = _rotation(rpy)
    return _Body(body.mass, _add(xyz, apply(r, body.centre)), _rotated(r, body.inertia))


def _combined(a: _Body, b: _Body) -> _Body:
    """Two bodies in one frame as one: masses add; each inertia moves to the joint centre of
    mass by the parallel-axis theorem (I + m (|d|² E - d dᵀ))."""
    mass = a.mass + b.mass
    centre = _scale(1.0 / mass, _add(_scale(a.mass, a.centre), _scale(b.mass, b.centre)))
    inertia = _sum(_about(a, centre), _about(b, centre))
    return _Body(mass, centre, inertia)


def _about(body: _Body, point: Vector) -> Matrix:
    d = (body.centre[0] - point[0], body.centre[1] - point[1], body.centre[2] - point[2])
    return shifted(body.inertia, body.mass, d)


def _sum(a: Matrix, b: Matrix) -> Matrix:
    return tuple(tuple(a[i][j] + b[i][j] for j in range(3)) for i in range(3))  # type: ignore[return-value]


def _merge_inertial(
    parent: etree._Element, child: etree._Element, offset: tuple[Vector, Vector]
) -> None:
    """The parent's ``<inertial>`` with the child's body added, each as SAPIEN simulates it
    (:func:`_simulated_body`), so the merged link moves as the two did together."""
    moved = _moved(_simulated_body(child), offset)
    _write_inertial(parent, _combined(_simulated_body(parent), moved))


def _write_inertial(link: etree._Element, body: _Body) -> None:
    """Replace (or add, first in the link) the link's ``<inertial>``, in the link's axes."""
    m = body.inertia
    inertial = etree.Element("inertial")
    etree.SubElement(inertial, "origin", xyz=_numbers(body.centre), rpy="0 0 0")
    etree.SubElement(inertial, "mass", value=repr(body.mass + 0.0))
    etree.SubElement(
        inertial,
        "inertia",
        {
            key: repr(value + 0.0)
            for key, value in zip(
                INERTIA_ATTRIBUTES,
                (m[0][0], m[0][1], m[0][2], m[1][1], m[1][2], m[2][2]),
                strict=True,
            )
        },
    )
    old = link.find("inertial")
    index = link.index(old) if old is not None else 0
    if old is not None:
        _remove(old)
    # indent the new element's children one level below it, as the rest of the file is
    _add_child(link, inertial, index)
    inner = _indent_before(inertial) + "  "
    inertial.text = inner
    for child in inertial[:-1]:
        child.tail = inner
    inertial[-1].tail = _indent_before(inertial)
