"""The planar base a spec's ``mobile_base`` asks for (RS780): three joints added above the
base link in the derived copy, as ManiSkill's guide builds a mobile base ("fake" base joints)
and ManiSkill's Fetch description has them.

Wheels rolling on a floor simulate slowly and transfer badly, so the base is driven directly:
a slide along x, a slide along y and a hinge about z, from a fixed root, each link between
them without mass (Fetch's ``root``, ``root_arm_1_link_1`` and ``root_arm_1_link_2``).

- URDF: the chain goes above the base link (default: the root, or the link a root moves by its
  only joint when that joint is ``planar`` or ``floating``). A base link that is the root gets
  a new root; one that hangs from its parent by a ``planar``, ``floating`` or ``fixed`` joint
  has that joint replaced by the chain (SAPIEN loads neither a planar nor a floating joint as
  one). A base link under a joint that moves is refused.
- MJCF: the three joints become the first joints of the base body (ManiSkill's loader chains
  several joints of one body through links of its own); a free joint there is replaced.

The section's ``height`` lifts the chain (the x slide's origin; an MJCF base body's ``pos``):
ManiSkill's scenes load a fixed-root robot at the origin, and a base link that sits above its
wheels must ride that high.

Wheels (the section's link patterns) leave the floor's collisions at run time (the agent sets
their collision bit); here, their ball joints, which ManiSkill loads in neither format, are
welded, and with ``wheel_joints: fixed`` every joint that moves only wheels is (in an MJCF,
with what names the joints welded away: a wheel's actuator, its sensors, an equality or a
fixed tendon through it, which MuJoCo would refuse the copy for). This is a
transformation the spec asks for in its own section, not a ``description.mend``: it is applied
after the mends that make the file loadable and before those that read joint types
(``spherical``, ``mimic``).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping, Sequence
from typing import Any, Literal

from lxml import etree

from robospec.derive.document import Document, insert_after
from robospec.derive.mjcf_tree import classes, effective, robot_body, whole
from robospec.description.mjcf_references import REFERENCES
from robospec.diagnostics.codes import DERIVED_PLANAR_BASE, PLANAR_BASE_REFUSED

NAME = "planar_base"
KINDS = frozenset({"urdf", "mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = DERIVED_PLANAR_BASE
FIXES: tuple[str, ...] = ()
WHY = "a drivable planar base: x and y slides and a z hinge above the base link"

# joints a base link may hang from, which the chain replaces
_REPLACED = frozenset({"planar", "floating", "fixed"})
_BALL = frozenset({"spherical", "ball", "floating"})
_TRAVEL = "100"  # metres each slide may travel: far beyond any scene
ADDED_ROOT = "base_root"  # the root a base link that was the root gets (URDF)


def apply(document: Document, policy: Mapping[str, Any]) -> None:
    if document.source.kind == "mjcf":
        _apply_mjcf(document, policy)
    else:
        _apply_urdf(document, policy)


def suggest(document: Document) -> None:
    """Never suggested as a mend: ``robospec new`` writes the ``mobile_base`` section."""
    return None


# -- URDF ------------------------------------------------------------------------------------


def _apply_urdf(document: Document, policy: Mapping[str, Any]) -> None:
    root = document.tree
    links = {e.get("name"): e for e in root.iterfind("link")}
    joints = list(root.iterfind("joint"))
    parent_of = {_link(j, "child"): j for j in joints}
    base = policy.get("link") or _default_base(_root(links, parent_of), joints)
    if base is None or base not in links:
        return  # an unknown base link: the spec's key says so (RS202)
    x_name, y_name, yaw_name = policy["joints"]
    height = float(policy.get("height") or 0.0)  # the slides lie this high above the floor
    taken = {e.get("name") for e in root if isinstance(e.tag, str)}
    x_link, y_link = (_unique(_link_name(n), taken) for n in (x_name, y_name))
    hanging = parent_of.get(base)
    if hanging is not None and hanging.get("type") not in _REPLACED:
        document.refuse(
            hanging,
            PLANAR_BASE_REFUSED,
            f"a planar base cannot be added above link '{base}': it hangs from joint "
            f"'{hanging.get('name')}', which moves ({hanging.get('type')})",
            "name the robot's base link in mobile_base.link (the root, or a link fixed to it)",
        )
        return
    if hanging is None:  # the base is the root: a new root holds the chain
        top = _unique(ADDED_ROOT, taken)
        anchor = links[base]
        added = [_massless(top), _massless(x_link)]
        first = _joint(x_name, "prismatic", top, x_link, "1 0 0")
        if height:
            first.insert(0, etree.Element("origin", xyz=f"0 0 {height:g}"))
        added.append(first)
        subject, before = f"link '{base}'", "the root"
    else:  # the joint it hangs from becomes the x slide, where it stood
        top = _link(hanging, "parent")
        anchor = hanging
        before = f"joint '{hanging.get('name')}' ({hanging.get('type')})"
        subject = f"link '{base}'"
        first = _joint(x_name, "prismatic", top, x_link, "1 0 0")
        origin = hanging.find("origin")
        if origin is not None or height:
            attributes = dict(origin.attrib) if origin is not None else {}
            xyz = [float(v) for v in attributes.get("xyz", "0 0 0").split()]
            if height and len(xyz) == 3:
                attributes["xyz"] = f"{xyz[0]:g} {xyz[1]:g} {xyz[2] + height:g}"
            first.insert(0, etree.Element("origin", attributes))
        added = [first, _massless(x_link)]
    added += [
        _joint(y_name, "prismatic", x_link, y_link, "0 1 0"),
        _massless(y_link),
        _joint(yaw_name, "continuous", y_link, base, "0 0 1"),
    ]
    insert_after(anchor, added)
    if hanging is not None:
        document.remove(hanging)
    document.changed(
        anchor if hanging is None else first,
        subject,
        before,
        f"driven by {x_name} (x), {y_name} (y) and {yaw_name} (yaw) from '{top}'",
    )
    _weld_wheels(document, [j for j in joints if j is not hanging], policy)


def _weld_wheels(
    document: Document, joints: Sequence[etree._Element], policy: Mapping[str, Any]
) -> None:
    patterns = policy.get("wheels") or []
    wheels = {name for j in joints if (name := _link(j, "child")) and _matches(patterns, name)}
    children: dict[str, list[str]] = {}
    for joint in joints:
        children.setdefault(_link(joint, "parent"), []).append(_link(joint, "child"))

    def only_wheels(name: str) -> bool:
        return name in wheels and all(only_wheels(c) for c in children.get(name, []))

    for joint in joints:
        kind = joint.get("type", "")
        child = _link(joint, "child")
        if child not in wheels or kind == "fixed":
            continue
        if kind in _BALL or (policy.get("wheel_joints") == "fixed" and only_wheels(child)):
            joint.set("type", "fixed")
            document.changed(joint, f"joint '{joint.get('name')}'", f'type="{kind}"', "fixed")


def _root(links: Mapping[str | None, Any], parent_of: Mapping[str, Any]) -> str | None:
    return next((n for n in links if n is not None and n not in parent_of), None)


def _default_base(root: str | None, joints: Sequence[etree._Element]) -> str | None:
    """The base link when the spec names none: the link the root moves by its one
    ``planar`` or ``floating`` joint (a ``world`` link above the robot: the chain replaces
    that joint), else the root."""
    below = [j for j in joints if _link(j, "parent") == root]
    moving = [j for j in below if j.get("type") in ("planar", "floating")]
    return _link(moving[0], "child") if len(moving) == 1 and len(below) == 1 else root


def _link(joint: etree._Element, which: str) -> str:
    element = joint.find(which)
    return element.get("link", "") if element is not None else ""


def _link_name(joint: str) -> str:
    return (joint.removesuffix("_joint") or joint) + "_link"


def _massless(name: str) -> etree._Element:
    """A link of the chain: no mass, no shape (Fetch's root links)."""
    link = etree.Element("link", name=name)
    inertial = etree.SubElement(link, "inertial")
    etree.SubElement(inertial, "mass", value="0")
    etree.SubElement(inertial, "inertia", ixx="0", ixy="0", ixz="0", iyy="0", iyz="0", izz="0")
    return link


def _joint(name: str, kind: str, parent: str, child: str, axis: str) -> etree._Element:
    joint = etree.Element("joint", name=name, type=kind)
    etree.SubElement(joint, "parent", link=parent)
    etree.SubElement(joint, "child", link=child)
    etree.SubElement(joint, "axis", xyz=axis)
    if kind == "prismatic":
        etree.SubElement(
            joint, "limit", lower=f"-{_TRAVEL}", upper=_TRAVEL, effort="1e6", velocity="100"
        )
    return joint


def _unique(name: str, taken: set[str | None]) -> str:
    candidate, n = name, 1
    while candidate in taken:
        n += 1
        candidate = f"{name}{n}"
    taken.add(candidate)
    return candidate


def _matches(patterns: Any, name: str) -> bool:
    items = patterns if isinstance(patterns, list) else [patterns]
    return any(fnmatch.fnmatchcase(name, str(p)) for p in items)


# -- MJCF ------------------------------------------------------------------------------------


def _apply_mjcf(document: Document, policy: Mapping[str, Any]) -> None:
    root = whole(document)
    worldbody = root.find("worldbody")
    # a platform with no joint at all is its first body
    robot = robot_body(root)
    if robot is None and worldbody is not None:
        robot = worldbody.find("body")
    if robot is None:
        return
    wanted = policy.get("link")
    body = (
        robot
        if not wanted
        else next((b for b in robot.iter("body") if b.get("name") == wanted), None)
    )
    if body is None:
        return  # an unknown base body: the spec's key says so (RS202)
    if body is not robot:
        document.refuse(
            body,
            PLANAR_BASE_REFUSED,
            f"a planar base cannot be added above body '{wanted}': only the robot's top body "
            f"('{robot.get('name', '')}') may carry it",
            "leave mobile_base.link out, or name the robot's top body",
        )
        return
    x_name, y_name, yaw_name = policy["joints"]
    free = [
        j
        for j in body
        if isinstance(j.tag, str)
        and (j.tag == "freejoint" or (j.tag == "joint" and j.get("type") == "free"))
    ]
    added = [
        etree.Element(
            "joint", name=x_name, type="slide", axis="1 0 0", range=f"-{_TRAVEL} {_TRAVEL}"
        ),
        etree.Element(
            "joint", name=y_name, type="slide", axis="0 1 0", range=f"-{_TRAVEL} {_TRAVEL}"
        ),
        etree.Element("joint", name=yaw_name, type="hinge", axis="0 0 1", limited="false"),
    ]
    for element in added:
        element.tail = " "
    added[-1].tail = body.text
    body.text = " "
    for index, element in enumerate(added):
        body.insert(index, element)
    height = float(policy.get("height") or 0.0)
    if height:
        pos = [float(v) for v in (body.get("pos") or "0 0 0").split()]
        if len(pos) == 3:
            body.set("pos", f"{pos[0]:g} {pos[1]:g} {pos[2] + height:g}")
    before = "its free joint" if free else "fixed to the world"
    for joint in free:
        document.remove(joint)
    document.changed(
        body,
        f"body '{body.get('name', '')}'",
        before,
        f"driven by {x_name} (x), {y_name} (y) and {yaw_name} (yaw)",
    )
    patterns = policy.get("wheels") or []
    table = classes(root, document.source.path)
    removed: set[str] = set()
    for wheel in robot.iter("body"):
        if not _matches(patterns, wheel.get("name", "")):
            continue
        for joint in list(wheel):
            if not isinstance(joint.tag, str) or joint.tag not in ("joint", "freejoint"):
                continue
            kind = effective(table, joint).get("type", "hinge")
            if kind == "ball" or (policy.get("wheel_joints") == "fixed" and kind == "hinge"):
                document.changed(
                    joint, f"joint '{joint.get('name', '')}'", f'type="{kind}"', "removed (fixed)"
                )
                document.remove(joint)
                removed.add(joint.get("name", ""))
    _drop_references(document, root, removed - {""})


# the sections whose elements name joints: an actuator's or a sensor's target, an equality's
# two joints, a fixed tendon's members
_SECTIONS = ("actuator", "sensor", "equality", "tendon")


def _drop_references(document: Document, root: etree._Element, removed: set[str]) -> None:
    """Take out what names a joint the base welded (a wheel's velocity actuator, its sensors,
    an equality or a fixed tendon through it): MuJoCo refuses a model that names a joint it
    does not have."""
    if not removed:
        return
    for section in (s for tag in _SECTIONS for s in root.iter(tag)):
        for element in list(section.iter()):
            if element is section or not isinstance(element.tag, str):
                continue
            named = [element.get(a) for a in REFERENCES["joint"] if element.get(a) in removed]
            if not named:
                continue
            # a tendon's member: the whole tendon goes (MuJoCo needs its every joint)
            gone = (
                element.getparent()
                if element.tag == "joint" and section.tag == "tendon"
                else element
            )
            if gone is None or gone.getparent() is None or not isinstance(gone.tag, str):
                continue
            what = gone.get("name") or gone.tag
            document.changed(
                gone, f"{gone.tag} '{what}'", f"on joint '{named[0]}'", "removed with it"
            )
            document.remove(gone)
