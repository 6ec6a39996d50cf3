"""The robot as an editor asks about it: the names a place takes, a joint's or link's facts, a
group's joints and a controller's fields through ``extends``.

Read from the last compilation's description and the document's own data, tolerantly: a spec
with errors (the usual state while typing) still has a description and names.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from robospec.description.facts import Joint, RobotDescription

# the keys of the spec that define names, by the reference kind that names them
DEFINED_IN = {
    "material": "materials",
    "controller": "controllers",
    "control-mode": "control_modes",
    "link-state": "link_states",
    "keyframe": "keyframes",
    "link-or-named": "named_links",
    "joint-selection": "groups",
}


def _keys(data: Any, section: str) -> list[str]:
    if isinstance(data, dict) and isinstance(data.get(section), dict):
        return [str(k) for k in data[section]]
    return []


def names(kind: str, description: RobotDescription | None, data: Any) -> dict[str, str]:
    """The names allowed for a reference ``kind`` (see robospec.model.refs), each with a short
    detail for a completion list."""
    joints = {j.name: joint_detail(j) for j in description.active_joints} if description else {}
    links = {name: "link" for name in description.link_names} if description else {}
    if kind == "joint":
        return joints
    if kind == "joint-selection":
        return {**joints, **{g: "group" for g in _keys(data, "groups")}}
    if kind in ("link", "link-pattern", "mount-link"):
        return links
    if kind == "link-or-named":
        return {**links, **{n: "named link" for n in _keys(data, "named_links")}}
    section = DEFINED_IN.get(kind)
    return {name: kind for name in _keys(data, section)} if section else {}


def part_names(kind: str, origins: Mapping[tuple[Any, ...], Any]) -> dict[str, str]:
    """The names of a reference ``kind`` that came along from the spec's parts (a part's
    controllers, named links, ...), each with what it is."""
    section = DEFINED_IN.get(kind)
    if section is None:
        return {}
    return {
        str(path[1]): f"{kind} from a part's spec"
        for path in origins
        if len(path) == 2 and path[0] == section
    }


def _number(value: float | None) -> str:
    return "∞" if value is None else f"{value:g}"


def joint_detail(joint: Joint) -> str:
    if joint.lower is None and joint.upper is None:
        return f"{joint.type} joint"
    return f"{joint.type} joint [{_number(joint.lower)}, {_number(joint.upper)}]"


@dataclass(frozen=True)
class ElementFacts:
    """What the located facts leave out, read from the XML: a joint's axis, a link's mass."""

    axes: Mapping[str, str]
    masses: Mapping[str, str]


def element_facts(description: RobotDescription, expanded: bool) -> ElementFacts:
    """Axes and masses of ``description`` (none for a xacro's expansion, which is not on disk)."""
    if expanded:
        return ElementFacts({}, {})
    path = Path(description.path)
    try:
        status = path.stat()
    except OSError:
        return ElementFacts({}, {})
    return _element_facts(str(path), description.kind, status.st_mtime_ns, status.st_size)


@lru_cache(maxsize=16)
def _element_facts(path: str, kind: str, _mtime: int, _size: int) -> ElementFacts:
    from lxml import etree

    try:
        root = etree.parse(path, etree.XMLParser(resolve_entities=False, no_network=True)).getroot()
    except (OSError, etree.XMLSyntaxError):
        return ElementFacts({}, {})
    axes: dict[str, str] = {}
    masses: dict[str, str] = {}
    if kind == "urdf":
        for joint in root.iter("joint"):
            axis = joint.find("axis")
            name = joint.get("name")
            if name and joint.getparent() is root:
                # URDF's default axis is x
                axes[name] = axis.get("xyz", "1 0 0") if axis is not None else "1 0 0"
        for link in root.iter("link"):
            mass = link.find("inertial/mass")
            if link.get("name") and mass is not None and mass.get("value"):
                masses[link.get("name", "")] = f"{mass.get('value')} kg"
    else:
        for joint in root.iter("joint"):
            if joint.get("name"):
                axes[joint.get("name", "")] = joint.get("axis", "0 0 1")  # MuJoCo's default
        for body in root.iter("body"):
            inertial = body.find("inertial")
            if body.get("name") and inertial is not None and inertial.get("mass"):
                masses[body.get("name", "")] = f"{inertial.get('mass')} kg (file <inertial>)"
    return ElementFacts(axes, masses)


def parent_chain(description: RobotDescription, link: str) -> list[tuple[str, str]]:
    """(joint, parent link) pairs from ``link`` up to the root."""
    by_child = {j.child: j for j in description.tree_joints}
    chain: list[tuple[str, str]] = []
    seen = {link}
    while link in by_child:
        joint = by_child[link]
        chain.append((joint.name or "(unnamed)", joint.parent))
        link = joint.parent
        if link in seen:  # a cycle is reported elsewhere; do not loop here
            break
        seen.add(link)
    return chain


def group_joints(
    name: str, description: RobotDescription | None, data: Any, stack: tuple[str, ...] = ()
) -> list[str]:
    """The joints a group selects (names, globs, other groups, ``all_but``), as written now."""
    groups = data.get("groups") if isinstance(data, dict) else None
    if not isinstance(groups, dict) or name not in groups or name in stack:
        return []
    return selection_joints(groups[name], description, data, (*stack, name))


def selection_joints(
    selection: Any, description: RobotDescription | None, data: Any, stack: tuple[str, ...] = ()
) -> list[str]:
    active = list(description.active_joint_names) if description else []
    groups = data.get("groups") if isinstance(data, dict) else {}
    if isinstance(selection, dict) and "all_but" in selection:
        left_out = set(selection_joints(selection["all_but"], description, data, stack))
        return [j for j in active if j not in left_out]
    items = selection if isinstance(selection, list) else [selection]
    out: list[str] = []
    for item in items:
        if not isinstance(item, str):
            continue
        if isinstance(groups, dict) and item in groups:
            out.extend(group_joints(item, description, data, stack))
        elif item in active or (description is not None and description.joint(item)):
            out.append(item)
        else:
            out.extend(j for j in active if fnmatch.fnmatchcase(j, item))
    return list(dict.fromkeys(out))


def controller_fields(name: str, data: Any) -> list[tuple[str, Any, str]]:
    """A controller's fields as ``extends`` merges them: (field, value, the controller that
    wrote it), bases first, a field written again by a child overriding it."""
    controllers = data.get("controllers") if isinstance(data, dict) else None
    if not isinstance(controllers, dict):
        return []
    chain: list[str] = []
    current: Any = name
    while isinstance(current, str) and current in controllers and current not in chain:
        chain.append(current)
        body = controllers[current]
        current = body.get("extends") if isinstance(body, dict) else None
    fields: dict[str, tuple[Any, str]] = {}
    for owner in reversed(chain):
        body = controllers[owner]
        if isinstance(body, dict):
            for key, value in body.items():
                if key != "extends":
                    fields[key] = (value, owner)
    return [(key, value, owner) for key, (value, owner) in fields.items()]
