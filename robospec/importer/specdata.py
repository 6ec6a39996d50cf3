"""Stage 2 of `robospec import`: an :class:`AgentRecord` → spec data (plain, ordered dicts) with
the comments that go with it, plus diagnostics about the class."""

from __future__ import annotations

import os
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robospec.diagnostics import Diagnostic, Location, warning
from robospec.diagnostics.codes import (
    AGENT_CODE_NOT_REPRODUCED,
    DESCRIPTION_NOT_INSTALLED,
    IMPORTED_UID_IS_MANISKILLS,
)
from robospec.geometry import IDENTITY
from robospec.importer.controllers import ControllerPlan, listify, plan_controllers
from robospec.importer.groups import (
    GroupPlan,
    glob_candidates,
    partition_of,
    plan_groups,
    selection_for,
    split_by_group,
)
from robospec.importer.records import (
    ALL_JOINTS,
    AgentRecord,
    CameraRecord,
    HookFacts,
    KeyframeRecord,
    ModeRecord,
)
from robospec.importer.upstream import Findings, find_upstream_mistakes

KeyPath = tuple[str | int, ...]
COMMENT_WIDTH = 98


@dataclass(frozen=True)
class SpecDoc:
    data: dict[str, Any]
    header: tuple[str, ...] = ()  # comment lines at the top, after the schema modeline
    notes: dict[KeyPath, str] = field(default_factory=dict)  # end-of-line comments by key path


def spec_data(record: AgentRecord, uid: str, out_dir: Path) -> tuple[SpecDoc, list[Diagnostic]]:
    paths = _SpecPaths(record, out_dir)
    found = find_upstream_mistakes(record, paths.text_unless_description)
    modes = [m for m in record.modes if m.name not in found.dropped_modes]
    groups = plan_groups(modes, record.active_joint_names)
    controllers = plan_controllers(modes, groups, paths.text_unless_description)
    passive = _undriven(modes, record)
    data = _data(record, uid, paths, found, modes, groups, controllers, passive)
    notes: dict[KeyPath, str] = {}
    for (key, field_name), note in found.field_notes.items():
        for name, controller in controllers.records.items():
            if controller.key == key and field_name in controllers.controllers[name]:
                notes[("controllers", name, field_name)] = note
    header = _header(record, found, passive)
    diagnostics = [*found.diagnostics, *_class_warnings(record, uid, modes, paths)]
    return SpecDoc(data, header, notes), diagnostics


@dataclass(frozen=True)
class _SpecPaths:
    """Files of the class as a spec writes them: under a ManiSkill placeholder, or relative to
    the folder the spec is written to."""

    record: AgentRecord
    out_dir: Path

    def text(self, absolute: str) -> str:
        if not absolute:
            return ""
        for placeholder, root in self.record.asset_roots:
            if absolute.startswith(root.rstrip(os.sep) + os.sep):
                rel = os.path.relpath(absolute, root)
                return placeholder + "/" + Path(rel).as_posix()
        try:
            return Path(os.path.relpath(absolute, self.out_dir.resolve())).as_posix()
        except ValueError:  # another drive
            return Path(absolute).as_posix()

    def text_unless_description(self, absolute: str) -> str | None:
        """None for the robot's own description, which controllers take by default."""
        return None if absolute == self.record.description_path else self.text(absolute)

    @property
    def description(self) -> str:
        return self.text(self.record.description_path)


def _data(
    record: AgentRecord,
    uid: str,
    paths: _SpecPaths,
    found: Findings,
    modes: list[ModeRecord],
    groups: GroupPlan,
    controllers: ControllerPlan,
    passive: tuple[str, ...],
) -> dict[str, Any]:
    """The spec, key by key in the order a person would write it."""
    all_joints = record.active_joint_names
    data: dict[str, Any] = {"robospec": 1, "uid": uid}
    data["description"] = {record.description_kind: paths.description}
    if record.asset_download_ids:
        data["description"]["download"] = list(record.asset_download_ids)
    loader = {
        name: getattr(record, name)
        for name, default in (
            ("fix_root_link", True),
            ("load_multiple_collisions", False),
            ("disable_self_collisions", False),
        )
        if getattr(record, name) is not default
    }
    if loader:
        data["loader"] = loader
    if record.materials:
        data["materials"] = {name: dict(settings) for name, settings in record.materials}
    rules = _link_rules(record, set(found.dropped_rules))
    if rules:
        data["links"] = rules
    if groups.values:
        data["groups"] = dict(groups.values)
    if passive:
        data["passive_joints"] = selection_for(passive, all_joints)
    partition = partition_of(modes, groups, all_joints)
    keyframes = [k for k in record.keyframes if k.name not in found.dropped_keyframes]
    if keyframes:
        data["keyframes"] = {
            frame.name: _keyframe(frame, all_joints, partition) for frame in keyframes
        }
    data["controllers"] = controllers.controllers
    data["control_modes"] = controllers.modes
    cameras = [c for c in record.cameras if c.uid not in found.dropped_cameras]
    if cameras:
        data["cameras"] = {camera.uid: _camera(camera) for camera in cameras}
    data.update(_hook_data(record.hooks))
    return data


def _hook_data(hooks: HookFacts) -> dict[str, Any]:
    """What the class's ``_after_init`` / ``_after_loading_articulation`` do, as spec sections
    (:mod:`robospec.importer.afterinit` read them), in the order the zoo's specs write them."""
    data: dict[str, Any] = {}
    if hooks.collision_rules:
        data["collision_rules"] = [
            {
                "links": rule.links[0] if len(rule.links) == 1 else list(rule.links),
                "group": rule.group,
                "bit": rule.bit,
                **({"value": rule.value} if rule.value != 1 else {}),
            }
            for rule in hooks.collision_rules
        ]
    tcp = hooks.tcp
    if tcp is not None:
        if tcp.midpoint is None:
            data["tcp"] = tcp.link
        else:
            data["tcp"] = {
                **({"link": tcp.link} if tcp.link is not None else {}),
                "midpoint": list(tcp.midpoint),
                "orientation": tcp.orientation,
            }
    if hooks.named_links:
        data["named_links"] = {
            name: value if isinstance(value, str) else list(value)
            for name, value in hooks.named_links
        }
    if hooks.grasping:
        data["grasping"] = {
            check.method: {
                "fingers": [{"link": f.attribute, "opening": f.opening} for f in check.fingers],
                "min_force": check.min_force,
                "max_angle": check.max_angle,
            }
            for check in hooks.grasping
        }
    return data


def _header(record: AgentRecord, found: Findings, passive: tuple[str, ...]) -> tuple[str, ...]:
    """The comment at the top of the spec: where it came from, and what was left out."""
    header = [f"Imported by `robospec import` from {record.module}:{record.class_name}."]
    if record.description_file is None:
        header.append(
            "Its robot description is not installed here, so joints are named as upstream "
            "names them and keyframes are full ordered lists."
        )
    if record.asset_download_ids:
        header.append(
            "ManiSkill downloads its assets with: python -m mani_skill.utils.download_asset "
            + " ".join(record.asset_download_ids)
        )
    if passive:
        header.append(
            "passive_joints: joints that some of upstream's control modes leave without a "
            "controller."
        )
    header += [f"Not imported: {message}." for message in record.not_imported]
    for what, dropped in (
        ("control mode", found.dropped_modes),
        ("the urdf_config rule for link", found.dropped_rules),
        ("keyframe", found.dropped_keyframes),
        ("camera", found.dropped_cameras),
    ):
        header += [f"Left out: {what} {name} ({why})." for name, why in dropped.items()]
    if record.unreproduced:
        header.append("Not reproduced (code, not data): " + ", ".join(record.unreproduced) + ".")
    wrapped: list[str] = []
    for line in header:
        wrapped.extend(
            textwrap.wrap(line, COMMENT_WIDTH, break_on_hyphens=False, break_long_words=False)
        )
    return tuple(wrapped)


def _class_warnings(
    record: AgentRecord, uid: str, modes: list[ModeRecord], paths: _SpecPaths
) -> list[Diagnostic]:
    """What the spec cannot carry over from the class (RS409, RS410), and a uid ManiSkill
    registers itself (RS411)."""
    from robospec.maniskill.installed import registered_uids

    at_class = Location(record.source.file, record.source.line, record.source.column)
    diagnostics: list[Diagnostic] = []
    if record.unreproduced:
        diagnostics.append(
            warning(
                at_class,
                AGENT_CODE_NOT_REPRODUCED,
                f"{record.class_name} defines {len(record.unreproduced)} member(s) that are code "
                "the spec does not reproduce: " + ", ".join(record.unreproduced),
                "keep them in a subclass of the generated agent, or port them by hand",
            )
        )
    if record.description_file is None and record.description_path:
        hint = (
            "download it with: python -m mani_skill.utils.download_asset "
            + " ".join(record.asset_download_ids)
            if record.asset_download_ids
            else None
        )
        every = any(c.joints == (ALL_JOINTS,) for m in modes for _, c in m.entries)
        diagnostics.append(
            warning(
                at_class,
                DESCRIPTION_NOT_INSTALLED,
                f"robot description '{paths.description}' is not installed: joint and link "
                "names are not checked, no globs, keyframes as ordered lists"
                + (
                    "; upstream drives every active joint, written '*', which `robospec "
                    "validate` can only expand once the description is there"
                    if every
                    else ""
                ),
                hint,
            )
        )
    if uid in registered_uids():
        diagnostics.append(
            warning(
                Location("<uid>", 1, 1),
                IMPORTED_UID_IS_MANISKILLS,
                f"uid '{uid}' is ManiSkill's own agent; registering the spec under it would be "
                "skipped",
                f"pass --uid rs_{uid}",
            )
        )
    return diagnostics


def _undriven(modes: list[ModeRecord], record: AgentRecord) -> tuple[str, ...]:
    """Joints some control mode leaves without a controller (upstream lets them hang), URDF
    mimic joints aside; unknowable when the joints are "all of an uninstalled description"."""
    driven = [{j for _, c in mode.entries for j in c.joints} for mode in modes]
    if any(ALL_JOINTS in joints for joints in driven):
        return ()
    if record.active_joints is not None:
        every = tuple(j.name for j in record.active_joints if not j.mimic)
    else:
        every = tuple(dict.fromkeys(j for m in modes for _, c in m.entries for j in c.joints))
    return tuple(j for j in every if any(j not in joints for joints in driven))


def _link_rules(record: AgentRecord, dropped: set[str]) -> dict[str, dict[str, Any]]:
    by_settings: dict[tuple[Any, ...], list[str]] = {}
    for link, settings in record.link_rules:
        if link not in dropped:
            by_settings.setdefault(settings, []).append(link)
    rules: dict[str, dict[str, Any]] = {}
    for settings, links in by_settings.items():
        pattern = _link_glob(links, record.link_names)
        if pattern is not None:
            rules[pattern] = dict(settings)
            continue
        for link in links:
            rules[link] = dict(settings)
    return rules


def _link_glob(links: list[str], names: tuple[str, ...] | None) -> str | None:
    if names is None or len(links) < 2:
        return None
    import fnmatch

    for pattern in glob_candidates(tuple(links)):
        if {n for n in names if fnmatch.fnmatchcase(n, pattern)} == set(links):
            return pattern
    return None


def _pose(p: tuple[float, ...], q: tuple[float, ...], *, keep_p: bool) -> dict[str, Any]:
    pose: dict[str, Any] = {}
    if keep_p or any(v != 0 for v in p):
        pose["p"] = list(p)
    if tuple(q) != IDENTITY:
        pose["q"] = list(q)
    return pose


def _keyframe(
    frame: KeyframeRecord,
    all_joints: tuple[str, ...] | None,
    partition: list[tuple[str, tuple[str, ...]]] | None,
) -> dict[str, Any]:
    entry: dict[str, Any] = {}
    pose = _pose(frame.p, frame.q, keep_p=False)
    if pose:
        entry["pose"] = pose
    for name in ("qpos", "qvel"):
        values = getattr(frame, name)
        if values is None:
            continue
        split = (
            split_by_group(values, all_joints, partition)
            if partition is not None and all_joints is not None
            else None
        )
        entry[name] = split if split is not None else listify(values)
    return entry


def _camera(camera: CameraRecord) -> dict[str, Any]:
    entry: dict[str, Any] = {"mount": camera.mount, "pose": _pose(camera.p, camera.q, keep_p=True)}
    entry["width"] = camera.width
    entry["height"] = camera.height
    if camera.fov is not None:
        entry["fov"] = camera.fov
    if camera.intrinsic is not None:
        entry["intrinsic"] = [list(row) for row in camera.intrinsic]
    if camera.near != 0.01:
        entry["near"] = camera.near
    if camera.far != 100:
        entry["far"] = camera.far
    if camera.shader_pack != "minimal":
        entry["shader_pack"] = camera.shader_pack
    return entry
