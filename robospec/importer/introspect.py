"""Stage 1 of `robospec import`: a ManiSkill agent class → an :class:`AgentRecord`.

The robot is never loaded into a scene (19 of ManiSkill's agents have no installed assets, and
loading needs SAPIEN). The class is instantiated with ``BaseAgent.__init__`` replaced by a
no-op, so a subclass ``__init__`` that sets attributes and then calls ``super().__init__`` still
runs its own part; then ``self.robot`` is a stand-in that answers the few questions agents ask
while building their configs (``active_joints``, ``links_map``, ...) from the installed robot
description, or with :data:`ALL_JOINTS` when the description is not installed.
"""

from __future__ import annotations

import contextlib
import dataclasses
import inspect
import os
import sys
from collections.abc import Iterator
from typing import Any, ClassVar, Literal, Protocol

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.codes import AGENT_DATA_UNREADABLE, UPSTREAM_INEXPRESSIBLE
from robospec.geometry import Quaternion, Vector
from robospec.importer.records import (
    ALL_JOINTS,
    AgentRecord,
    CameraRecord,
    ControllerRecord,
    HookFacts,
    JointFacts,
    KeyframeRecord,
    ModeRecord,
    SourceRef,
)
from robospec.model.controller_kinds import kind_of_config

# members a spec reproduces as data, or that every agent inherits unchanged in meaning
DATA_MEMBERS = frozenset(
    {"_controller_configs", "_sensor_configs", "__init__", "__doc__", "__module__"}
)


# -- the stand-in robot ------------------------------------------------------------------------


class _Named:
    def __init__(self, name: str) -> None:
        self.name = name

    def get_name(self) -> str:
        return self.name


class AgentClass(Protocol):
    """What is read off a ManiSkill agent class: BaseAgent's class attributes (ManiSkill has no
    type annotations)."""

    urdf_path: ClassVar[str | None]
    mjcf_path: ClassVar[str | None]
    fix_root_link: ClassVar[bool]
    load_multiple_collisions: ClassVar[bool]
    disable_self_collisions: ClassVar[bool]


class _AnyName(dict[str, _Named]):
    """``links_map`` when the description is not installed: every name is a link."""

    def __missing__(self, key: str) -> _Named:
        return _Named(key)


class StandInRobot:
    """What agents read from ``self.robot`` while building configs, from the description."""

    def __init__(self, description: RobotDescription | None) -> None:
        if description is None:
            active = [ALL_JOINTS]
            joints = [ALL_JOINTS]
            self.links_map: dict[str, _Named] = _AnyName()
        else:
            active = list(description.active_joint_names)
            joints = list(description.joint_names)
            self.links_map = {name: _Named(name) for name in description.link_names}
        self.active_joints = [_Named(n) for n in active]
        self.active_joints_map = {j.name: j for j in self.active_joints}
        self.joints = [_Named(n) for n in joints]
        self.joints_map = {j.name: j for j in self.joints}
        self.links = list(self.links_map.values())

    def get_active_joints(self) -> list[_Named]:
        return self.active_joints

    def get_joints(self) -> list[_Named]:
        return self.joints

    def get_links(self) -> list[_Named]:
        return self.links


@contextlib.contextmanager
def _without_base_init() -> Iterator[None]:
    from unittest import mock

    from mani_skill.agents.base_agent import BaseAgent

    def no_op(self: Any, *args: Any, **kwargs: Any) -> None:
        return None

    with mock.patch.object(BaseAgent, "__init__", no_op):
        yield


def instantiate(cls: Any, robot: StandInRobot) -> tuple[Any, BaseException | None]:
    """An instance of ``cls`` with only its own ``__init__`` code run, and ``robot`` set."""
    obj = cls.__new__(cls)
    failure: BaseException | None = None
    with _without_base_init():
        try:
            obj.__init__(None, 20)
        except Exception as exc:
            failure = exc
    obj.robot = robot
    return obj, failure


# -- values ------------------------------------------------------------------------------------


def plain(value: Any, *, float32_short: bool = False) -> Any:
    """numpy / torch / containers → Python scalars and tuples (dicts stay dicts).

    ``float32_short``: write a float32 as the shortest decimal that reads back as the same
    float32 (for poses, which ManiSkill and SAPIEN store as float32 either way).
    """
    import numpy as np

    if type(value).__module__.startswith("torch"):
        value = value.detach().cpu().numpy()
    if isinstance(value, np.ndarray):
        if value.ndim == 0:
            return plain(value[()], float32_short=float32_short)
        return tuple(plain(v, float32_short=float32_short) for v in value)
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, np.floating):
        if float32_short and value.dtype == np.float32:
            return float(str(value))
        return float(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float) and float32_short:
        return float(str(np.float32(value)))
    if isinstance(value, (list, tuple)):
        return tuple(plain(v, float32_short=float32_short) for v in value)
    if isinstance(value, dict):
        return {str(k): plain(v, float32_short=float32_short) for k, v in value.items()}
    return value


def _pose(pose: Any) -> tuple[Vector, Quaternion]:
    p, q = pose.p, pose.q
    if getattr(p, "ndim", 1) == 2:  # a batched ManiSkill Pose
        p, q = p[0], q[0]
    return plain(p, float32_short=True), plain(q, float32_short=True)


# -- where things are --------------------------------------------------------------------------


def shown_path(module_name: str) -> str:
    """A module's file relative to the folder its top package lives in (no machine paths)."""
    module = sys.modules.get(module_name)
    file = getattr(module, "__file__", None)
    if not file:
        return module_name.replace(".", "/") + ".py"
    parts = os.path.normpath(file).split(os.sep)
    depth = module_name.count(".") + 1 + (os.path.basename(file) == "__init__.py")
    return "/".join(parts[-depth:])


def _source_of(obj: Any) -> SourceRef | None:
    try:
        lines, start = inspect.getsourcelines(obj)
    except (OSError, TypeError):
        return None
    module = getattr(obj, "__module__", None) or ""
    indent = len(lines[0]) - len(lines[0].lstrip()) if lines else 0
    return SourceRef(shown_path(module), max(start, 1), indent + 1)


def _own_classes(cls: type) -> list[type]:
    from mani_skill.agents.base_agent import BaseAgent

    mro = cls.__mro__
    return list(mro[: mro.index(BaseAgent)]) if BaseAgent in mro else [cls]


def _defined_at(cls: type, name: str) -> SourceRef | None:
    for klass in _own_classes(cls):
        if name in vars(klass):
            member = vars(klass)[name]
            target = member.fget if isinstance(member, property) else member
            found = _source_of(target) if callable(target) else None
            if found is None:
                found = _attribute_line(klass, name)
            return found
    return None


def _attribute_line(klass: type, name: str) -> SourceRef | None:
    try:
        lines, start = inspect.getsourcelines(klass)
    except (OSError, TypeError):
        return None
    for offset, line in enumerate(lines):
        stripped = line.lstrip()
        if stripped.startswith(name) and stripped[len(name) :].lstrip().startswith(("=", ":")):
            return SourceRef(
                shown_path(klass.__module__), start + offset, len(line) - len(stripped) + 1
            )
    return None


def _sources(cls: type) -> tuple[tuple[str, tuple[str, ...]], ...]:
    out: list[tuple[str, tuple[str, ...]]] = []
    for klass in _own_classes(cls):
        module = sys.modules.get(klass.__module__)
        file = getattr(module, "__file__", None)
        shown = shown_path(klass.__module__)
        if not file or any(s == shown for s, _ in out):
            continue
        try:
            with open(file, encoding="utf-8") as handle:
                out.append((shown, tuple(handle.read().splitlines())))
        except OSError:
            continue
    return tuple(out)


def _unreproduced(cls: type, hooks: HookFacts) -> tuple[str, ...]:
    """Members of the class that are code the spec does not reproduce: a hook the spec
    reproduces in part is named with what it leaves out."""
    partly = {hook: ", ".join(statements) for hook, statements in hooks.left_out}
    names: list[str] = []
    seen: set[str] = set()
    for klass in _own_classes(cls):
        for name, member in vars(klass).items():
            if name in seen or (name.startswith("__") and name != "__init__"):
                continue
            seen.add(name)
            if name == "__init__":
                try:
                    signature = inspect.signature(member)
                except (TypeError, ValueError):
                    continue
                parameters = [
                    p.name
                    for p in signature.parameters.values()
                    if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) and p.name != "self"
                ]
                own = [p for p in parameters if p not in ("scene", "control_freq", "control_mode")]
                if own:
                    names.append(f"__init__({', '.join(own)})")
                continue
            if name in DATA_MEMBERS or name in hooks.reproduced:
                continue
            if isinstance(member, (property, staticmethod, classmethod)) or inspect.isfunction(
                member
            ):
                names.append(f"{name} (in part: {partly[name]})" if name in partly else name)
    return tuple(names)


# -- the agent ---------------------------------------------------------------------------------


def absolute_path(text: str) -> str:
    """A path as ManiSkill resolves it (``{PACKAGE_ASSET_DIR}`` etc. filled in), made real."""
    from mani_skill import format_path

    return os.path.realpath(format_path(str(text)))


def asset_roots() -> tuple[tuple[str, str], ...]:
    """Spec placeholders and the folders they stand for on this machine."""
    import mani_skill

    return (
        ("{maniskill_assets}", os.path.realpath(mani_skill.PACKAGE_ASSET_DIR)),
        ("{maniskill_data}", os.path.realpath(mani_skill.ASSET_DIR)),
    )


def load_installed_description(
    cls: type[AgentClass],
) -> tuple[str | None, RobotDescription | None, list[Diagnostic]]:
    """The description file of ``cls`` on this machine and its facts, when installed."""
    from robospec.description import load_description

    kind: Literal["urdf", "mjcf"] = "urdf" if cls.urdf_path is not None else "mjcf"
    raw = cls.urdf_path if cls.urdf_path is not None else cls.mjcf_path
    if raw is None:
        return None, None, []
    path = absolute_path(str(raw))
    if not os.path.isfile(path):
        return None, None, []
    description, diagnostics = load_description(path, kind)
    return path, description, [_relocated(d, path) for d in diagnostics]


def _relocated(diagnostic: Diagnostic, path: str) -> Diagnostic:
    """A description diagnostic shown under the spec's name for the file, not this machine's."""
    if diagnostic.location.file != path:
        return diagnostic
    shown = path
    for placeholder, root in asset_roots():
        if path.startswith(root.rstrip(os.sep) + os.sep):
            shown = placeholder + "/" + os.path.relpath(path, root).replace(os.sep, "/")
    location = Location(shown, diagnostic.location.line, diagnostic.location.column)
    return dataclasses.replace(diagnostic, location=location)


def read_agent(
    cls: type[AgentClass], description: RobotDescription | None, description_file: str | None
) -> tuple[AgentRecord, list[Diagnostic]]:
    """Everything a spec can say about ``cls``, plus diagnostics for what could not be read.

    ``description`` answers ``self.robot`` questions; pass None when it is not installed.
    """
    diagnostics: list[Diagnostic] = []
    class_at = _source_of(cls) or SourceRef(shown_path(cls.__module__))
    obj = _instance(cls, description, class_at, diagnostics)
    controllers_at = _defined_at(cls, "_controller_configs")
    modes = _read_modes(cls, obj, _location(controllers_at, class_at), diagnostics)
    cameras = _read_cameras(cls, obj, class_at, diagnostics)
    materials, link_rules = _urdf_config(
        getattr(obj, "urdf_config", None),
        _location(_defined_at(cls, "urdf_config"), class_at),
        diagnostics,
    )
    keyframes = tuple(
        _keyframe(str(name), frame)
        for name, frame in (getattr(obj, "keyframes", None) or {}).items()
    )
    downloads = _asset_download_ids(cls)

    from robospec.importer.afterinit import read_hooks

    hooks = read_hooks(cls, obj, description.link_names if description is not None else None)

    kind: Literal["urdf", "mjcf"] = "urdf" if cls.urdf_path is not None else "mjcf"
    raw_path = cls.urdf_path if cls.urdf_path is not None else cls.mjcf_path
    record = AgentRecord(
        module=cls.__module__,
        class_name=cls.__qualname__,
        uid=str(getattr(cls, "uid", "")),
        source=class_at,
        description_kind=kind,
        description_path=absolute_path(str(raw_path)) if raw_path is not None else "",
        asset_roots=asset_roots(),
        description_file=description_file,
        fix_root_link=bool(cls.fix_root_link),
        load_multiple_collisions=bool(cls.load_multiple_collisions),
        disable_self_collisions=bool(cls.disable_self_collisions),
        materials=materials,
        link_rules=link_rules,
        keyframes=keyframes,
        modes=modes,
        cameras=cameras,
        asset_download_ids=downloads,
        unreproduced=_unreproduced(cls, hooks),
        active_joints=(
            tuple(
                JointFacts(j.name, j.lower, j.upper, j.mimic is not None)
                for j in description.active_joints
            )
            if description is not None
            else None
        ),
        link_names=description.link_names if description is not None else None,
        controllers_at=controllers_at,
        urdf_config_at=_defined_at(cls, "urdf_config"),
        sources=_sources(cls),
        not_imported=tuple(
            d.message
            for d in diagnostics
            if d.code in (AGENT_DATA_UNREADABLE, UPSTREAM_INEXPRESSIBLE)
        ),
        hooks=hooks,
    )
    return record, diagnostics


def _location(ref: SourceRef | None, class_at: SourceRef) -> Location:
    """Where ``ref`` points, or the class itself when a member's line is unknown."""
    ref = ref or class_at
    return Location(ref.file, ref.line, ref.column)


def _instance(
    cls: type[AgentClass],
    description: RobotDescription | None,
    class_at: SourceRef,
    diagnostics: list[Diagnostic],
) -> Any:
    """``cls`` instantiated over a stand-in robot (its class when ``__init__`` raised)."""
    if cls.urdf_path is None and cls.mjcf_path is None:
        diagnostics.append(
            error(
                _location(class_at, class_at),
                UPSTREAM_INEXPRESSIBLE,
                f"{cls.__name__} has neither urdf_path nor mjcf_path; write the spec's "
                "description by hand",
            )
        )
    robot = StandInRobot(description)
    obj, failure = instantiate(cls, robot)
    if failure is not None:
        diagnostics.append(
            warning(
                _location(_defined_at(cls, "__init__"), class_at),
                AGENT_DATA_UNREADABLE,
                f"{cls.__name__}.__init__ raised {type(failure).__name__}: {failure}; "
                "reading the class attributes only",
            )
        )
    return obj


def _read_modes(
    cls: type, obj: Any, location: Location, diagnostics: list[Diagnostic]
) -> tuple[ModeRecord, ...]:
    """The control modes of ``obj._controller_configs`` (none when it raised)."""
    try:
        configs = obj._controller_configs
    except Exception as exc:
        diagnostics.append(
            error(
                location,
                AGENT_DATA_UNREADABLE,
                f"{cls.__name__}._controller_configs raised {type(exc).__name__}: {exc}",
                "the spec has no control modes; write them by hand",
            )
        )
        configs = {}
    modes: list[ModeRecord] = []
    for mode_name, mode in configs.items():
        record = _mode(str(mode_name), mode, cls, location, diagnostics)
        if record is not None:
            modes.append(record)
    return tuple(modes)


def _read_cameras(
    cls: type, obj: Any, class_at: SourceRef, diagnostics: list[Diagnostic]
) -> tuple[CameraRecord, ...]:
    """The cameras of ``obj._sensor_configs`` (none when it raised)."""
    location = _location(_defined_at(cls, "_sensor_configs"), class_at)
    try:
        sensors = list(obj._sensor_configs)
    except Exception as exc:
        diagnostics.append(
            error(
                location,
                AGENT_DATA_UNREADABLE,
                f"{cls.__name__}._sensor_configs raised {type(exc).__name__}: {exc}",
                "the spec has no cameras; write them by hand",
            )
        )
        sensors = []
    cameras: list[CameraRecord] = []
    for sensor in sensors:
        camera = _camera(sensor, location, diagnostics)
        if camera is not None:
            cameras.append(camera)
    return tuple(cameras)


def _asset_download_ids(cls: type) -> tuple[str, ...]:
    """ManiSkill's asset download ids for ``cls``: the class's own ids, else its nearest
    registered base's."""
    from mani_skill.agents.registration import REGISTERED_AGENTS

    for klass in _own_classes(cls):
        entry = REGISTERED_AGENTS.get(getattr(klass, "uid", ""))
        if entry is not None and entry.agent_cls is klass and entry.asset_download_ids:
            return tuple(entry.asset_download_ids)
    return ()


def _mode(
    name: str, mode: Any, cls: type, location: Location, diagnostics: list[Diagnostic]
) -> ModeRecord | None:
    if not isinstance(mode, dict):
        controller = _controller(mode, name, location, diagnostics)
        return ModeRecord(name, ((None, controller),)) if controller is not None else None
    entries: list[tuple[str | None, ControllerRecord]] = []
    balance: bool | None = None
    for key, value in mode.items():
        if key == "balance_passive_force":
            balance = bool(value)
            continue
        controller = _controller(value, f"{name}.{key}", location, diagnostics)
        if controller is None:
            return None
        entries.append((str(key), controller))
    return ModeRecord(name, tuple(entries), balance)


def _controller(
    config: Any, where: str, location: Location, diagnostics: list[Diagnostic]
) -> ControllerRecord | None:
    kind = kind_of_config(type(config).__name__)
    if kind is None or not type(config).__module__.startswith("mani_skill."):
        diagnostics.append(
            error(
                location,
                UPSTREAM_INEXPRESSIBLE,
                f"control mode '{where}' uses {type(config).__name__}, which is not one of "
                "ManiSkill's controller configs; the mode is left out",
            )
        )
        return None
    joints: tuple[str, ...] = ()
    values: list[tuple[str, Any]] = []
    defaults: set[str] = set()
    for f in dataclasses.fields(config):
        if not f.init:
            continue
        value = plain(getattr(config, f.name))
        if f.name == "urdf_path" and isinstance(value, str):
            value = absolute_path(value)
        if f.name == "joint_names":
            joints = tuple(str(j) for j in (value if isinstance(value, tuple) else (value,)))
            continue
        values.append((f.name, value))
        if f.default is not dataclasses.MISSING:
            default = f.default
        elif f.default_factory is not dataclasses.MISSING:
            default = f.default_factory()
        else:
            continue
        if _same(value, plain(default)):
            defaults.add(f.name)
    return ControllerRecord(kind.name, joints, tuple(values), frozenset(defaults))


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return float(a) == float(b)
    return type(a) is type(b) and a == b


def _camera(sensor: Any, location: Location, diagnostics: list[Diagnostic]) -> CameraRecord | None:
    if type(sensor).__name__ != "CameraConfig":
        diagnostics.append(
            error(
                location,
                UPSTREAM_INEXPRESSIBLE,
                f"sensor {getattr(sensor, 'uid', '?')!r} is a {type(sensor).__name__}; "
                "a spec has cameras only, so it is left out",
            )
        )
        return None
    mount = getattr(sensor, "mount", None)
    mount_name = getattr(mount, "name", None) if mount is not None else sensor.entity_uid
    if mount_name is None:
        diagnostics.append(
            error(
                location,
                UPSTREAM_INEXPRESSIBLE,
                f"camera {sensor.uid!r} is mounted on no link; a spec's cameras are mounted on "
                "links of the robot, so it is left out",
            )
        )
        return None
    p, q = _pose(sensor.pose)
    intrinsic = plain(sensor.intrinsic) if sensor.intrinsic is not None else None
    return CameraRecord(
        uid=str(sensor.uid),
        mount=str(mount_name),
        p=p,
        q=q,
        width=int(sensor.width),
        height=int(sensor.height),
        fov=plain(sensor.fov),
        intrinsic=intrinsic,
        near=plain(sensor.near),
        far=plain(sensor.far),
        shader_pack=str(sensor.shader_pack),
    )


def _keyframe(name: str, frame: Any) -> KeyframeRecord:
    p, q = _pose(frame.pose)
    return KeyframeRecord(name, p, q, _joint_values(frame.qpos), _joint_values(frame.qvel))


def _joint_values(values: Any) -> tuple[Any, ...] | None:
    """One value per joint; a batch of one (``[[...]]``, as some agents write) is unwrapped."""
    if values is None:
        return None
    values = plain(values)
    if not isinstance(values, tuple):
        return (values,)
    while len(values) == 1 and isinstance(values[0], tuple):
        values = values[0]
    return values


def _urdf_config(
    config: Any, location: Location, diagnostics: list[Diagnostic]
) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
    if not config:
        return (), ()
    if not isinstance(config, dict):
        diagnostics.append(
            error(
                location,
                UPSTREAM_INEXPRESSIBLE,
                "urdf_config is given as a file; import the materials by hand",
            )
        )
        return (), ()
    for key in config:
        if key not in ("_materials", "link"):
            diagnostics.append(
                error(
                    location,
                    UPSTREAM_INEXPRESSIBLE,
                    f"urdf_config key {key!r} has no spec equivalent; it is left out",
                )
            )
    materials = tuple(
        (str(name), tuple(plain(settings).items()))
        for name, settings in (config.get("_materials") or {}).items()
    )
    rules = tuple(
        (str(link), tuple(plain(settings).items()))
        for link, settings in (config.get("link") or {}).items()
    )
    return materials, rules
