"""Mechanisms (robospec.model.mechanisms) bound to the description: each closed loop's links,
its meeting point and the joints of the cycle it closes; the touch sensors' links; the planar
base's joints (which the derived copy added), its controller, its wheels and their joints.

Whether they fit the robot (a loop between two links of one rigid body, a planar base on a
robot the description fixes to the world) is judged by the checks (RS340-RS343).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from robospec.description.facts import RobotDescription
from robospec.geometry import IDENTITY
from robospec.load.source_map import KeyPath
from robospec.model.controller_kinds import FIELD_ORDER
from robospec.model.frozen import Pose
from robospec.resolve.context import ResolveContext
from robospec.resolve.poses import position_and_quaternion
from robospec.resolve.resolved import (
    ResolvedCollisionRule,
    ResolvedController,
    ResolvedLoop,
    ResolvedMobileBase,
    ResolvedMode,
    ResolvedTouch,
)
from robospec.resolve.selection import link, select_links

# ManiSkill's Empty and table-top scenes set this bit of collision group 2 on the ground: a
# link with it set does not touch the floor there (Fetch's wheels)
FLOOR_GROUP, FLOOR_BIT = 2, 30
BASE_MODE = "pd_base_vel"  # the mode of a robot with nothing to drive but its base


def loops(context: ResolveContext) -> tuple[ResolvedLoop, ...]:
    out = []
    for name, loop in context.spec.loops.items():
        path: KeyPath = ("loops", name)
        bound = [link(context, n, (*path, "links", i)) for i, n in enumerate(loop.links)]
        first, second = bound
        if first is None or second is None:
            continue
        poses = tuple(_meeting(at) for at in loop.at)
        joints = cycle_joints(context.description, first, second)
        out.append(ResolvedLoop(name, (first, second), (poses[0], poses[1]), loop.weld, joints))
    return tuple(out)


def _meeting(at: Any) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    if isinstance(at, Pose):
        return position_and_quaternion(at)
    return (float(at[0]), float(at[1]), float(at[2])), IDENTITY


def tree_path(description: RobotDescription, first: str, second: str) -> list[str]:
    """The joints on the tree's path between two links (up from each to where they meet)."""
    parent_joint = {j.child: j for j in description.joints}

    def up(name: str) -> list[str]:
        chain, seen = [name], {name}
        while (joint := parent_joint.get(chain[-1])) is not None and joint.parent not in seen:
            chain.append(joint.parent)
            seen.add(joint.parent)
        return chain

    above_first, above_second = up(first), up(second)
    common = next((n for n in above_first if n in set(above_second)), None)
    if common is None:
        return []
    joints = [parent_joint[n].name for n in above_first[: above_first.index(common)]]
    joints += [parent_joint[n].name for n in above_second[: above_second.index(common)]]
    return joints


def cycle_joints(description: RobotDescription, first: str, second: str) -> tuple[str, ...]:
    """The active joints of the cycle a loop between ``first`` and ``second`` closes, in the
    description's joint order."""
    on_path = set(tree_path(description, first, second))
    return tuple(j for j in description.active_joint_names if j in on_path)


def rigid_bodies(description: RobotDescription) -> dict[str, str]:
    """Each link -> the first link of the rigid body it belongs to (links welded by fixed
    joints move as one)."""
    parent_joint = {j.child: j for j in description.joints}
    out: dict[str, str] = {}
    for name in description.link_names:
        top = name
        while (joint := parent_joint.get(top)) is not None and not joint.is_active:
            top = joint.parent
        out[name] = top
    return out


def loop_joined(
    description: RobotDescription, links: Iterable[tuple[str, str]]
) -> set[frozenset[str]]:
    """The pairs of links closed loops join, given each loop's two ``links``: the two, and
    every link welded to one of them with every link welded to the other (a pad on a finger)."""
    body = rigid_bodies(description)
    members: dict[str, list[str]] = {}
    for name, top in body.items():
        members.setdefault(top, []).append(name)
    pairs: set[frozenset[str]] = set()
    for pair in links:
        first, second = (members.get(body.get(n, n), [n]) for n in pair)
        pairs.update(frozenset((a, b)) for a in first for b in second if a != b)
    return pairs


def touch(context: ResolveContext) -> ResolvedTouch | None:
    section = context.spec.touch
    if section is None:
        return None
    links = [link(context, n, ("touch", "links", i)) for i, n in enumerate(section.links)]
    return ResolvedTouch(tuple(n for n in links if n is not None), section.proprioception)


# -- the planar base --------------------------------------------------------------------------


def mobile_base(context: ResolveContext) -> ResolvedMobileBase | None:
    """The planar base the derived copy of the description has (robospec.derive.planar_base)."""
    section = context.spec.mobile_base
    if section is None:
        return None
    description = context.description
    base = section.link if section.link is not None else _original_root(description, section)
    if section.link is not None:
        link(context, section.link, ("mobile_base", "link"))
    wheels = tuple(select_links(context, section.wheels, ("mobile_base", "wheels")))
    return ResolvedMobileBase(
        base,
        tuple(section.joints),
        section.controller,
        wheels,
        wheel_joints(description, wheels),
    )


def _original_root(description: RobotDescription, section: Any) -> str:
    """The link below the yaw hinge the derived copy added (the description's own root)."""
    yaw = description.joint(section.joints[2])
    return yaw.child if yaw is not None else description.root_link


def wheel_joints(description: RobotDescription, wheels: tuple[str, ...]) -> tuple[str, ...]:
    """The active joints that move only wheels: each joint whose subtree holds wheel links
    alone."""
    children: dict[str, list[str]] = {}
    for joint in description.joints:
        children.setdefault(joint.parent, []).append(joint.child)

    def only_wheels(name: str) -> bool:
        below = children.get(name, [])
        return name in wheels and all(only_wheels(child) for child in below)

    by_child = {j.child: j for j in description.joints}
    return tuple(
        j
        for j in description.active_joint_names
        if (active := description.joint(j)) is not None and only_wheels(active.child)
        if by_child.get(active.child) is active
    )


def base_controller(base: ResolvedMobileBase, section: Any) -> ResolvedController:
    """The ``pd_base_vel`` controller that drives the base's three joints."""
    kwargs = [
        ("joint_names", list(base.joints)),
        ("lower", [float(v) for v in section.lower]),
        ("upper", [float(v) for v in section.upper]),
        ("damping", float(section.damping)),
        ("force_limit", float(section.force_limit)),
    ]
    kwargs.sort(key=lambda item: FIELD_ORDER.index(item[0]))
    return ResolvedController(base.controller, "pd_base_vel", tuple(kwargs))


def with_base_controller(
    modes: tuple[ResolvedMode, ...],
    controllers: tuple[ResolvedController, ...],
    base: ResolvedMobileBase,
) -> tuple[ResolvedMode, ...]:
    """Every control mode with the base's controller, unless it drives the base already; a
    robot with no mode of its own gets one, ``pd_base_vel``."""
    if not modes:
        return (ResolvedMode(BASE_MODE, ((base.controller, base.controller),)),)
    by_name = {c.name: c for c in controllers}
    out = []
    for mode in modes:
        entries = list(mode.groups) if mode.groups is not None else []
        if mode.groups is None and mode.controller is not None:
            controller = by_name.get(mode.controller)
            key = (controller.joints_group if controller is not None else None) or mode.controller
            entries = [(key, mode.controller)]
        driven = {j for _, name in entries if name in by_name for j in by_name[name].joint_names}
        if driven & set(base.joints):
            out.append(mode)
            continue
        entries.append((base.controller, base.controller))
        out.append(ResolvedMode(mode.name, tuple(entries), None, mode.balance_passive_force))
    return tuple(out)


def floor_rule(base: ResolvedMobileBase) -> tuple[ResolvedCollisionRule, ...]:
    """The wheels out of the floor's collisions."""
    if not base.wheels:
        return ()
    return (ResolvedCollisionRule(base.wheels, FLOOR_GROUP, FLOOR_BIT, 1),)
