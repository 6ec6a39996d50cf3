"""A stand-in description for a robot whose files ManiSkill has not downloaded yet.

Half of ManiSkill's agents (anymal_c, unitree_h1, xarm6_robotiq, ...) download their URDF on
first use. A spec for one of them must still validate and build on a machine without the
download — in CI, or before ``python -m mani_skill.utils.download_asset``. Then the joints and
links the spec names are taken as they are written: every explicit joint name is assumed to be
an unbounded active joint, every explicit link name a link. Nothing is checked against the
robot (the caller says so with a warning); globs, joints chosen by keyframe name order and
limits need the real file and are reported as such by the resolver.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from robospec.description.facts import Joint, Link, RobotDescription
from robospec.model.frozen import AllBut, Spec
from robospec.model.names import GLOB


def assumed_description(spec: Spec, path: str) -> RobotDescription:
    joints = _unique(n for n in _joint_names(spec) if n not in spec.groups)
    links = _unique(_link_names(spec))
    return RobotDescription(
        kind=spec.description.loaded_kind if spec.description is not None else "urdf",
        path=path,
        links=tuple(Link(name, 0) for name in links),
        joints=tuple(Joint(name, "revolute", "", "", 0) for name in joints),
        active_joint_names=tuple(joints),
        root_link=links[0] if links else "",
        assumed=True,
    )


def _unique(names: Iterator[str]) -> list[str]:
    return list(dict.fromkeys(n for n in names if not GLOB.search(n)))


def _selection_names(selection: Any) -> Iterator[str]:
    if isinstance(selection, AllBut):
        yield from _selection_names(selection.all_but)
    elif isinstance(selection, list):
        for item in selection:
            yield from _selection_names(item)
    elif isinstance(selection, str):
        yield selection


def _joint_names(spec: Spec) -> Iterator[str]:
    for selection in spec.groups.values():
        yield from _selection_names(selection)
    for config in spec.controllers.values():
        yield from _selection_names(getattr(config, "joints", None))
        mimic = getattr(config, "mimic", None) or {}
        for follower, target in mimic.items():
            yield follower
            yield target if isinstance(target, str) else getattr(target, "joint", "")
    yield from _selection_names(spec.passive_joints)


def _link_names(spec: Spec) -> Iterator[str]:
    yield from spec.links
    for config in spec.controllers.values():
        for field in ("ee_link", "root_link_name"):
            value = getattr(config, field, None)
            if isinstance(value, str):
                yield value
    for camera in spec.cameras.values():
        yield camera.mount
    for rule in spec.collision_rules:
        yield from _selection_names(rule.links)
    for entry in spec.never_collide:
        yield from _selection_names(entry)
    tcp = spec.tcp
    if isinstance(tcp, str):
        yield tcp
    elif tcp is not None:
        yield from [tcp.link or "", *(tcp.midpoint or [])]
        if tcp.orientation not in (None, "midpoint"):
            yield tcp.orientation or ""
    for value in spec.named_links.values():
        yield from _selection_names(value)
    for check in spec.grasping.values():
        yield from (finger.link for finger in check.fingers)
    for state in spec.link_states.values():
        yield from _selection_names(state.link)
        if isinstance(state.links, list):
            yield from state.links
    if spec.is_fallen is not None and spec.is_fallen.contact is not None:
        yield from spec.is_fallen.contact.links
    yield from _selection_names(spec.disable_gravity)
    for drive in spec.drives:
        yield from (drive.parent, drive.child)
