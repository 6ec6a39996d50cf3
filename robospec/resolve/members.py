"""The task-facing members of an agent — tcp, is_grasping, is_static, ... — and the Python a
spec names (``extends``, hooks), bound to the description.

These are the members tasks call, rather than what ManiSkill's ``BaseAgent`` reads. Every link
and joint name is bound here, once; whether the members fit together (a list where one link is
needed, a member defined twice) is judged by the checks (RS316, RS317).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from robospec.diagnostics.codes import NOT_DOWNLOADED, UNKNOWN_LINK, UNUSABLE_PYTHON_REFERENCE
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath
from robospec.model.frozen import HeightBand
from robospec.resolve.carried import part_named_link
from robospec.resolve.context import ResolveContext
from robospec.resolve.keyframes import NEEDS_DOWNLOAD
from robospec.resolve.poses import position_and_quaternion
from robospec.resolve.resolved import (
    PythonRef,
    ResolvedDrive,
    ResolvedFallen,
    ResolvedFinger,
    ResolvedGrasping,
    ResolvedHeight,
    ResolvedHooks,
    ResolvedLinkState,
    ResolvedSimulation,
    ResolvedStanding,
    ResolvedStatic,
    ResolvedTcp,
)
from robospec.resolve.selection import link, select_joints, select_links

if TYPE_CHECKING:
    # imported where a spec names Python (extends, hooks): most specs name none
    from robospec.resolve.python_refs import RefKind

AXES = {"x": 0, "y": 1, "z": 2}


def link_or_named(context: ResolveContext, name: str, path: KeyPath) -> str:
    """A link name, or a ``named_links`` attribute (one link or a list: RS316 tells which fits)."""
    if name in context.spec.named_links or part_named_link(context, name):
        return name
    if context.description.link(name) is None:
        candidates = [*context.description.link_names, *context.spec.named_links]
        context.err(path, UNKNOWN_LINK, f"unknown link '{name}'", did_you_mean(name, candidates))
    else:
        context.bindings.link_names.append((path, name))
    return name


def named_links(context: ResolveContext) -> tuple[tuple[str, str | tuple[str, ...]], ...]:
    out: list[tuple[str, str | tuple[str, ...]]] = []
    for attribute, value in context.spec.named_links.items():
        path: KeyPath = ("named_links", attribute)
        if isinstance(value, str):
            link(context, value, path)
            out.append((attribute, value))
        else:
            for index, name in enumerate(value):
                link(context, name, (*path, index))
            out.append((attribute, tuple(value)))
    return tuple(out)


def tcp(context: ResolveContext) -> ResolvedTcp | None:
    tcp = context.spec.tcp
    if tcp is None:
        return None
    if isinstance(tcp, str):
        return ResolvedTcp(link_or_named(context, tcp, ("tcp",)))
    tcp_link = link_or_named(context, tcp.link, ("tcp", "link")) if tcp.link else None
    midpoint = None
    if tcp.midpoint is not None:
        first, second = (
            link_or_named(context, n, ("tcp", "midpoint", i)) for i, n in enumerate(tcp.midpoint)
        )
        midpoint = (first, second)
    orientation = tcp.orientation
    if orientation is not None and orientation != "midpoint":
        link_or_named(context, orientation, ("tcp", "orientation"))
    return ResolvedTcp(tcp_link, midpoint, orientation)


def grasping(context: ResolveContext) -> tuple[ResolvedGrasping, ...]:
    out = []
    for method, check in context.spec.grasping.items():
        fingers = []
        for index, finger in enumerate(check.fingers):
            path: KeyPath = ("grasping", method, "fingers", index, "link")
            name = link_or_named(context, finger.link, path)
            sign = -1 if finger.opening.startswith("-") else 1
            fingers.append(ResolvedFinger(name, AXES[finger.opening[1]], sign))
        out.append(
            ResolvedGrasping(method, (fingers[0], fingers[1]), check.min_force, check.max_angle)
        )
    return tuple(out)


def _qvel_columns(context: ResolveContext, selection: Any, path: KeyPath) -> tuple[int, ...]:
    order = {name: i for i, name in enumerate(context.description.active_joint_names)}
    return tuple(order[j] for j in select_joints(context, selection, path) if j in order)


def is_static(context: ResolveContext) -> ResolvedStatic | None:
    rule = context.spec.is_static
    if rule is None:
        return None
    if context.assumed:  # qvel columns follow the description's joint order
        context.err(("is_static",), NOT_DOWNLOADED, *NEEDS_DOWNLOAD)
        return None
    columns = _qvel_columns(context, rule.joints, ("is_static", "joints"))
    base = None
    if rule.base is not None:
        base = _qvel_columns(context, rule.base.joints, ("is_static", "base", "joints"))
    return ResolvedStatic(
        columns,
        rule.threshold,
        base,
        rule.base.threshold if rule.base is not None else None,
        rule.absolute,
    )


def is_standing(context: ResolveContext) -> ResolvedStanding | None:
    rule = context.spec.is_standing
    if rule is None:
        return None
    return ResolvedStanding(_height(rule.height), rule.upright_within)


def is_fallen(context: ResolveContext) -> ResolvedFallen | None:
    rule = context.spec.is_fallen
    if rule is None:
        return None
    if rule.height is not None:
        return ResolvedFallen(_height(rule.height))
    assert rule.contact is not None
    links = tuple(
        link(context, n, ("is_fallen", "contact", "links", i)) or n
        for i, n in enumerate(rule.contact.links)
    )
    return ResolvedFallen(None, links, rule.contact.force_above)


def link_states(context: ResolveContext) -> tuple[ResolvedLinkState, ...]:
    out = []
    for name, state in context.spec.link_states.items():
        path: KeyPath = ("link_states", name)
        links: tuple[str, ...] | str
        if state.link is not None:
            links, single = (link_or_named(context, state.link, (*path, "link")),), True
        elif isinstance(state.links, str):
            links, single = state.links, False  # a named_links attribute holding a list
        else:
            single = False
            links = tuple(
                link_or_named(context, n, (*path, "links", i))
                for i, n in enumerate(state.links or [])
            )
        out.append(
            ResolvedLinkState(name, links, single, state.quantity, state.stack_dim, state.method)
        )
    return tuple(out)


def simulation(context: ResolveContext) -> ResolvedSimulation:
    section = context.spec.simulation
    offset = section.contact_offset
    return ResolvedSimulation(
        profile=section.profile,
        category=section.category,
        contact_offset=float(offset) if offset is not None else None,
        solver_position_iterations=section.solver_position_iterations,
        solver_velocity_iterations=section.solver_velocity_iterations,
    )


def armature(context: ResolveContext) -> tuple[tuple[str, float], ...]:
    """Each joint's armature, in qpos order: the description's (an MJCF compiled by MuJoCo),
    then the spec's ``simulation.armature``, each entry over what comes before it."""
    values = dict(context.description.armature)
    for pattern, value in context.spec.simulation.armature.items():
        for joint in select_joints(context, pattern, ("simulation", "armature", pattern)):
            values[joint] = float(value)
    order = context.description.active_joint_names
    return tuple((joint, values[joint]) for joint in order if values.get(joint))


def disable_gravity(context: ResolveContext) -> tuple[str, ...]:
    if context.spec.disable_gravity is None:
        return ()
    return tuple(select_links(context, context.spec.disable_gravity, ("disable_gravity",)))


def drives(context: ResolveContext) -> tuple[ResolvedDrive, ...]:
    out = []
    for index, drive in enumerate(context.spec.drives):
        path: KeyPath = ("drives", index)
        link(context, drive.parent, (*path, "parent"))
        link(context, drive.child, (*path, "child"))
        limits = tuple(
            (axis, bounds[0], bounds[1])
            for axis in ("x", "y", "z")
            if (bounds := getattr(drive.limit, axis)) is not None
        )
        out.append(
            ResolvedDrive(
                drive.parent,
                position_and_quaternion(drive.parent_pose),
                drive.child,
                position_and_quaternion(drive.child_pose),
                limits,
            )
        )
    return tuple(out)


# -- python ----------------------------------------------------------------------------------


def python_ref(
    context: ResolveContext, text: str, path: KeyPath, kind: RefKind
) -> PythonRef | None:
    from robospec.resolve.python_refs import check_ref

    checked = check_ref(text, kind)
    if checked.problem is not None:
        context.err(path, UNUSABLE_PYTHON_REFERENCE, checked.problem, checked.hint)
    return checked.ref


def base_class(context: ResolveContext) -> tuple[PythonRef | None, Any]:
    """``extends``: the agent class the spec builds on, and the class itself."""
    if context.spec.extends is None:
        return None, None
    from robospec.resolve.python_refs import check_ref

    checked = check_ref(context.spec.extends, "agent_class")
    if checked.problem is not None:
        context.err(("extends",), UNUSABLE_PYTHON_REFERENCE, checked.problem, checked.hint)
    return checked.ref, checked.value if checked.ref is not None else None


def hooks(context: ResolveContext) -> ResolvedHooks:
    spec_hooks = context.spec.hooks
    loading = after_init = None
    if spec_hooks.after_loading_articulation is not None:
        loading = python_ref(
            context,
            spec_hooks.after_loading_articulation,
            ("hooks", "after_loading_articulation"),
            "hook",
        )
    if spec_hooks.after_init is not None:
        after_init = python_ref(context, spec_hooks.after_init, ("hooks", "after_init"), "hook")
    methods = []
    for name, text in spec_hooks.methods.items():
        ref = python_ref(context, text, ("hooks", "methods", name), "member")
        if ref is not None:
            methods.append((name, ref))
    return ResolvedHooks(loading, after_init, tuple(methods))


def _height(band: HeightBand) -> ResolvedHeight:
    return ResolvedHeight(band.above, band.below)
