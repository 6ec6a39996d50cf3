"""Parts: the robots a spec mounts (``parts:``), composed into its description, and what comes
along from their specs merged into its robot.

Each part's spec is compiled on its own first (by :mod:`robospec.pipeline`: it is a robot of
its own, checked where it is written) and handed here as a :class:`PartInput`; a part given as
a bare description is loaded here, mended as the spec's own would be. :func:`compose_parts`
writes the combined description (:mod:`robospec.compose`); the robot's spec is then resolved
against it, so it may name any link or joint of its parts. What the parts' specs declare comes
along, with its names as the part's description names them in the combined one
(:class:`Plan`, made once the combined description is loaded):

- controllers, and in each of the robot's control modes the controllers of the part's default
  mode (``parts.NAME.mode`` picks another), unless the mode already drives the part's joints;
- keyframes, merged by joint: a keyframe of the robot takes the values of the part's joints
  from the part's keyframe of the same name, else from its first (:func:`keyframe_values`);
- materials and link rules (``urdf_config``), collision rules and ``never_collide`` (packed
  with the robot's into one set of bits), the SRDF pairs SAPIEN would have read beside the
  part's URDF, named links, grasp checks, link states, cameras, drives, gravity;
- the tcp, unless the robot's spec gives one.

Names of the part's spec (controllers, groups, materials, ...) that the robot's spec also
defines get the part's prefix, as clashing link and joint names do; where a merged item is
reported on, the report points into the part's spec (``ResolveContext.origins``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator, Mapping
from typing import TYPE_CHECKING, Any

from robospec.description.facts import RobotDescription
from robospec.diagnostics import error, note, warning
from robospec.load.source_map import KeyPath
from robospec.resolve.context import ResolveContext
from robospec.resolve.part_types import PartInput, Plan
from robospec.resolve.resolved import (
    FileRef,
    ResolvedController,
    ResolvedFinger,
    ResolvedKeyframe,
    ResolvedMode,
    ResolvedPart,
    ResolvedRobot,
    ResolvedTcp,
)

if TYPE_CHECKING:
    from robospec.compose import Mounted, PartSource, Problem

# the codes of this module (robospec/diagnostics/codes.py)
PART_HAS_ERRORS = "RS737"
NOT_CARRIED = "RS738"
UNKNOWN_PART_MODE = "RS739"
NO_DESCRIPTION = "RS740"


# -- composing -------------------------------------------------------------------------------


def compose_parts(context: ResolveContext, ref: FileRef, kind: str, shown: str) -> FileRef | None:
    """The robot's description (``ref``) with every part mounted, as the ref of the combined
    text (and ``context.composed``); None (and the reasons, located) when a part cannot be
    mounted."""
    from robospec.compose import BaseSource, compose

    sources = []
    ready = True
    for name, part in context.spec.parts.items():
        source = _part_source(context, name, part, kind)
        if source is None:
            ready = False
        else:
            sources.append(source)
    data = _text(ref)
    if not ready or data is None:
        return None
    composed = compose(BaseSource(kind, data, str(ref.absolute), shown), sources)  # type: ignore[arg-type]
    for problem in composed.problems:
        _report(context, problem)
    if composed.text is None:
        return None
    if ref.has_srdf_beside:  # its pairs come along as never_collide entries (see make_plan)
        context.base_srdf = str(ref.absolute)
    # written beside the generated module (robospec.output): it names its meshes from there
    combined = dataclasses.replace(
        ref,
        generated_text=composed.text,
        derived=True,
        has_srdf_beside=False,
        parts=tuple(f"part '{m.name}'" for m in composed.parts),
        sources=tuple(dict.fromkeys(_sources(context))),
    )
    context.composed = composed
    return combined


def _sources(context: ResolveContext) -> Iterator[str]:
    """The files the combined description is written from, besides the robot's own: what
    ``register`` must see unchanged to trust its cache."""
    for given in context.parts.values():
        if given.spec_path is not None:
            yield given.spec_path
        ref = given.robot.description if given.robot is not None else given.ref
        if ref is not None:
            yield str(ref.absolute)
            yield from ref.sources


def _report(context: ResolveContext, problem: Problem) -> None:
    where = problem.path
    located = context.at_key(where) if len(where) == 2 else context.at_value(where)
    make = {"note": note, "warning": warning}.get(problem.severity, error)
    context.diagnostics.append(make(located, problem.code, problem.message, problem.hint))


def _text(ref: FileRef) -> bytes | None:
    try:
        return ref.read_bytes()
    except OSError:
        return None  # the description's own load says why


def _part_source(
    context: ResolveContext, name: str, part: Any, base_kind: str
) -> PartSource | None:
    from robospec.compose import NOT_A_FIXED_TREE, PartSource, mixed_formats
    from robospec.resolve.description_files import load_part_description
    from robospec.resolve.poses import position_and_quaternion

    where: KeyPath = ("parts", name)
    given = context.parts.get(name)
    if part.spec is not None:
        if given is None or given.cycle:
            return None  # the pipeline reported the ring of specs
        if given.failed or given.robot is None or given.description is None:
            first = given.errors[0] if given.errors else "it did not compile"
            more = f" (and {len(given.errors) - 1} more)" if len(given.errors) > 1 else ""
            context.err(
                (*where, "spec"),
                PART_HAS_ERRORS,
                f"part '{name}' cannot be mounted: its spec has errors: {first}{more}",
                f"robospec validate {given.spec_shown}",
            )
            return None
        ref = given.robot.description
        description = given.description
        kind = given.robot.description_kind
        if kind != base_kind:
            _report(context, mixed_formats(base_kind, name, kind, "spec"))  # type: ignore[arg-type]
            return None
        if not given.fix_root_link or description.floating_root:
            context.err(
                (*where, "spec"),
                NOT_A_FIXED_TREE,
                f"part '{name}' moves freely (its spec sets loader.fix_root_link: false, or "
                "its root has a free joint): only a robot fixed at its root can be mounted",
                "mount a description of the part without its free root",
            )
            return None
        key = "spec"
    else:
        kind = "mjcf" if part.description.kind == "mjcf" else "urdf"
        if kind != base_kind:  # said before the part is read: its problems would not matter
            _report(context, mixed_formats(base_kind, name, kind, "description"))  # type: ignore[arg-type]
            return None
        loaded = load_part_description(context, part.description, (*where, "description"))
        if loaded is None:
            return None
        ref, description, shown = loaded
        kind = description.kind
        if description.floating_root:
            context.err(
                (*where, "description"),
                NOT_A_FIXED_TREE,
                f"part '{name}' has a free root joint: only a robot fixed at its root can be "
                "mounted",
            )
            return None
        given = PartInput(name, None, description, shown, ref=ref)
        context.parts[name] = given
        key = "description"
    data = _text(ref)
    if data is None:
        return None
    p, q = position_and_quaternion(part.pose)
    rpy = tuple(part.pose.rpy) if part.pose.q is None and part.pose.rpy is not None else None
    entry = context.at_key(where)
    return PartSource(
        name=name,
        kind=kind,
        text=data,
        path=str(ref.absolute),
        shown=given.shown,
        at=part.at,
        position=p,
        quaternion=q,
        rpy=rpy,  # type: ignore[arg-type]
        joint=part.joint_name(name),
        prefix=part.name_prefix(name),
        files={m.uri: m.path for m in description.mesh_files if m.path is not None},
        entry=(entry.file, entry.line),
        entry_path=str(context.spec_file.resolve()),
        key=key,  # type: ignore[arg-type]
        joint_given=part.joint is not None,
        fold_frames=part.fold_frames,
    )


# -- the plan: every merged name, decided once -------------------------------------------------


class _Names:
    """One namespace of the robot's spec (controllers, groups, ...): a part's name that is
    taken gets the part's prefix, and the part's own locator remembers where it was written."""

    def __init__(self, context: ResolveContext, section: str, taken: Iterable[str]) -> None:
        self.context = context
        self.section = section
        self.taken = set(taken)

    def add(self, given: PartInput, prefix: str, name: str, origin: KeyPath | None = None) -> str:
        new = name if name not in self.taken else prefix + name
        while new in self.taken:  # a prefixed name taken too: prefix again (ours, not the user's)
            new = prefix + new
        self.taken.add(new)
        if given.locate is not None:
            self.context.origins[(self.section, new)] = (
                given.locate,
                origin if origin is not None else (self.section, name),
            )
        return new


def make_plan(context: ResolveContext) -> Plan:
    """Decide every name that comes along from the parts, and rename what their specs bound."""
    plan = Plan()
    composed = context.composed
    if composed is None:
        return plan
    spec = context.spec
    description = context.description
    controllers = _Names(context, "controllers", spec.controllers)
    groups = _Names(context, "groups", [*spec.groups, *spec.named_links])
    named = _Names(context, "named_links", spec.named_links)
    grasps = _Names(context, "grasping", spec.grasping)
    states = _Names(context, "link_states", spec.link_states)
    cameras = _Names(context, "cameras", spec.cameras)
    materials = dict(spec.materials)
    by_name = {m.name: m for m in composed.parts}
    if context.base_srdf is not None:
        from robospec.description.srdf import read_srdf_bits

        bits, _ = read_srdf_bits(context.base_srdf, description)  # read with the robot's own
        plan.never_collide.extend(links for _, links in bits)
    mode_keys = {
        key for mode in spec.control_modes.values() if isinstance(mode, dict) for key in mode
    }
    for name, part in spec.parts.items():
        mounted = by_name.get(name)
        given = context.parts.get(name)
        if mounted is None or given is None:
            continue
        plan.parts.append(_resolved_part(name, part, mounted, given))
        active = given.description.active_joint_names if given.description else ()
        plan.joints[name] = frozenset(mounted.new_name("joint", j) for j in active)
        if given.description is not None and given.description.kind == "urdf":
            for _, links in given.description.loader_collision_bits:
                plan.never_collide.append(tuple(mounted.new_name("link", n) for n in links))
        robot = given.robot
        if robot is None:
            continue
        prefix = part.name_prefix(name)
        rename = _Renamer(mounted, robot.description, context, description)
        for what in given.carried_not:
            context.warn(
                ("parts", name, "spec"),
                NOT_CARRIED,
                f"part '{name}': its spec's {what} do not come along",
                "declare what the robot needs in this spec",
            )
        plan.passive_joints.extend(rename.joint(j) for j in given.passive_joints)
        # controllers, their groups first (the emitter names joint lists after them)
        group_names: dict[str, str] = {}
        controller_names: dict[str, str] = {}
        for controller in robot.controllers:
            new = controllers.add(given, prefix, controller.name)
            controller_names[controller.name] = new
            group = controller.joints_group
            if group is not None and group not in group_names:
                group_names[group] = groups.add(given, prefix, group)
            plan.controllers.append(
                ResolvedController(
                    new,
                    controller.type,
                    tuple((k, rename.kwarg(k, v)) for k, v in controller.kwargs),
                    joints_group=group_names.get(group) if group is not None else None,
                )
            )
        plan.modes[name] = _part_mode(
            context, name, part, robot, controller_names, mode_keys, prefix
        )
        mode_keys.update(key for key, _ in plan.modes[name])
        # task-facing members
        attributes: dict[str, str] = {}
        for attribute, value in robot.named_links:
            attributes[attribute] = named.add(given, prefix, attribute)
            links = rename.link(value) if isinstance(value, str) else tuple(map(rename.link, value))
            plan.named_links.append((attributes[attribute], links))
        member = rename.member(attributes)
        for check in robot.grasping:
            fingers = tuple(ResolvedFinger(member(f.link), f.axis, f.sign) for f in check.fingers)
            plan.grasping.append(
                dataclasses.replace(
                    check,
                    method=grasps.add(given, prefix, check.method),
                    fingers=fingers,  # type: ignore[arg-type]
                )
            )
        state_names: dict[str, str] = {}
        for state in robot.link_states:
            state_names[state.name] = states.add(given, prefix, state.name)
            links_value = (
                member(state.links)
                if isinstance(state.links, str)
                else tuple(map(member, state.links))
            )
            plan.link_states.append(
                dataclasses.replace(state, name=state_names[state.name], links=links_value)
            )
        plan.proprioception.extend(state_names.get(n, n) for n in robot.proprioception)
        for camera in robot.cameras:
            plan.cameras.append(
                dataclasses.replace(
                    camera,
                    uid=cameras.add(given, prefix, camera.uid),
                    mount=rename.link(camera.mount),
                )
            )
        plan.drives.extend(
            dataclasses.replace(d, parent=rename.link(d.parent), child=rename.link(d.child))
            for d in robot.drives
        )
        plan.disable_gravity.extend(rename.link(n) for n in robot.disable_gravity)
        packed = len(robot.never_collide.bits) if robot.never_collide is not None else 0
        own = robot.collision_rules[: len(robot.collision_rules) - packed]
        plan.collision_rules.extend(
            dataclasses.replace(r, links=tuple(map(rename.link, r.links))) for r in own
        )
        if robot.never_collide is not None:
            for index, links in enumerate(robot.never_collide.entries):
                context.origins.setdefault(
                    ("never_collide", len(spec.never_collide) + len(plan.never_collide)),
                    (given.locate, ("never_collide", index)),  # type: ignore[arg-type]
                )
                plan.never_collide.append(tuple(map(rename.link, links)))
        _merge_urdf_config(plan, robot.urdf_config, materials, rename, prefix)
        if plan.tcp is None and robot.tcp is not None:
            tcp = robot.tcp
            plan.tcp = ResolvedTcp(
                member(tcp.link) if tcp.link else None,
                (member(tcp.midpoint[0]), member(tcp.midpoint[1])) if tcp.midpoint else None,
                member(tcp.orientation)
                if tcp.orientation not in (None, "midpoint")
                else tcp.orientation,
            )
            if given.locate is not None:
                context.origins[("tcp",)] = (given.locate, ("tcp",))
    return plan


class _Renamer:
    """A part's link and joint names as the combined description has them."""

    def __init__(
        self,
        mounted: Mounted,
        part_ref: FileRef,
        context: ResolveContext,
        combined: RobotDescription,
    ) -> None:
        self.mounted = mounted
        self.part_ref = part_ref
        self.context = context
        self.combined = combined

    def link(self, name: str) -> str:
        return self.mounted.new_name("link", name)

    def joint(self, name: str) -> str:
        return self.mounted.new_name("joint", name)

    def member(self, attributes: Mapping[str, str]) -> Any:
        """A finger's or tcp's link: a named_links attribute (renamed) or a link (renamed)."""

        def rename(name: str) -> str:
            return attributes[name] if name in attributes else self.link(name)

        return rename

    def kwarg(self, key: str, value: Any) -> Any:
        if key == "joint_names":
            return [self.joint(j) for j in value]
        if key in ("ee_link", "root_link_name") and isinstance(value, str):
            return self.link(value)
        if key == "urdf_path" and value == self.part_ref:
            # the IK chain runs in the combined description, where the part's links are
            return self.context.robot_description_ref
        if key == "mimic" and isinstance(value, dict):
            return {
                self.joint(follower): {**target, "joint": self.joint(target["joint"])}
                for follower, target in value.items()
            }
        return value


def _part_mode(
    context: ResolveContext,
    name: str,
    part: Any,
    robot: ResolvedRobot,
    controller_names: Mapping[str, str],
    taken_keys: set[str],
    prefix: str,
) -> tuple[tuple[str, str], ...]:
    """The (key, controller) entries part ``name``'s chosen mode adds to the robot's modes."""
    if not robot.modes:
        return ()
    chosen = robot.modes[0]
    if part.mode is not None:
        found = next((m for m in robot.modes if m.name == part.mode), None)
        if found is None:
            from robospec.diagnostics.suggest import did_you_mean

            context.err(
                ("parts", name, "mode"),
                UNKNOWN_PART_MODE,
                f"part '{name}' has no control mode '{part.mode}'",
                did_you_mean(part.mode, [m.name for m in robot.modes])
                or "its modes: " + ", ".join(m.name for m in robot.modes),
            )
        else:
            chosen = found
    if chosen.groups is None:
        entries = [(name, chosen.controller or "")]
    else:
        entries = list(chosen.groups)
    out = []
    for key, controller in entries:
        new_key = key if key not in taken_keys else prefix + key
        out.append((new_key, controller_names.get(controller, controller)))
    return tuple(out)


def _merge_urdf_config(
    plan: Plan,
    config: Mapping[str, Any],
    materials: dict[str, Any],
    rename: _Renamer,
    prefix: str,
) -> None:
    """The part's materials (shared where the robot's spec has the same one by the same name,
    else prefixed) and its link rules, by the links' new names."""
    renamed: dict[str, str] = {}
    for name, values in config.get("_materials", {}).items():
        existing = materials.get(name)
        if existing is None:
            new = name
        elif _material_values(existing) == values:
            renamed[name] = name
            continue
        else:
            new = prefix + name
            while new in materials:
                new = prefix + new
        renamed[name] = new
        materials[new] = values
        plan.materials[new] = dict(values)
    for link, rule in config.get("link", {}).items():
        rule = dict(rule)
        if "material" in rule:
            rule["material"] = renamed.get(rule["material"], rule["material"])
        plan.link_rules[rename.link(link)] = rule


def _material_values(material: Any) -> dict[str, Any]:
    return material if isinstance(material, dict) else material.model_dump()


def _resolved_part(name: str, part: Any, mounted: Mounted, given: PartInput) -> ResolvedPart:
    from robospec.resolve.poses import position_and_quaternion

    p, q = position_and_quaternion(part.pose)
    return ResolvedPart(
        name=name,
        source=part.spec if part.spec is not None else part.description.path,
        kind="spec" if part.spec is not None else "description",
        at=part.at,
        joint=mounted.joint,
        root=mounted.root,
        p=p,
        q=q,
        links=mounted.links,
        joints=mounted.joints,
        renamed=mounted.renamed,
        description=given.shown,
        folded=mounted.folded,
    )


# -- while the robot resolves ----------------------------------------------------------------


def part_controller(context: ResolveContext, name: str) -> bool:
    """Whether a control mode of the robot may name ``name``: a controller from a part."""
    plan = context.part_plan
    return plan is not None and any(c.name == name for c in plan.controllers)


def part_named_link(context: ResolveContext, name: str) -> bool:
    plan = context.part_plan
    return plan is not None and any(attribute == name for attribute, _ in plan.named_links)


def keyframe_values(context: ResolveContext, keyframe: str, field_name: str) -> dict[str, float]:
    """The part joints' values for the robot's keyframe ``keyframe``: each part's keyframe of
    that name, else its first; velocities the part does not give are 0."""
    out: dict[str, float] = {}
    composed = context.composed
    if composed is None:
        return out
    for mounted in composed.parts:
        given = context.parts.get(mounted.name)
        if given is None or given.description is None:
            continue
        active = given.description.active_joint_names
        robot = given.robot
        frames = robot.keyframes if robot is not None else ()
        frame = next((k for k in frames if k.name == keyframe), frames[0] if frames else None)
        values = getattr(frame, field_name) if frame is not None else None
        if values is None and field_name == "qvel":
            values = (0.0,) * len(active)
        if values is None or len(values) != len(active):
            continue
        for joint, value in zip(active, values, strict=True):
            out[mounted.new_name("joint", joint)] = value
    return out


def filled_joints(context: ResolveContext) -> frozenset[str]:
    """The active joints whose keyframe positions the parts give (RS303 does not miss them)."""
    composed = context.composed
    if composed is None:
        return frozenset()
    out: set[str] = set()
    for mounted in composed.parts:
        given = context.parts.get(mounted.name)
        if given is None or given.robot is None or not given.robot.keyframes:
            continue
        if given.description is not None:
            out.update(mounted.new_name("joint", j) for j in given.description.active_joint_names)
    return frozenset(out)


# -- merging into the robot ------------------------------------------------------------------


def merge(context: ResolveContext, robot: ResolvedRobot) -> ResolvedRobot:
    """``robot`` (the spec's own, resolved against the combined description) with everything
    the plan brings along."""
    plan = context.part_plan
    if plan is None or context.composed is None:
        return robot
    controllers = {c.name: c for c in (*robot.controllers, *plan.controllers)}
    modes = tuple(_merged_mode(mode, plan, controllers) for mode in robot.modes)
    keyframes = _part_only_keyframes(context, robot)
    urdf_config = dict(robot.urdf_config)
    if plan.materials:
        urdf_config["_materials"] = {**plan.materials, **urdf_config.get("_materials", {})}
    if plan.link_rules:
        order = {name: i for i, name in enumerate(context.description.link_names)}
        links = {**plan.link_rules}
        for link, rule in urdf_config.get("link", {}).items():
            links[link] = {**links.get(link, {}), **rule}  # the robot's spec has the last word
        urdf_config["link"] = {n: links[n] for n in sorted(links, key=lambda n: order.get(n, 0))}
    return dataclasses.replace(
        robot,
        controllers=(*robot.controllers, *plan.controllers),
        modes=modes,
        keyframes=(*robot.keyframes, *keyframes),
        urdf_config=urdf_config,
        cameras=(*robot.cameras, *plan.cameras),
        tcp=robot.tcp if robot.tcp is not None else plan.tcp,
        named_links=(*robot.named_links, *plan.named_links),
        grasping=(*robot.grasping, *plan.grasping),
        link_states=(*robot.link_states, *plan.link_states),
        proprioception=(*robot.proprioception, *plan.proprioception),
        disable_gravity=tuple(dict.fromkeys((*robot.disable_gravity, *plan.disable_gravity))),
        drives=(*robot.drives, *plan.drives),
        parts=tuple(plan.parts),
    )


def _merged_mode(
    mode: ResolvedMode, plan: Plan, controllers: Mapping[str, ResolvedController]
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
    for part, joints in plan.joints.items():
        if driven & joints or not plan.modes.get(part):
            continue
        entries.extend(plan.modes[part])
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
    out: list[ResolvedKeyframe] = []
    extra: list[str] = []
    for given in context.parts.values():
        if given.robot is not None:
            extra.extend(k.name for k in given.robot.keyframes if k.name not in names)
    for name in dict.fromkeys(extra):
        values = keyframe_values(context, name, "qpos")
        speeds = keyframe_values(context, name, "qvel")
        qpos = tuple(values.get(j, v) for j, v in zip(active, first.qpos, strict=True))
        base_qvel = first.qvel if first.qvel is not None else (0.0,) * len(active)
        qvel = tuple(speeds.get(j, v) for j, v in zip(active, base_qvel, strict=True))
        out.append(ResolvedKeyframe(name, first.p, first.q, qpos, qvel))
    return out


def warn_unsupported(context: ResolveContext) -> None:
    """A robot whose description comes from an extended class cannot mount parts."""
    if context.spec.parts and context.spec.description is None:
        context.diagnostics.append(
            error(
                context.at_key(("parts",)),
                NO_DESCRIPTION,
                "parts are mounted on the spec's own description, and this spec takes its "
                "robot from the extended class",
                "give `description:` (the class's URDF or MJCF)",
            )
        )


__all__ = [
    "PartInput",
    "Plan",
    "compose_parts",
    "filled_joints",
    "keyframe_values",
    "make_plan",
    "merge",
]
