"""What the robot takes from its parts, each renamed into its names
(:mod:`robospec.resolve.part_renaming`): looked up while the robot's own spec resolves (a mode
may name a part's controller, a member a part's named link; a keyframe takes the part joints'
values), then concatenated with the robot's own (:func:`with_parts`):

- controllers, and in each of the robot's control modes the controllers of the part's chosen
  mode, unless the mode already drives the part's joints;
- keyframes, merged by joint: a keyframe of the robot takes the values of the part's joints
  from the part's keyframe of the same name, else from its first (:func:`keyframe_values`);
  a keyframe only a part has comes along with the robot's joints as its first keyframe has them;
- materials and link rules (``urdf_config``), collision rules and ``never_collide`` (packed
  with the robot's into one set of bits), the SRDF pairs SAPIEN would have read beside the
  robot's and each part's URDF, named links, grasp checks, link states, cameras, drives,
  closed loops, gravity;
- the tcp, unless the robot's spec gives one.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from robospec.resolve.context import ResolveContext
from robospec.resolve.resolved import (
    FileRef,
    ResolvedCollisionRule,
    ResolvedController,
    ResolvedKeyframe,
    ResolvedMode,
    ResolvedRobot,
    ResolvedTcp,
)

if TYPE_CHECKING:
    from robospec.resolve.part_types import CarriedPart

# the sections of a part's robot that come along as they are, after the robot's own
CONCATENATED = (
    "controllers",
    "cameras",
    "named_links",
    "grasping",
    "link_states",
    "proprioception",
    "drives",
    "loops",
    "armature",
)


def _robots(context: ResolveContext) -> list[ResolvedRobot]:
    return [part.robot for part in context.carried if part.robot is not None]


# -- while the robot resolves ----------------------------------------------------------------


def part_controllers(context: ResolveContext) -> list[str]:
    """The controllers the parts bring, by their names here: a control mode may name them."""
    return [c.name for robot in _robots(context) for c in robot.controllers]


def part_named_link(context: ResolveContext, name: str) -> bool:
    return any(attribute == name for r in _robots(context) for attribute, _ in r.named_links)


def keyframe_values(context: ResolveContext, keyframe: str, field_name: str) -> dict[str, float]:
    """The part joints' values for the robot's keyframe ``keyframe``: each part's keyframe of
    that name, else its first; velocities the part does not give are 0."""
    out: dict[str, float] = {}
    for part in context.carried:
        frames = part.robot.keyframes if part.robot is not None else ()
        frame = next((k for k in frames if k.name == keyframe), frames[0] if frames else None)
        values = getattr(frame, field_name) if frame is not None else None
        if values is None and field_name == "qvel":
            values = (0.0,) * len(part.joints)
        if values is None or len(values) != len(part.joints):
            continue
        out.update(zip(part.joints, values, strict=True))
    return out


def filled_joints(context: ResolveContext) -> frozenset[str]:
    """The active joints whose keyframe positions the parts give (RS303 does not miss them)."""
    return frozenset(
        joint
        for part in context.carried
        if part.robot is not None and part.robot.keyframes
        for joint in part.joints
    )


def passive_joints(context: ResolveContext) -> frozenset[str]:
    """The joints the parts' specs leave undriven on purpose."""
    return frozenset(joint for part in context.carried for joint in part.passive_joints)


def collision_rules(context: ResolveContext) -> tuple[ResolvedCollisionRule, ...]:
    """The parts' own collision rules (what their never_collide packed is packed again here)."""
    return tuple(rule for robot in _robots(context) for rule in robot.own_collision_rules)


def never_collide_entries(context: ResolveContext, ref: FileRef) -> tuple[tuple[str, ...], ...]:
    """The link sets the parts keep apart, after the spec's own entries: the pairs of the SRDF
    SAPIEN would have read beside the robot's URDF (``ref``'s file; none beside a xacro's
    expansion) and beside each part's, and each part's ``never_collide``."""
    entries: list[tuple[str, ...]] = []
    spec = context.spec
    if (
        context.composed is not None
        and spec.description is not None
        and spec.description.kind != "xacro"
    ):
        from robospec.description.srdf import read_srdf_bits

        bits, _ = read_srdf_bits(str(ref.absolute), context.description)
        entries.extend(links for _, links in bits)
    for part in context.carried:
        entries.extend(part.loader_pairs)
        robot = part.robot
        if robot is None or robot.never_collide is None:
            continue
        for index, links in enumerate(robot.never_collide.entries):
            if part.locate is not None:
                at = ("never_collide", len(spec.never_collide) + len(entries))
                context.origins.setdefault(at, (part.locate, ("never_collide", index)))
            entries.append(links)
    return tuple(entries)


# -- concatenated with the robot -------------------------------------------------------------


def with_parts(context: ResolveContext, robot: ResolvedRobot) -> ResolvedRobot:
    """``robot`` (the spec's own, resolved against the combined description) and what its
    parts bring, concatenated."""
    if context.composed is None:
        return robot
    robots = _robots(context)
    sections: dict[str, Any] = {
        name: (*getattr(robot, name), *(item for r in robots for item in getattr(r, name)))
        for name in CONCATENATED
    }
    controllers = {c.name: c for c in sections["controllers"]}
    return dataclasses.replace(
        robot,
        **sections,
        modes=tuple(_merged_mode(mode, context.carried, controllers) for mode in robot.modes),
        keyframes=(*robot.keyframes, *_part_only_keyframes(context, robot)),
        urdf_config=_merged_urdf_config(context, robot.urdf_config, robots),
        tcp=robot.tcp if robot.tcp is not None else _part_tcp(context),
        disable_gravity=tuple(
            dict.fromkeys((*robot.disable_gravity, *(n for r in robots for n in r.disable_gravity)))
        ),
        parts=tuple(part.part for part in context.carried),
    )


def _part_tcp(context: ResolveContext) -> ResolvedTcp | None:
    """The first part's tcp, for a robot whose spec gives none; reported on in its spec."""
    for part in context.carried:
        if part.robot is not None and part.robot.tcp is not None:
            if part.locate is not None:
                context.origins[("tcp",)] = (part.locate, ("tcp",))
            return part.robot.tcp
    return None


def _merged_mode(
    mode: ResolvedMode,
    carried: tuple[CarriedPart, ...],
    controllers: Mapping[str, ResolvedController],
) -> ResolvedMode:
    """``mode`` with the controllers of each part whose joints it does not drive yet."""
    entries = list(mode.groups) if mode.groups is not None else []
    if mode.groups is None and mode.controller is not None:
        controller = controllers.get(mode.controller)
        key = (controller.joints_group if controller is not None else None) or mode.controller
        entries = [(key, mode.controller)]
    driven = {
        joint
        for _, name in entries
        if name in controllers
        for joint in controllers[name].joint_names
    }
    added = False
    for part in carried:
        if driven & set(part.joints) or not part.mode:
            continue
        entries.extend(part.mode)
        added = True
    if not added:
        return mode
    return ResolvedMode(mode.name, tuple(entries), None, mode.balance_passive_force)


def _part_only_keyframes(context: ResolveContext, robot: ResolvedRobot) -> list[ResolvedKeyframe]:
    """Keyframes only a part has: the robot's joints as its first keyframe has them."""
    if not robot.keyframes:
        return []
    first = robot.keyframes[0]
    if first.qpos is None:
        return []
    names = {k.name for k in robot.keyframes}
    active = context.description.active_joint_names
    extra = [k.name for r in _robots(context) for k in r.keyframes if k.name not in names]
    out: list[ResolvedKeyframe] = []
    for name in dict.fromkeys(extra):
        values = keyframe_values(context, name, "qpos")
        speeds = keyframe_values(context, name, "qvel")
        qpos = tuple(values.get(j, v) for j, v in zip(active, first.qpos, strict=True))
        base_qvel = first.qvel if first.qvel is not None else (0.0,) * len(active)
        qvel = tuple(speeds.get(j, v) for j, v in zip(active, base_qvel, strict=True))
        out.append(ResolvedKeyframe(name, first.p, first.q, qpos, qvel))
    return out


def _merged_urdf_config(
    context: ResolveContext, config: Mapping[str, Any], robots: list[ResolvedRobot]
) -> dict[str, Any]:
    """The robot's ``urdf_config`` with the parts' materials (before its own; one shared with
    the robot or an earlier part once) and link rules (the robot's spec has the last word on a
    link), in the combined description's link order."""
    merged = dict(config)
    own = config.get("_materials", {})
    materials: dict[str, Any] = {}
    link_rules: dict[str, dict[str, Any]] = {}
    for r in robots:
        for name, values in r.urdf_config.get("_materials", {}).items():
            if name not in own and name not in materials:
                materials[name] = values
        link_rules.update(r.urdf_config.get("link", {}))
    if materials:
        merged["_materials"] = {**materials, **own}
    if link_rules:
        order = {name: i for i, name in enumerate(context.description.link_names)}
        for link, rule in config.get("link", {}).items():
            link_rules[link] = {**link_rules.get(link, {}), **rule}
        merged["link"] = {
            n: link_rules[n] for n in sorted(link_rules, key=lambda n: order.get(n, 0))
        }
    return merged
