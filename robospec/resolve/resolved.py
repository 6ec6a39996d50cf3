"""The resolved robot: a spec with every reference bound to the description, ready to emit.

Everything here is plain, frozen data in ManiSkill's own terms (joint-name lists, ordered qpos
arrays, ``urdf_config`` dicts). The emitter reads only this.

Each type that names something — a joint, a link, a controller, a group, a named link, ... —
knows how to rename those references (``renamed``, through a :class:`Renaming`): a part's
robot, resolved on its own, is renamed into the names of the robot it is mounted on, the way
dm_control's ``attach`` scopes an attached model's names
(robospec.resolve.part_renaming).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from robospec.geometry import Pose, Quaternion, Vector
from robospec.load.source_map import KeyPath
from robospec.model.controller_kinds import ControllerKind, controller_kind
from robospec.resolve.paths import ASSETS_PLACEHOLDER, DATA_PLACEHOLDER


@dataclass
class Bindings:
    """How the spec's names bound to the robot description, by where each was written: what
    the checks stage judges (one joint listed twice, a keyframe one value short, ...).

    A selection that did not bind whole (an unknown name in it) is left out: resolve has
    reported it, and a check of it would only repeat that error in other words.
    """

    # selection path -> the active joints it selected, in the order written (globs: qpos order)
    joints: dict[KeyPath, tuple[str, ...]] = field(default_factory=dict)
    # selection path -> the links it selected
    links: dict[KeyPath, tuple[str, ...]] = field(default_factory=dict)
    # every name that named a joint of the description (active or not), where it was written
    joint_names: list[tuple[KeyPath, str]] = field(default_factory=list)
    # every link of the description the spec names (directly, by a glob or a rule), and where:
    # what robospec optimize must keep
    link_names: list[tuple[KeyPath, str]] = field(default_factory=list)


@dataclass(frozen=True)
class FileRef:
    """A file the generated agent names: in ManiSkill's assets, or a file on disk."""

    kind: Literal["maniskill_assets", "maniskill_data", "file"]
    relative: str  # for maniskill_assets/maniskill_data: the path below that folder
    absolute: Path  # where it is on this machine
    # a xacro expansion: the URDF text the generated package must carry as a file
    generated_text: str | None = None
    # The description's mesh and texture files as written -> where robospec found them, when
    # the generated package must carry the URDF with these paths rewritten: always for a
    # xacro expansion (written elsewhere), and for a URDF whose package:// (or file://) URIs
    # SAPIEN's loader would resolve differently or not at all. Empty: loaded as it is.
    mesh_paths: tuple[tuple[str, str], ...] = ()
    # a description robospec derived (robospec.derive: mended): a built package carries it
    # with copies of every file it names, so that it loads where the original is absent
    derived: bool = False
    # a description composed with parts mounted (robospec.compose): the parts' names, and
    # the files it was written from besides this one (the parts' specs and descriptions)
    parts: tuple[str, ...] = ()
    sources: tuple[str, ...] = ()
    # whether SAPIEN reads an SRDF beside this file (a URDF file, mended or not; never a
    # xacro expansion, which SAPIEN never sees as a file)
    has_srdf_beside: bool = True

    @property
    def carried(self) -> bool:
        """Whether the generated package carries its own copy of this file."""
        return self.generated_text is not None or bool(self.mesh_paths)

    def read_text(self) -> str:
        """The description's text: robospec's own (an expansion, a derived or combined copy),
        else the file's. OSError when the file cannot be read."""
        return self.generated_text if self.generated_text is not None else self.absolute.read_text()

    def read_bytes(self) -> bytes:
        """:meth:`read_text` as bytes, the file's as they are (a regular file only: a FIFO
        would block the read)."""
        if self.generated_text is not None:
            return self.generated_text.encode("utf-8")
        from robospec.description.urdf import read_file_bytes

        return read_file_bytes(str(self.absolute))

    @property
    def placeholder_text(self) -> str | None:
        """How a spec writes a file in ManiSkill's folders (``{maniskill_assets}/...``); None
        for a file on disk, which each reader shows its own way."""
        if self.kind == "maniskill_assets":
            return f"{ASSETS_PLACEHOLDER}/{self.relative}"
        if self.kind == "maniskill_data":
            return f"{DATA_PLACEHOLDER}/{self.relative}"
        return None


@dataclass(frozen=True)
class Renaming:
    """A mounted part's names as the robot it is mounted on has them: its links and joints as
    the combined description names them (robospec.compose), the names its spec gave, by the
    section that gives them (``controllers``, ``groups``, ``named_links``, ``grasping``,
    ``link_states``, ``cameras``, ``materials``, and ``mode_keys``: the keys of a control
    mode), and the files its controllers name. A name it does not list stays as it is."""

    links: Mapping[str, str] = field(default_factory=dict)
    joints: Mapping[str, str] = field(default_factory=dict)
    names: Mapping[str, Mapping[str, str]] = field(default_factory=dict)
    # (the part's file, the robot's): its description, and the combined one where the IK
    # chain of its end-effector controller now runs
    files: tuple[tuple[FileRef, FileRef], ...] = ()

    def link(self, name: str) -> str:
        return self.links.get(name, name)

    def joint(self, name: str) -> str:
        return self.joints.get(name, name)

    def name(self, section: str, name: str) -> str:
        return self.names.get(section, {}).get(name, name)

    def member(self, name: str) -> str:
        """A finger's, a link state's or the tcp's link: a ``named_links`` attribute, else a
        link."""
        attributes = self.names.get("named_links", {})
        return attributes[name] if name in attributes else self.link(name)

    def file(self, ref: FileRef) -> FileRef:
        return next((new for old, new in self.files if old == ref), ref)


@dataclass(frozen=True)
class ResolvedController:
    name: str
    type: str
    # ManiSkill config keyword arguments, in emission order; FileRef values name files
    kwargs: tuple[tuple[str, Any], ...]
    # the spec group its joints were given as, when exactly one group
    joints_group: str | None = None

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(dict(self.kwargs)["joint_names"])

    @property
    def kind(self) -> ControllerKind:
        """What its ``type`` is (:mod:`robospec.model.controller_kinds`)."""
        return controller_kind(self.type)

    def renamed(self, r: Renaming) -> ResolvedController:
        group = self.joints_group
        return ResolvedController(
            r.name("controllers", self.name),
            self.type,
            tuple((key, _renamed_kwarg(key, value, r)) for key, value in self.kwargs),
            r.name("groups", group) if group is not None else None,
        )


def _renamed_kwarg(key: str, value: Any, r: Renaming) -> Any:
    """A controller config's argument with the joints, links and files it names renamed."""
    if key == "joint_names":
        return [r.joint(j) for j in value]
    if key in ("ee_link", "root_link_name") and isinstance(value, str):
        return r.link(value)
    if key == "urdf_path" and isinstance(value, FileRef):
        return r.file(value)
    if key == "mimic" and isinstance(value, dict):
        return {
            r.joint(follower): {**target, "joint": r.joint(target["joint"])}
            for follower, target in value.items()
        }
    return value


@dataclass(frozen=True)
class ResolvedMode:
    name: str
    # group -> controller name; None for a single-controller mode
    groups: tuple[tuple[str, str], ...] | None
    controller: str | None = None
    balance_passive_force: bool | None = None

    def renamed(self, r: Renaming) -> ResolvedMode:
        groups = self.groups
        return ResolvedMode(
            self.name,
            tuple((r.name("mode_keys", k), r.name("controllers", c)) for k, c in groups)
            if groups is not None
            else None,
            r.name("controllers", self.controller) if self.controller is not None else None,
            self.balance_passive_force,
        )


@dataclass(frozen=True)
class ResolvedKeyframe:
    name: str
    p: Vector
    q: Quaternion
    qpos: tuple[float, ...] | None
    qvel: tuple[float, ...] | None


@dataclass(frozen=True)
class ResolvedCamera:
    uid: str
    mount: str
    p: Vector
    q: Quaternion
    width: int
    height: int
    fov: float | None
    intrinsic: tuple[tuple[float, ...], ...] | None
    near: float
    far: float
    shader_pack: str

    def renamed(self, r: Renaming) -> ResolvedCamera:
        return dataclasses.replace(self, uid=r.name("cameras", self.uid), mount=r.link(self.mount))


@dataclass(frozen=True)
class ResolvedCollisionRule:
    links: tuple[str, ...]
    group: int
    bit: int
    value: int

    def renamed(self, r: Renaming) -> ResolvedCollisionRule:
        return dataclasses.replace(self, links=tuple(map(r.link, self.links)))


@dataclass(frozen=True)
class ResolvedNeverCollide:
    """``never_collide`` after packing. The bits themselves are ordinary group-2 rules at the end
    of ``ResolvedRobot.collision_rules``; this records what the checks report on."""

    entries: tuple[tuple[str, ...], ...]  # the links of each entry, in the description's order
    bits: tuple[int, ...] = ()  # the group-2 bits the packed rules set
    available: tuple[int, ...] = ()  # the bits that were free to use
    # pairs that share a bit though no entry lists them (bits were short), by entry index
    side_effects: tuple[tuple[int, tuple[tuple[str, str], ...]], ...] = ()
    # listed pairs left colliding: no bit was free
    uncovered: tuple[tuple[str, str], ...] = ()
    # loader.disable_self_collisions: nothing was packed
    skipped: bool = False

    def renamed(self, r: Renaming) -> ResolvedNeverCollide:
        def pairs(found: tuple[tuple[str, str], ...]) -> tuple[tuple[str, str], ...]:
            return tuple((r.link(a), r.link(b)) for a, b in found)

        return dataclasses.replace(
            self,
            entries=tuple(tuple(map(r.link, links)) for links in self.entries),
            side_effects=tuple((index, pairs(found)) for index, found in self.side_effects),
            uncovered=pairs(self.uncovered),
        )


@dataclass(frozen=True)
class PythonRef:
    """``module:attribute.path``, checked importable; emitted as constants, never as names."""

    module: str
    attributes: tuple[str, ...]

    @property
    def text(self) -> str:
        return f"{self.module}:{'.'.join(self.attributes)}"


@dataclass(frozen=True)
class ResolvedTcp:
    link: str | None
    midpoint: tuple[str, str] | None = None
    # with a midpoint: a link's name, or "midpoint" for the mean of the two quaternions
    orientation: str | None = None

    def renamed(self, r: Renaming) -> ResolvedTcp:
        midpoint, orientation = self.midpoint, self.orientation
        return ResolvedTcp(
            r.member(self.link) if self.link else None,
            (r.member(midpoint[0]), r.member(midpoint[1])) if midpoint else None,
            r.member(orientation) if orientation not in (None, "midpoint") else orientation,
        )


@dataclass(frozen=True)
class ResolvedFinger:
    link: str  # a link name, or a named_links attribute (see ResolvedRobot.named_links)
    axis: int  # column of the link's rotation matrix: 0 x, 1 y, 2 z
    sign: int  # +1 or -1

    def renamed(self, r: Renaming) -> ResolvedFinger:
        return dataclasses.replace(self, link=r.member(self.link))


@dataclass(frozen=True)
class ResolvedGrasping:
    method: str
    fingers: tuple[ResolvedFinger, ResolvedFinger]
    min_force: float
    max_angle: float

    def renamed(self, r: Renaming) -> ResolvedGrasping:
        first, second = self.fingers
        return dataclasses.replace(
            self,
            method=r.name("grasping", self.method),
            fingers=(first.renamed(r), second.renamed(r)),
        )


@dataclass(frozen=True)
class ResolvedStatic:
    indices: tuple[int, ...]  # qvel columns
    threshold: float
    base_indices: tuple[int, ...] | None
    base_threshold: float | None
    absolute: bool


@dataclass(frozen=True)
class ResolvedReset:
    """What the agent's ``reset()`` starts each episode at: keyframe ``keyframe``'s joints, with
    Gaussian noise of ``qpos_noise`` on the qpos columns ``noise_columns`` (of ``dof``)."""

    keyframe: str
    qpos_noise: float
    noise_columns: tuple[int, ...]
    dof: int
    # the keyframe sets joint velocities too: the reset restores them after the positions
    with_qvel: bool = False


@dataclass(frozen=True)
class ResolvedHeight:
    above: float | None
    below: float | None


@dataclass(frozen=True)
class ResolvedStanding:
    height: ResolvedHeight
    upright_within: float | None


@dataclass(frozen=True)
class ResolvedFallen:
    height: ResolvedHeight | None
    contact_links: tuple[str, ...] = ()
    force_above: float | None = None

    def renamed(self, r: Renaming) -> ResolvedFallen:
        return dataclasses.replace(self, contact_links=tuple(map(r.link, self.contact_links)))


@dataclass(frozen=True)
class ResolvedLinkState:
    name: str
    links: tuple[str, ...] | str  # link names, or a named_links attribute holding a list
    single: bool  # one link: its (N, 7) pose or (N, 3) velocity, not a stack
    quantity: str  # "pose" | "linear_velocity"
    stack_dim: int
    method: bool

    @property
    def width(self) -> int:
        return 7 if self.quantity == "pose" else 3

    def renamed(self, r: Renaming) -> ResolvedLinkState:
        links = self.links
        return dataclasses.replace(
            self,
            name=r.name("link_states", self.name),
            links=r.member(links) if isinstance(links, str) else tuple(map(r.member, links)),
        )


@dataclass(frozen=True)
class ResolvedDrive:
    parent: str
    parent_pose: Pose
    child: str
    child_pose: Pose
    limits: tuple[tuple[str, float, float], ...]  # ("x", lower, upper), ...

    def renamed(self, r: Renaming) -> ResolvedDrive:
        return dataclasses.replace(self, parent=r.link(self.parent), child=r.link(self.child))


@dataclass(frozen=True)
class ResolvedLoop:
    """A closed loop (``loops``): the drive that closes it after loading, and the joints of
    the cycle it closes (the tree's path between its two links), which no controller needs
    to drive."""

    name: str
    links: tuple[str, str]
    poses: tuple[Pose, Pose]  # where they meet, in each link's frame
    weld: bool
    joints: tuple[str, ...]

    def renamed(self, r: Renaming) -> ResolvedLoop:
        first, second = self.links
        return dataclasses.replace(
            self, links=(r.link(first), r.link(second)), joints=tuple(map(r.joint, self.joints))
        )


@dataclass(frozen=True)
class ResolvedTouch:
    """Force-sensing links (``touch``), in the order their readings come."""

    links: tuple[str, ...]
    proprioception: bool

    def renamed(self, r: Renaming) -> ResolvedTouch:
        return dataclasses.replace(self, links=tuple(map(r.link, self.links)))


@dataclass(frozen=True)
class ResolvedMobileBase:
    """A planar base (``mobile_base``): the joints the derived copy added, the controller
    that drives them, the links kept off the floor and the wheel joints left passive."""

    link: str
    joints: tuple[str, ...]  # x slide, y slide, z hinge
    controller: str
    wheels: tuple[str, ...]
    wheel_joints: tuple[str, ...]

    def renamed(self, r: Renaming) -> ResolvedMobileBase:
        return dataclasses.replace(
            self,
            link=r.link(self.link),
            joints=tuple(map(r.joint, self.joints)),
            controller=r.name("controllers", self.controller),
            wheels=tuple(map(r.link, self.wheels)),
            wheel_joints=tuple(map(r.joint, self.wheel_joints)),
        )


@dataclass(frozen=True)
class ResolvedHooks:
    after_loading_articulation: PythonRef | None = None
    after_init: PythonRef | None = None
    methods: tuple[tuple[str, PythonRef], ...] = ()


@dataclass(frozen=True)
class ResolvedPart:
    """A robot mounted on this one (``parts:``), as the combined description has it."""

    name: str
    source: str  # its spec file, or its description file, as the spec wrote it
    kind: Literal["spec", "description"]
    at: str  # the link the spec mounts it on (before fold_frames)
    joint: str  # the fixed joint that mounts it ("" for an MJCF body, welded to its parent)
    root: str  # its root link
    p: Vector
    q: Quaternion
    links: tuple[str, ...]
    joints: tuple[str, ...]
    # (link | joint | material, name in the part's file, name here) for every prefixed name
    renamed: tuple[tuple[str, str, str], ...] = ()
    description: str = ""  # the part's description file, as diagnostics name it
    folded: tuple[str, ...] = ()  # empty frames fold_frames left out (links and joints)


@dataclass(frozen=True)
class ResolvedSimulation:
    """The spec's ``simulation`` section: what the agent sets on its own shapes, and the sim
    config it recommends (``sim_config``: ManiSkill's ``SimConfig`` as the nested dict that
    ``gym.make(sim_config=...)`` merges over a task's defaults)."""

    profile: str | None = None
    category: str | None = None
    contact_offset: float | None = None
    solver_position_iterations: int | None = None
    solver_velocity_iterations: int | None = None

    @property
    def sim_config(self) -> dict[str, Any]:
        scene = {
            key: value
            for key, value in (
                ("solver_position_iterations", self.solver_position_iterations),
                ("solver_velocity_iterations", self.solver_velocity_iterations),
            )
            if value is not None
        }
        return {"scene_config": scene} if scene else {}

    @property
    def empty(self) -> bool:
        return self == ResolvedSimulation()


@dataclass(frozen=True)
class ResolvedRobot:
    uid: str
    class_name: str
    spec_path: str
    description_kind: Literal["urdf", "mjcf"]
    description: FileRef
    fix_root_link: bool
    load_multiple_collisions: bool
    disable_self_collisions: bool
    # ManiSkill's urdf_config: {"_materials": {...}, "link": {...}}; empty when there are none
    urdf_config: dict[str, Any]
    keyframes: tuple[ResolvedKeyframe, ...]
    controllers: tuple[ResolvedController, ...]
    modes: tuple[ResolvedMode, ...]
    cameras: tuple[ResolvedCamera, ...]
    collision_rules: tuple[ResolvedCollisionRule, ...]
    tcp: ResolvedTcp | None
    active_joints: tuple[str, ...] = field(default=())
    override: bool = False
    download_ids: tuple[str, ...] = ()
    # extends: a Python agent class; then only the sections in `declared` are emitted
    base: PythonRef | None = None
    declared: frozenset[str] = frozenset(
        {"description", "loader", "urdf_config", "keyframes", "controllers", "cameras"}
    )
    named_links: tuple[tuple[str, str | tuple[str, ...]], ...] = ()
    grasping: tuple[ResolvedGrasping, ...] = ()
    is_static: ResolvedStatic | None = None
    is_standing: ResolvedStanding | None = None
    is_fallen: ResolvedFallen | None = None
    reset: ResolvedReset | None = None
    link_states: tuple[ResolvedLinkState, ...] = ()
    proprioception: tuple[str, ...] = ()
    disable_gravity: tuple[str, ...] = ()
    drives: tuple[ResolvedDrive, ...] = ()
    loops: tuple[ResolvedLoop, ...] = ()
    # joint -> armature the agent sets after loading: the description's (an MJCF compiled by
    # MuJoCo), which its URDF cannot say
    armature: tuple[tuple[str, float], ...] = ()
    touch: ResolvedTouch | None = None
    mobile_base: ResolvedMobileBase | None = None
    hooks: ResolvedHooks = ResolvedHooks()
    never_collide: ResolvedNeverCollide | None = None
    # the robots mounted on this one (their links and joints are in the description)
    parts: tuple[ResolvedPart, ...] = ()
    simulation: ResolvedSimulation = ResolvedSimulation()

    @property
    def mechanism_passive_joints(self) -> frozenset[str]:
        """The joints the robot's mechanisms move, which no control mode needs to drive: the
        joints of its closed loops and its wheels' joints under a planar base."""
        wheels = self.mobile_base.wheel_joints if self.mobile_base is not None else ()
        return frozenset((*(j for loop in self.loops for j in loop.joints), *wheels))

    @property
    def own_collision_rules(self) -> tuple[ResolvedCollisionRule, ...]:
        """The spec's collision rules, without the group-2 bits ``never_collide`` packed."""
        packed = len(self.never_collide.bits) if self.never_collide is not None else 0
        return self.collision_rules[: len(self.collision_rules) - packed]

    def defined_names(self) -> Iterator[tuple[str, str]]:
        """``(section, name)`` for each name this robot's spec defines that a renaming maps
        (besides links, joints, materials and mode keys), in the order defined; a group once
        per controller that names it."""
        for controller in self.controllers:
            yield "controllers", controller.name
            if controller.joints_group is not None:
                yield "groups", controller.joints_group
        yield from (("named_links", attribute) for attribute, _ in self.named_links)
        yield from (("grasping", check.method) for check in self.grasping)
        yield from (("link_states", state.name) for state in self.link_states)
        yield from (("cameras", camera.uid) for camera in self.cameras)

    def renamed(self, r: Renaming) -> ResolvedRobot:
        """This robot with every joint, link, controller, group, ... it names mapped through
        ``r``: a part's robot in the names of the robot it is mounted on. Its description,
        loader settings, hooks and the parts mounted on it are left as they are."""

        def each(items: tuple[Any, ...]) -> tuple[Any, ...]:
            return tuple(item.renamed(r) for item in items)

        def optional(item: Any) -> Any:
            return item.renamed(r) if item is not None else None

        return dataclasses.replace(
            self,
            urdf_config=_renamed_urdf_config(self.urdf_config, r),
            controllers=each(self.controllers),
            modes=each(self.modes),
            cameras=each(self.cameras),
            collision_rules=each(self.collision_rules),
            tcp=optional(self.tcp),
            active_joints=tuple(map(r.joint, self.active_joints)),
            named_links=tuple(
                (
                    r.name("named_links", attribute),
                    r.link(value) if isinstance(value, str) else tuple(map(r.link, value)),
                )
                for attribute, value in self.named_links
            ),
            grasping=each(self.grasping),
            is_fallen=optional(self.is_fallen),
            link_states=each(self.link_states),
            proprioception=tuple(r.name("link_states", n) for n in self.proprioception),
            disable_gravity=tuple(map(r.link, self.disable_gravity)),
            drives=each(self.drives),
            loops=each(self.loops),
            armature=tuple((r.joint(joint), value) for joint, value in self.armature),
            touch=optional(self.touch),
            mobile_base=optional(self.mobile_base),
            never_collide=optional(self.never_collide),
        )


def _renamed_urdf_config(config: Mapping[str, Any], r: Renaming) -> dict[str, Any]:
    """ManiSkill's ``urdf_config`` with its materials and the links its rules name renamed."""
    out = dict(config)
    if "_materials" in config:
        out["_materials"] = {
            r.name("materials", name): dict(values) for name, values in config["_materials"].items()
        }
    if "link" in config:
        out["link"] = {
            r.link(link): {**rule, "material": r.name("materials", rule["material"])}
            if "material" in rule
            else dict(rule)
            for link, rule in config["link"].items()
        }
    return out
