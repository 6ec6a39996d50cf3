"""Stage 3: bind a :class:`Spec` to its robot description in one pass.

Every joint, link, group, controller and material name is looked up here, once; what comes out
is a :class:`~robospec.resolve.resolved.ResolvedRobot` in ManiSkill's own terms, the
:class:`~robospec.resolve.resolved.Bindings` the checks judge, and located diagnostics for
names that bind to nothing. One module per part of the spec, each taking the
:class:`~robospec.resolve.context.ResolveContext`.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from robospec.diagnostics import error
from robospec.diagnostics.codes import GROUP_NAMED_AS_JOINT
from robospec.load.source_map import LoadedSpec
from robospec.model.validate import SpecModelResult
from robospec.resolve import carried, mechanisms, members
from robospec.resolve.cameras import resolve_camera
from robospec.resolve.context import ResolveContext
from robospec.resolve.controllers import resolve_controller
from robospec.resolve.description_files import (
    Mount,
    load_inherited_description,
    load_spec_description,
)
from robospec.resolve.keyframes import resolve_keyframe
from robospec.resolve.modes import resolve_modes
from robospec.resolve.never_collide import resolve_never_collide
from robospec.resolve.reset import resolve_reset
from robospec.resolve.resolved import (
    FileRef,
    ResolvedCollisionRule,
    ResolvedNeverCollide,
    ResolvedRobot,
)
from robospec.resolve.selection import group_joints, select_joints, select_links
from robospec.resolve.urdf_config import resolve_urdf_config

if TYPE_CHECKING:
    # parts (robospec.resolve.parts, part_renaming, part_types) are imported for a spec that
    # mounts some, and for no other
    from robospec.resolve.part_types import CarriedPart, PartInput


def resolve(
    loaded: LoadedSpec,
    model: SpecModelResult,
    spec_file: Path,
    parts: Mapping[str, PartInput] | None = None,
) -> ResolveContext:
    """Resolve ``model``'s spec; the context holds the robot (None when its description could
    not be loaded), the bindings and the diagnostics. ``parts``: the spec's parts, each
    compiled on its own (robospec.pipeline), which are mounted on its description."""
    context = ResolveContext(loaded, model, spec_file, parts=dict(parts or {}))
    context.robot = _resolve_robot(context)
    return context


def _resolve_robot(context: ResolveContext) -> ResolvedRobot | None:
    spec = context.spec
    if spec.parts and spec.description is None:
        from robospec.resolve.parts import warn_unsupported

        warn_unsupported(context)  # said before the extended class is imported
        return None
    base_ref, base_class = members.base_class(context)
    if spec.extends is not None and base_ref is None:
        return None
    description_kind: Literal["urdf", "mjcf"]
    if spec.description is not None:
        description_ref = load_spec_description(context, _parts_mount(context))
        description_kind = spec.description.loaded_kind
    else:
        description_ref, description_kind = load_inherited_description(context, base_class)
    if description_ref is None or context.loaded_description is None:
        return None
    description = context.description
    context.carried = _carried_parts(context, description_ref)
    _resolve_groups(context)
    if spec.passive_joints is not None:
        select_joints(context, spec.passive_joints, ("passive_joints",))

    urdf_config = resolve_urdf_config(context)
    keyframes = tuple(resolve_keyframe(context, n, k) for n, k in spec.keyframes.items())
    controllers = tuple(
        resolve_controller(context, name, config, description_ref)
        for name, config in spec.controllers.items()
    )
    modes = tuple(resolve_modes(context))
    base = mechanisms.mobile_base(context)
    if base is not None:
        controllers = (*controllers, mechanisms.base_controller(base, spec.mobile_base))
        modes = mechanisms.with_base_controller(modes, controllers, base)
    cameras = tuple(resolve_camera(context, uid, cam) for uid, cam in spec.cameras.items())
    rules, never_collide = _collision_rules(
        context, description_ref, mechanisms.floor_rule(base) if base is not None else ()
    )
    robot = ResolvedRobot(
        uid=spec.uid,
        class_name=spec.class_name or class_name_for(spec.uid),
        spec_path=context.loaded.path,
        description_kind=description_kind,
        description=description_ref,
        fix_root_link=spec.loader.fix_root_link,
        load_multiple_collisions=spec.loader.load_multiple_collisions,
        disable_self_collisions=spec.loader.disable_self_collisions,
        urdf_config=urdf_config,
        keyframes=keyframes,
        controllers=controllers,
        modes=modes,
        cameras=cameras,
        collision_rules=rules,
        tcp=members.tcp(context),
        active_joints=description.active_joint_names,
        override=spec.override,
        download_ids=tuple(spec.description.download) if spec.description else (),
        base=base_ref,
        declared=declared_sections(context),
        named_links=members.named_links(context),
        grasping=members.grasping(context),
        is_static=members.is_static(context),
        is_standing=members.is_standing(context),
        is_fallen=members.is_fallen(context),
        reset=resolve_reset(context, keyframes),
        link_states=members.link_states(context),
        proprioception=tuple(spec.proprioception),
        disable_gravity=members.disable_gravity(context),
        drives=members.drives(context),
        loops=mechanisms.loops(context),
        armature=members.armature(context),
        touch=mechanisms.touch(context),
        mobile_base=base,
        hooks=members.hooks(context),
        never_collide=never_collide,
        simulation=members.simulation(context),
    )
    return carried.with_parts(context, robot)


def _parts_mount(context: ResolveContext) -> Mount | None:
    """What mounts the spec's parts on its description; None for a spec without parts."""
    if not context.spec.parts:
        return None
    from robospec.resolve.parts import compose_parts

    return compose_parts


def _carried_parts(context: ResolveContext, description: FileRef) -> tuple[CarriedPart, ...]:
    """The mounted parts renamed into the robot's names; none where nothing was mounted."""
    if context.composed is None:
        return ()
    from robospec.resolve.part_renaming import carry_parts

    return carry_parts(context, description)


def _resolve_groups(context: ResolveContext) -> None:
    """Each group expanded once (into ``context.group_joints``)."""
    for name in context.spec.groups:
        if context.description.joint(name) is not None:
            # a selection names a group or a joint by the same word: one of them would be
            # unreachable, and the group would select itself (a false "circular" error)
            context.diagnostics.append(
                error(
                    context.at_key(("groups", name)),
                    GROUP_NAMED_AS_JOINT,
                    f"group '{name}' has the name of a joint",
                    f"rename the group (e.g. '{name}_group')",
                )
            )
            continue
        group_joints(context, name)


def _collision_rules(
    context: ResolveContext,
    description_ref: FileRef,
    mechanism_rules: tuple[ResolvedCollisionRule, ...] = (),
) -> tuple[tuple[ResolvedCollisionRule, ...], ResolvedNeverCollide | None]:
    """The spec's collision rules, its mechanisms' (the wheels off the floor) and the parts',
    then the bits ``never_collide`` (the spec's and the parts') is packed into."""
    rules = tuple(
        ResolvedCollisionRule(
            tuple(select_links(context, rule.links, ("collision_rules", i, "links"))),
            rule.group,
            rule.bit,
            rule.value,
        )
        for i, rule in enumerate(context.spec.collision_rules)
    )
    rules += mechanism_rules + carried.collision_rules(context)
    packed, never_collide = resolve_never_collide(
        context, rules, carried.never_collide_entries(context, description_ref)
    )
    return rules + packed, never_collide


def declared_sections(context: ResolveContext) -> frozenset[str]:
    """What the generated class sets itself; with ``extends`` the rest is inherited."""
    spec = context.spec
    if spec.extends is None:
        return ResolvedRobot.declared
    given = spec.model_fields_set
    sections = {
        "description": "description" in given,
        "loader": "loader" in given,
        "urdf_config": bool(given & {"materials", "links"}),
        "keyframes": "keyframes" in given,
        "controllers": bool(spec.control_modes),
        "cameras": "cameras" in given,
    }
    return frozenset(name for name, declared in sections.items() if declared)


def class_name_for(uid: str) -> str:
    """``rs_panda`` -> ``RsPanda``; always a valid Python identifier."""
    parts = [p for p in re.split(r"[^A-Za-z0-9]+", uid) if p]
    name = "".join(p[:1].upper() + p[1:] for p in parts) or "Agent"
    if name[0].isdigit():
        name = "Agent" + name
    return name


__all__ = ["ResolveContext", "class_name_for", "resolve"]
