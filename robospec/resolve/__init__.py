"""Stage 3: bind a :class:`Spec` to its robot description in one pass.

Every joint, link, group, controller and material name is looked up here, once; what comes
out is a :class:`ResolvedRobot` in ManiSkill's own terms, plus located diagnostics.
"""

from __future__ import annotations

import fnmatch
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath, LoadedSpec
from robospec.model.frozen import AllBut, Keyframe, MimicTarget, Pose, Spec
from robospec.model.names import GLOB
from robospec.model.validate import SpecModelResult
from robospec.resolve.paths import (
    maniskill_assets_dir,
    maniskill_data_dir,
    split_assets,
    split_data,
)
from robospec.resolve.resolved import (
    FileRef,
    ResolvedCamera,
    ResolvedCollisionRule,
    ResolvedController,
    ResolvedKeyframe,
    ResolvedMode,
    ResolvedRobot,
)

PER_JOINT_FIELDS = (
    "stiffness",
    "damping",
    "force_limit",
    "friction",
    "lower",
    "upper",
    "vel_lower",
    "vel_upper",
    "drive_mode",
)
LIMIT_TOLERANCE = 1e-6
NEEDS_DOWNLOAD = (
    "this needs the robot description, which is not downloaded",
    "write the values as one full list in qpos order, or download the robot's assets",
)
# ManiSkill's dataclass field order, so generated configs read like its own
KWARG_ORDER = (
    "joint_names",
    "lower",
    "upper",
    "pos_lower",
    "pos_upper",
    "rot_lower",
    "rot_upper",
    "vel_lower",
    "vel_upper",
    "stiffness",
    "damping",
    "force_limit",
    "friction",
    "ee_link",
    "urdf_path",
    "frame",
    "root_link_name",
    "use_delta",
    "use_target",
    "interpolate",
    "normalize_action",
    "delta_solver_config",
    "drive_mode",
    "mimic",
)


@dataclass
class Resolution:
    robot: ResolvedRobot | None
    description: RobotDescription | None
    diagnostics: list[Diagnostic] = field(default_factory=list)


class Resolver:
    def __init__(self, loaded: LoadedSpec, model: SpecModelResult, spec_file: Path) -> None:
        assert model.spec is not None
        self.loaded = loaded
        self.model = model
        self.spec: Spec = model.spec
        self.spec_file = spec_file
        self.diagnostics: list[Diagnostic] = []
        self.description: RobotDescription | None = None
        self._group_cache: dict[str, list[str]] = {}
        self.inherited_kind: Literal["urdf", "mjcf"] = "urdf"
        # the description is not downloaded: names are taken as written (see assumed.py)
        self.assumed = False

    # -- locations --------------------------------------------------------------------------

    def at_value(self, path: KeyPath) -> Location:
        return self.loaded.source.value(self.model.origin(path))

    def at_key(self, path: KeyPath) -> Location:
        return self.loaded.source.key(self.model.origin(path))

    def err(self, path: KeyPath, code: str, message: str, hint: str | None = None) -> None:
        self.diagnostics.append(error(self.at_value(path), code, message, hint))

    def warn(self, path: KeyPath, code: str, message: str, hint: str | None = None) -> None:
        self.diagnostics.append(warning(self.at_value(path), code, message, hint))

    # -- description ------------------------------------------------------------------------

    def file_ref(self, text: str, path: KeyPath, *, may_be_missing: bool = False) -> FileRef | None:
        in_assets = split_assets(text)
        in_data = split_data(text)
        if in_data is not None:
            ref = FileRef("maniskill_data", in_data, maniskill_data_dir() / in_data)
        elif in_assets is not None:
            assets = maniskill_assets_dir()
            if assets is None:
                self.err(
                    path,
                    "RS050",
                    f"'{text}' names ManiSkill's assets, but ManiSkill is not installed",
                    "pip install 'robospec[maniskill]'",
                )
                return None
            ref = FileRef("maniskill_assets", in_assets, assets / in_assets)
        else:
            ref = FileRef("file", text, (self.spec_file.parent / text).resolve())
        try:
            found = ref.absolute.is_file()
            exists = found or ref.absolute.exists()
        except OSError as exc:  # a name too long for the file system, a loop of links, ...
            self.err(path, "RS050", f"cannot use '{text}' as a file: {exc.strerror or exc}")
            return None
        if exists and not found:  # a folder or a FIFO: there, but not a file to read
            what = "a folder" if ref.absolute.is_dir() else "not a regular file"
            self.err(path, "RS050", f"cannot use '{text}' as a file: it is {what}")
            return None
        if not found:
            if may_be_missing:
                return ref
            self.err(
                path,
                "RS050",
                f"file not found: '{text}'",
                f"looked for {ref.absolute}" if ref.kind == "file" else None,
            )
            return None
        return ref

    def inherited_description(self, base: Any) -> FileRef | None:
        """The description an ``extends`` class names, for a spec that gives none."""
        from robospec.description import load_description

        text = getattr(base, "mjcf_path", None) or getattr(base, "urdf_path", None)
        kind = "mjcf" if getattr(base, "mjcf_path", None) else "urdf"
        if not isinstance(text, str):
            self.err(
                ("extends",),
                "RS220",
                "the extended class names no urdf_path or mjcf_path",
                "add a description to the spec",
            )
            return None
        assets = maniskill_assets_dir()
        path = Path(text)
        if assets is not None and path.is_relative_to(assets):
            ref = FileRef("maniskill_assets", path.relative_to(assets).as_posix(), path)
        else:
            ref = FileRef("file", text, path)
        if not path.is_file():
            self.err(("extends",), "RS050", f"the extended class's description is missing: {text}")
            return None
        description, diags = load_description(str(path), kind)
        self.diagnostics.extend(_relocate(diags, str(path), self._display(ref)))
        self.description = description
        self.inherited_kind = kind
        return ref if description is not None else None

    def load_description(self) -> FileRef | None:
        from robospec.description import load_description

        desc = self.spec.description
        assert desc is not None
        path: KeyPath = ("description", desc.kind)
        ref = self.file_ref(desc.path, path, may_be_missing=bool(desc.download))
        if ref is None:
            return None
        shown = self._display(ref)
        if not ref.absolute.is_file():  # a download ManiSkill has not fetched yet
            from robospec.description.assumed import assumed_description

            self.warn(
                path,
                "RS055",
                f"'{desc.path}' is not downloaded: joint and link names are not checked",
                "python -m mani_skill.utils.download_asset " + " ".join(desc.download),
            )
            self.assumed = True
            self.description = assumed_description(self.spec, shown)
            return ref
        if desc.kind == "xacro":
            from robospec.description.xacro import expand_xacro

            args = {k: _xacro_arg(v) for k, v in desc.args.items()}
            text, diags = expand_xacro(str(ref.absolute), args)
            self.diagnostics.extend(_relocate(diags, str(ref.absolute), shown))
            if text is None:
                return None
            description, diags = load_description(str(ref.absolute), "urdf", text=text)
            self.diagnostics.extend(_relocate(diags, str(ref.absolute), shown + " (expanded)"))
            ref = FileRef(ref.kind, ref.relative, ref.absolute, generated_text=text)
        else:
            description, diags = load_description(str(ref.absolute), desc.kind)
            self.diagnostics.extend(_relocate(diags, str(ref.absolute), shown))
        self.description = description
        return ref if description is not None else None

    def _display(self, ref: FileRef) -> str:
        return ref.placeholder_text or str(Path(self.loaded.path).parent / ref.relative)

    # -- joint selections --------------------------------------------------------------------

    def select(self, selection: Any, path: KeyPath, *, stack: tuple[str, ...] = ()) -> list[str]:
        """Expand a joint selection into joint names, in the order written (globs: qpos order)."""
        assert self.description is not None
        if isinstance(selection, AllBut):
            excluded = set(self.select(selection.all_but, (*path, "all_but"), stack=stack))
            return [j for j in self.description.active_joint_names if j not in excluded]
        if isinstance(selection, list):
            out: list[str] = []
            for index, item in enumerate(selection):
                out.extend(self.select(item, (*path, index), stack=stack))
            return out
        name = str(selection)
        joint = self.description.joint(name)
        if joint is None and name in self.spec.groups:
            return self.group(name, path, stack)
        if joint is not None:
            if not joint.is_active:
                self.err(
                    path,
                    "RS311",
                    f"joint '{name}' is {joint.type}, not an active joint",
                    "only revolute, continuous and prismatic joints can be selected",
                )
                return []
            return [name]
        if GLOB.search(name):
            matched = [
                j for j in self.description.active_joint_names if fnmatch.fnmatchcase(j, name)
            ]
            if not matched:
                self.err(path, "RS207", f"pattern '{name}' matches no active joint")
            return matched
        candidates = [*self.description.joint_names, *self.spec.groups]
        self.err(path, "RS201", f"unknown joint '{name}'", did_you_mean(name, candidates))
        return []

    def group(self, name: str, used_at: KeyPath, stack: tuple[str, ...]) -> list[str]:
        if name in stack:
            cycle = " -> ".join((*stack[stack.index(name) :], name))
            self.err(("groups", name), "RS209", f"group definition is circular: {cycle}")
            return []
        if name not in self._group_cache:
            self._group_cache[name] = self.select(
                self.spec.groups[name], ("groups", name), stack=(*stack, name)
            )
        return self._group_cache[name]

    def select_links(self, selection: str | list[str], path: KeyPath) -> list[str]:
        assert self.description is not None
        items = selection if isinstance(selection, list) else [selection]
        out: list[str] = []
        for index, item in enumerate(items):
            item_path = (*path, index) if isinstance(selection, list) else path
            out.extend(self.links_matching(item, item_path))
        return out

    def links_matching(self, pattern: str, path: KeyPath) -> list[str]:
        assert self.description is not None
        if self.description.link(pattern) is not None:
            return [pattern]
        if GLOB.search(pattern):
            matched = [n for n in self.description.link_names if fnmatch.fnmatchcase(n, pattern)]
            if not matched:
                self.err(path, "RS206", f"pattern '{pattern}' matches no link")
            return matched
        self.err(
            path,
            "RS202",
            f"unknown link '{pattern}'",
            did_you_mean(pattern, self.description.link_names),
        )
        return []

    def link(self, name: str, path: KeyPath) -> str | None:
        assert self.description is not None
        if self.description.link(name) is None:
            self.err(
                path,
                "RS202",
                f"unknown link '{name}'",
                did_you_mean(name, self.description.link_names),
            )
            return None
        return name

    # -- per-joint values -------------------------------------------------------------------

    def per_joint(self, value: Any, joints: Sequence[str], path: KeyPath) -> Any:
        """A scalar stays a scalar; a list must have one value per joint; a mapping by
        joint or group name becomes a list in the controller's joint order."""
        if isinstance(value, list):
            if len(value) != len(joints):
                self.err(
                    path,
                    "RS102",
                    f"expected {len(joints)} values (one per joint), got {len(value)}",
                )
            return list(value)
        if not isinstance(value, dict):
            return value
        by_joint: dict[str, Any] = {}
        for key, item in value.items():
            for joint in self.select(key, (*path, key)):
                if joint not in joints:
                    self.err(
                        (*path, key), "RS201", f"joint '{joint}' is not driven by this controller"
                    )
                elif joint in by_joint:
                    self.err((*path, key), "RS313", f"joint '{joint}' is given a value twice")
                by_joint[joint] = item
        missing = [j for j in joints if j not in by_joint]
        if missing:
            self.err(path, "RS102", "no value for joint(s) " + ", ".join(missing))
        return [by_joint.get(j) for j in joints]

    # -- keyframes --------------------------------------------------------------------------

    def joint_values(self, values: Any, path: KeyPath, *, limits: bool) -> tuple[float, ...] | None:
        assert self.description is not None
        active = self.description.active_joint_names
        if values is None:
            return None
        if self.assumed:
            # the joint order is the description's, which is not here: only a full list works
            if isinstance(values, list):
                return tuple(float(v) for v in values)
            self.err(path, "RS055", *NEEDS_DOWNLOAD)
            return None
        if isinstance(values, list):
            if len(values) != len(active):
                self.err(
                    path,
                    "RS303",
                    f"expected {len(active)} values, one per active joint "
                    f"({', '.join(active)}), got {len(values)}",
                )
                return None
            result = list(values)
            value_paths = [(*path, i) for i in range(len(values))]
        else:
            by_joint: dict[str, float] = {}
            where: dict[str, KeyPath] = {}
            for key, item in values.items():
                joints = self.select(key, (*path, key))
                items = item if isinstance(item, list) else [item] * len(joints)
                if len(items) != len(joints):
                    self.err(
                        (*path, key),
                        "RS303",
                        f"'{key}' has {len(joints)} joints but {len(items)} values",
                    )
                    continue
                for index, (joint, number) in enumerate(zip(joints, items, strict=True)):
                    if joint in by_joint:
                        self.err((*path, key), "RS313", f"joint '{joint}' is set twice")
                    by_joint[joint] = number
                    where[joint] = (*path, key, index) if isinstance(item, list) else (*path, key)
            missing = [j for j in active if j not in by_joint]
            if missing:
                self.err(path, "RS303", "no value for active joint(s) " + ", ".join(missing))
                return None
            result = [by_joint[j] for j in active]
            value_paths = [where[j] for j in active]
        if limits:
            for joint, number, value_path in zip(
                self.description.active_joints, result, value_paths, strict=True
            ):
                low = -math.inf if joint.lower is None else joint.lower
                high = math.inf if joint.upper is None else joint.upper
                if not low - LIMIT_TOLERANCE <= number <= high + LIMIT_TOLERANCE:
                    self.err(
                        value_path,
                        "RS304",
                        f"{number:g} is outside the limits of '{joint.name}' [{low:g}, {high:g}]",
                    )
        return tuple(float(v) for v in result)

    def keyframe(self, name: str, frame: Keyframe) -> ResolvedKeyframe:
        path: KeyPath = ("keyframes", name)
        p, q = _pose(frame.pose)
        return ResolvedKeyframe(
            name=name,
            p=p,
            q=q,
            qpos=self.joint_values(frame.qpos, (*path, "qpos"), limits=True),
            qvel=self.joint_values(frame.qvel, (*path, "qvel"), limits=False),
        )

    # -- controllers ------------------------------------------------------------------------

    def controller(self, name: str, config: Any, description_ref: FileRef) -> ResolvedController:
        path: KeyPath = ("controllers", name)
        joints = self.select(config.joints, (*path, "joints"))
        seen: set[str] = set()
        for joint in joints:
            if joint in seen:
                self.err((*path, "joints"), "RS310", f"joint '{joint}' is listed twice")
            seen.add(joint)
        kwargs: list[tuple[str, Any]] = [("joint_names", joints)]
        required = {n for n, f in type(config).model_fields.items() if f.is_required()}
        for field_name in type(config).model_fields:
            if field_name in ("type", "joints"):
                continue
            if field_name not in config.model_fields_set and field_name not in required:
                continue
            value = getattr(config, field_name)
            field_path = (*path, field_name)
            if config.type == "pd_base_forward_vel" and field_name in ("lower", "upper"):
                # bounds of the 2-D action (forward speed, turn rate), not per joint
                value = self.per_joint(value, ("forward", "turn"), field_path)
            elif field_name in PER_JOINT_FIELDS:
                value = self.per_joint(value, joints, field_path)
            elif field_name == "mimic":
                value = self.mimic(value, joints, field_path)
            elif field_name in ("ee_link", "root_link_name") and value is not None:
                self.link(value, field_path)
            elif field_name == "urdf_path" and value is not None:
                value = self.file_ref(value, field_path)
            elif field_name == "delta_solver_config" and value is not None:
                value = value.model_dump()
            kwargs.append((field_name, value))
        if (
            config.type in ("pd_ee_pos", "pd_ee_pose")
            and "urdf_path" not in config.model_fields_set
        ):
            # ManiSkill's own agents pass their URDF to the IK controller; so do we
            kwargs.append(("urdf_path", description_ref))
        if config.type in ("pd_base_vel", "pd_base_forward_vel") and len(joints) < 3:
            self.err(
                (*path, "joints"),
                "RS315",
                f"{config.type} drives x, y and yaw joints: "
                f"needs at least 3 joints, got {len(joints)}",
            )
        kwargs.sort(key=lambda item: KWARG_ORDER.index(item[0]))
        group = (
            config.joints
            if isinstance(config.joints, str) and config.joints in self.spec.groups
            else None
        )
        return ResolvedController(name, config.type, tuple(kwargs), joints_group=group)

    def mimic(self, value: dict[str, Any], joints: Sequence[str], path: KeyPath) -> dict:
        result: dict[str, dict[str, Any]] = {}
        for follower, target in value.items():
            leader = target if isinstance(target, str) else target.joint
            entry: dict[str, Any] = {"joint": leader}
            if isinstance(target, MimicTarget):
                entry.update(
                    {
                        k: getattr(target, k)
                        for k in ("multiplier", "offset")
                        if k in target.model_fields_set
                    }
                )
            for joint, where in ((follower, (*path, follower)), (leader, (*path, follower))):
                if joint not in joints:
                    known = self.description and self.description.joint(joint)
                    if known:
                        self.err(
                            where,
                            "RS305",
                            f"mimic joint '{joint}' is not one of this controller's joints",
                        )
                    else:
                        self.err(
                            where, "RS201", f"unknown joint '{joint}'", did_you_mean(joint, joints)
                        )
            if follower == leader:
                self.err((*path, follower), "RS305", f"joint '{follower}' mimics itself")
            result[follower] = entry
        followers, leaders = set(result), {e["joint"] for e in result.values()}
        if followers & leaders:
            both = ", ".join(sorted(followers & leaders))
            self.err(path, "RS305", f"joint(s) {both} both mimic and are mimicked")
        uncovered = [j for j in joints if j not in followers | leaders]
        if result and uncovered:
            self.err(
                path,
                "RS305",
                "every joint of a mimic controller must appear in the mimic "
                "map; missing: " + ", ".join(uncovered),
            )
        return result

    def modes(self, controllers: dict[str, ResolvedController]) -> list[ResolvedMode]:
        modes: list[ResolvedMode] = []
        for mode_name, mode in self.spec.control_modes.items():
            path: KeyPath = ("control_modes", mode_name)
            if isinstance(mode, str):
                self.known_controller(mode, path)
                modes.append(ResolvedMode(mode_name, None, controller=mode))
                continue
            groups: list[tuple[str, str]] = []
            balance: bool | None = None
            for key, value in mode.items():
                if key == "balance_passive_force":
                    if not isinstance(value, bool):
                        self.err(
                            (*path, key), "RS102", "balance_passive_force must be true or false"
                        )
                    else:
                        balance = value
                    continue
                if not isinstance(value, str):
                    self.err((*path, key), "RS102", f"'{key}' must name a controller")
                    continue
                self.known_controller(value, (*path, key))
                groups.append((key, value))
            if not groups:
                self.err(path, "RS103", f"control mode '{mode_name}' has no controllers")
            modes.append(ResolvedMode(mode_name, tuple(groups), balance_passive_force=balance))
        return modes

    def known_controller(self, name: str, path: KeyPath) -> None:
        if name not in self.spec.controllers:
            self.err(
                path,
                "RS204",
                f"unknown controller '{name}'",
                did_you_mean(name, self.spec.controllers),
            )

    # -- the whole robot --------------------------------------------------------------------

    def resolve(self) -> Resolution:
        from robospec.resolve.members import HelperResolver
        from robospec.resolve.never_collide import resolve_never_collide

        spec = self.spec
        helpers = HelperResolver(self)
        base_ref, base_class = helpers.base_class()
        if spec.extends is not None and base_ref is None:
            return Resolution(None, None, self.diagnostics)
        if spec.description is not None:
            description_ref = self.load_description()
            description_kind = "mjcf" if spec.description.kind == "mjcf" else "urdf"
        else:
            description_ref = self.inherited_description(base_class)
            description_kind = self.inherited_kind
        if description_ref is None or self.description is None:
            return Resolution(None, self.description, self.diagnostics)
        description = self.description
        for name in spec.groups:
            if description.joint(name) is not None:
                # a selection names a group or a joint by the same word: one of them would be
                # unreachable, and the group would select itself (a false "circular" error)
                self.diagnostics.append(
                    error(
                        self.at_key(("groups", name)),
                        "RS210",
                        f"group '{name}' has the name of a joint",
                        f"rename the group (e.g. '{name}_group')",
                    )
                )
                continue
            self.group(name, ("groups", name), ())

        urdf_config = self.urdf_config()
        keyframes = tuple(self.keyframe(n, k) for n, k in spec.keyframes.items())
        controllers = {
            name: self.controller(name, config, description_ref)
            for name, config in spec.controllers.items()
        }
        modes = self.modes(controllers)
        cameras = tuple(self.camera(uid, cam) for uid, cam in spec.cameras.items())
        rules = tuple(
            ResolvedCollisionRule(
                tuple(self.select_links(rule.links, ("collision_rules", i, "links"))),
                rule.group,
                rule.bit,
                rule.value,
            )
            for i, rule in enumerate(spec.collision_rules)
        )
        packed, never_collide = resolve_never_collide(self, rules)
        helpers.check_members()
        robot = ResolvedRobot(
            uid=spec.uid,
            class_name=spec.class_name or class_name_for(spec.uid),
            spec_path=self.loaded.path,
            description_kind=description_kind,
            description=description_ref,
            fix_root_link=spec.loader.fix_root_link,
            load_multiple_collisions=spec.loader.load_multiple_collisions,
            disable_self_collisions=spec.loader.disable_self_collisions,
            urdf_config=urdf_config,
            keyframes=keyframes,
            controllers=tuple(controllers.values()),
            modes=tuple(modes),
            cameras=cameras,
            collision_rules=rules + packed,
            tcp=helpers.tcp(),
            active_joints=description.active_joint_names,
            override=spec.override,
            download_ids=tuple(spec.description.download) if spec.description else (),
            base=base_ref,
            declared=self.declared_sections(),
            named_links=helpers.named_links(),
            grasping=helpers.grasping(),
            is_static=helpers.is_static(),
            is_standing=helpers.is_standing(),
            is_fallen=helpers.is_fallen(),
            link_states=helpers.link_states(),
            proprioception=helpers.proprioception(),
            disable_gravity=helpers.disable_gravity(),
            drives=helpers.drives(),
            hooks=helpers.hooks(),
            never_collide=never_collide,
        )
        return Resolution(robot, description, self.diagnostics)

    def declared_sections(self) -> frozenset[str]:
        """What the generated class sets itself; with ``extends`` the rest is inherited."""
        spec = self.spec
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

    def urdf_config(self) -> dict[str, Any]:
        spec = self.spec
        links: dict[str, dict[str, Any]] = {}
        for pattern, rule in spec.links.items():
            path: KeyPath = ("links", pattern)
            if rule.material is None:
                self.diagnostics.append(
                    error(
                        self.at_key(path),
                        "RS312",
                        f"link rule '{pattern}' has no material",
                        "ManiSkill 3 requires a material in every link entry of urdf_config",
                    )
                )
            elif rule.material not in spec.materials:
                self.err(
                    (*path, "material"),
                    "RS205",
                    f"unknown material '{rule.material}'",
                    did_you_mean(rule.material, spec.materials),
                )
            settings = rule.model_dump(exclude_none=True)
            key_location = self.at_key(path)
            for link in self._links_for_rule(pattern, path, key_location):
                links.setdefault(link, {}).update(settings)
        config: dict[str, Any] = {}
        if spec.materials:
            config["_materials"] = {name: m.model_dump() for name, m in spec.materials.items()}
        if links:
            assert self.description is not None
            order = {name: i for i, name in enumerate(self.description.link_names)}
            config["link"] = {name: links[name] for name in sorted(links, key=order.__getitem__)}
        return config

    def _links_for_rule(self, pattern: str, path: KeyPath, at: Location) -> list[str]:
        assert self.description is not None
        if self.description.link(pattern) is not None:
            return [pattern]
        matched = [n for n in self.description.link_names if fnmatch.fnmatchcase(n, pattern)]
        if not matched:
            code = "RS206" if GLOB.search(pattern) else "RS202"
            message = (
                f"link rule '{pattern}' matches no link"
                if code == "RS206"
                else f"unknown link '{pattern}'"
            )
            self.diagnostics.append(
                error(at, code, message, did_you_mean(pattern, self.description.link_names))
            )
        return matched

    def camera(self, uid: str, camera: Any) -> ResolvedCamera:
        path: KeyPath = ("cameras", uid)
        self.link(camera.mount, (*path, "mount"))
        if (camera.fov is None) == (camera.intrinsic is None):
            self.diagnostics.append(
                error(
                    self.at_key(path),
                    "RS314",
                    f"camera '{uid}' needs exactly one of fov and intrinsic",
                )
            )
        p, q = _pose(camera.pose)
        intrinsic = tuple(tuple(row) for row in camera.intrinsic) if camera.intrinsic else None
        return ResolvedCamera(
            uid,
            camera.mount,
            p,
            q,
            camera.width,
            camera.height,
            camera.fov,
            intrinsic,
            camera.near,
            camera.far,
            camera.shader_pack,
        )


def _pose(pose: Pose) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    p = (pose.p[0], pose.p[1], pose.p[2])
    if pose.q is not None:
        q = (pose.q[0], pose.q[1], pose.q[2], pose.q[3])
    elif pose.rpy is not None:
        q = rpy_to_quaternion(*pose.rpy)
    else:
        q = (1.0, 0.0, 0.0, 0.0)
    return p, q


def rpy_to_quaternion(roll: float, pitch: float, yaw: float) -> tuple[float, float, float, float]:
    """wxyz quaternion of R = Rz(yaw) Ry(pitch) Rx(roll), URDF's and SAPIEN's convention."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )


def class_name_for(uid: str) -> str:
    """``rs_panda`` -> ``RsPanda``; always a valid Python identifier."""
    parts = [p for p in re.split(r"[^A-Za-z0-9]+", uid) if p]
    name = "".join(p[:1].upper() + p[1:] for p in parts) or "Agent"
    if name[0].isdigit():
        name = "Agent" + name
    return name


def _xacro_arg(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _relocate(diagnostics: list[Diagnostic], absolute: str, shown: str) -> list[Diagnostic]:
    """Show description diagnostics under the path the user wrote, not this machine's path."""
    out = []
    for d in diagnostics:
        if d.location.file == absolute:
            d = Diagnostic(
                Location(shown, d.location.line, d.location.column),
                d.code,
                d.severity,
                d.message,
                d.hint,
            )
        out.append(d)
    return out
