"""Each part renamed into the robot's names, once the combined description is loaded.

A part's spec was resolved on its own (robospec.pipeline); here it gets its
:class:`~robospec.resolve.resolved.Renaming` — its links and joints as composing named them,
and the names its spec gave (controllers, groups, named links, grasp checks, link states,
cameras, materials, the keys of its control mode), each kept where neither the robot's spec
nor an earlier part has it, else given the part's prefix — and its robot is renamed through
it (:meth:`~robospec.resolve.resolved.ResolvedRobot.renamed`). Where a renamed item is
reported on, the report points into the part's spec (``ResolveContext.origins``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from robospec.diagnostics.codes import PART_NOT_CARRIED, UNKNOWN_PART_MODE
from robospec.model.frozen import Spec
from robospec.resolve.context import ResolveContext
from robospec.resolve.part_types import CarriedPart, PartInput
from robospec.resolve.resolved import FileRef, Renaming, ResolvedMode, ResolvedPart, ResolvedRobot

if TYPE_CHECKING:
    from robospec.compose.model import Mounted

# the codes of this module (robospec/diagnostics/codes.py)


class _Taken:
    """The names the robot has in each section of its spec, and those earlier parts took."""

    def __init__(self, spec: Spec) -> None:
        self.names: dict[str, set[str]] = {
            "controllers": set(spec.controllers),
            "groups": {*spec.groups, *spec.named_links},
            "named_links": set(spec.named_links),
            "grasping": set(spec.grasping),
            "link_states": set(spec.link_states),
            "cameras": set(spec.cameras),
        }
        self.mode_keys = {
            key for mode in spec.control_modes.values() if isinstance(mode, dict) for key in mode
        }
        self.materials: dict[str, Any] = dict(spec.materials)

    def take(self, section: str, prefix: str, name: str) -> str:
        """``name``, or the part's prefix and it when taken (again, while that is taken)."""
        taken = self.names[section]
        new = name if name not in taken else prefix + name
        while new in taken:  # a prefixed name taken too: prefix again (ours, not the user's)
            new = prefix + new
        taken.add(new)
        return new

    def materials_of(self, config: dict[str, Any], prefix: str) -> dict[str, str]:
        """A part's materials: one the robot (or an earlier part) has by the same name and
        values is shared, one it has with other values is prefixed."""
        renamed: dict[str, str] = {}
        for name, values in config.get("_materials", {}).items():
            existing = self.materials.get(name)
            if existing is not None and _material_values(existing) == values:
                renamed[name] = name
                continue
            new = name
            if existing is not None:
                new = prefix + name
                while new in self.materials:
                    new = prefix + new
            renamed[name] = new
            self.materials[new] = values
        return renamed

    def mode_keys_of(self, mode: ResolvedMode | None, prefix: str) -> dict[str, str]:
        """The keys the part's chosen mode adds to the robot's modes: prefixed when taken."""
        if mode is None or mode.groups is None:
            return {}
        keys = {key: key if key not in self.mode_keys else prefix + key for key, _ in mode.groups}
        self.mode_keys.update(keys.values())
        return keys


def _material_values(material: Any) -> dict[str, Any]:
    return material if isinstance(material, dict) else material.model_dump()


def carry_parts(context: ResolveContext, description: FileRef) -> tuple[CarriedPart, ...]:
    """Every mounted part in the robot's names, in the order the spec lists them.
    ``description``: the robot's combined description, where its parts' IK chains now run."""
    composed = context.composed
    if composed is None:
        return ()
    taken = _Taken(context.spec)
    by_name = {m.name: m for m in composed.parts}
    carried = []
    for name, part in context.spec.parts.items():
        mounted, given = by_name.get(name), context.parts.get(name)
        if mounted is not None and given is not None:
            carried.append(_carried(context, taken, (name, part), mounted, given, description))
    return tuple(carried)


def _carried(
    context: ResolveContext,
    taken: _Taken,
    entry: tuple[str, Any],
    mounted: Mounted,
    given: PartInput,
    description: FileRef,
) -> CarriedPart:
    """Part ``entry`` (its name and spec entry) renamed: its robot, when it has a spec, and its
    joints, passive joints and SRDF pairs."""
    name, part = entry
    links, joints = _description_names(mounted)
    robot, mode = given.robot, None
    names: dict[str, dict[str, str]] = {}
    files: tuple[tuple[FileRef, FileRef], ...] = ()
    if robot is not None:
        _warn_not_carried(context, name, given)
        mode = _chosen_mode(context, name, part, robot)
        names = _spec_names(context, taken, part.name_prefix(name), given, mode)
        files = ((robot.description, description),)
    renaming = Renaming(links, joints, names, files)
    facts = given.description
    active = facts.active_joint_names if facts is not None else ()
    pairs = facts.loader_collision_bits if facts is not None and facts.kind == "urdf" else ()
    return CarriedPart(
        part=_resolved_part(name, part, mounted, given),
        joints=tuple(map(renaming.joint, active)),
        robot=robot.renamed(renaming) if robot is not None else None,
        mode=(mode.renamed(renaming).groups or ()) if mode is not None else (),
        passive_joints=tuple(map(renaming.joint, given.passive_joints)),
        loader_pairs=tuple(tuple(map(renaming.link, links)) for _, links in pairs),
        locate=given.locate,
    )


def _description_names(mounted: Mounted) -> tuple[dict[str, str], dict[str, str]]:
    """The part's links and joints as the combined description names them, old -> new."""
    links: dict[str, str] = {}
    joints: dict[str, str] = {}
    for what, old, new in mounted.renamed:
        if what == "link":
            links.setdefault(old, new)
        elif what == "joint":
            joints.setdefault(old, new)
    return links, joints


def _spec_names(
    context: ResolveContext,
    taken: _Taken,
    prefix: str,
    given: PartInput,
    mode: ResolvedMode | None,
) -> dict[str, dict[str, str]]:
    """The names the part's spec gave, old -> new by section, each section's in its order."""
    robot = given.robot
    assert robot is not None
    names: dict[str, dict[str, str]] = {}
    for section, name in robot.defined_names():
        found = names.setdefault(section, {})
        if name in found:
            continue
        found[name] = new = taken.take(section, prefix, name)
        if given.locate is not None:  # a report on it points into the part's spec
            context.origins[(section, new)] = (given.locate, (section, name))
    names["materials"] = taken.materials_of(robot.urdf_config, prefix)
    names["mode_keys"] = taken.mode_keys_of(mode, prefix)
    return names


def _warn_not_carried(context: ResolveContext, name: str, given: PartInput) -> None:
    for what in given.carried_not:
        context.warn(
            ("parts", name, "spec"),
            PART_NOT_CARRIED,
            f"part '{name}': its spec's {what} do not come along",
            "declare what the robot needs in this spec",
        )


def _chosen_mode(
    context: ResolveContext, name: str, part: Any, robot: ResolvedRobot
) -> ResolvedMode | None:
    """The part's control mode whose controllers join the robot's modes (its first, unless
    ``parts.NAME.mode`` picks another), as groups: a one-controller mode's key is the part's
    name."""
    if not robot.modes:
        return None
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
    groups = chosen.groups if chosen.groups is not None else ((name, chosen.controller or ""),)
    return ResolvedMode(chosen.name, groups, None, chosen.balance_passive_force)


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
