"""The spec, version 1: everything a ManiSkill ``BaseAgent`` subclass declares, as data.

Pure data and local rules only: no file is read here. References into the robot description
(joint and link names) are bound later, in :mod:`robospec.resolve`.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, StrictBool, model_validator

from robospec.model.common import (
    GroupSelection,
    JointSelection,
    LinkPatterns,
    LinkSelection,
    Number,
    Pose,
    StrictModel,
)
from robospec.model.controllers import ControllerConfig
from robospec.model.helpers import (
    Drive,
    Grasping,
    Hooks,
    IsFallen,
    IsStanding,
    IsStatic,
    LinkState,
    Member,
    NamedLink,
    PythonRef,
    Tcp,
)
from robospec.model.physics import Checks
from robospec.model.refs import (
    ControllerName,
    JointPattern,
    LinkName,
    LinkOrNamed,
    LinkPattern,
    LinkStateName,
    MaterialName,
)

UID_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.\-]{0,63}$"
NAME_PATTERN = r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$"
CLASS_NAME_PATTERN = r"^[A-Za-z_][A-Za-z0-9_]{0,63}$"

ScalarArg = str | int | float | bool


class Description(StrictModel):
    """The robot description file: exactly one of ``urdf``, ``mjcf`` or ``xacro``.

    Relative paths are taken against the spec file's folder; ``{maniskill_assets}`` stands for
    ManiSkill's bundled asset folder.
    """

    urdf: str | None = Field(
        default=None, examples=["{maniskill_assets}/robots/panda/panda_v2.urdf"]
    )
    mjcf: str | None = Field(
        default=None, examples=["{maniskill_assets}/robots/humanoid/humanoid.xml"]
    )
    xacro: str | None = Field(default=None, examples=["robots/twolink/twolink.urdf.xacro"])
    args: dict[str, ScalarArg] = Field(
        default_factory=dict, description="xacro arguments (name := value)"
    )
    download: list[Annotated[str, Field(pattern=NAME_PATTERN)]] = Field(
        default_factory=list,
        description="ManiSkill asset download ids (`register_agent(asset_download_ids=...)`); "
        "a spec whose description is not downloaded yet is checked without it",
    )

    @model_validator(mode="after")
    def _exactly_one(self) -> Description:
        given = [k for k in ("urdf", "mjcf", "xacro") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of urdf, mjcf or xacro")
        if self.args and self.xacro is None:
            raise ValueError("args are only for xacro descriptions")
        return self

    @property
    def kind(self) -> Literal["urdf", "mjcf", "xacro"]:
        if self.urdf is not None:
            return "urdf"
        return "mjcf" if self.mjcf is not None else "xacro"

    @property
    def path(self) -> str:
        return self.urdf or self.mjcf or self.xacro or ""


class Loader(StrictModel):
    """How ManiSkill loads the articulation (BaseAgent class attributes)."""

    fix_root_link: bool = Field(default=True, description="fix the root link in place")
    load_multiple_collisions: bool = Field(
        default=False, description="load collision meshes as multiple convex shapes"
    )
    disable_self_collisions: bool = Field(
        default=False, description="disable all collisions between the robot's own links"
    )


class Material(StrictModel):
    """A physical material (PhysX friction and restitution)."""

    static_friction: Number
    dynamic_friction: Number
    restitution: Number = 0.0


class LinkRule(StrictModel):
    """Physical properties for the links a name or glob matches."""

    material: MaterialName | None = Field(default=None, description="a name from `materials`")
    patch_radius: Number | None = None
    min_patch_radius: Number | None = None
    density: Number | None = None


JointValues = list[Number] | dict[JointPattern, Number | list[Number]]


class Keyframe(StrictModel):
    """A named robot state: root pose, joint positions and velocities."""

    pose: Pose = Field(default_factory=Pose)
    qpos: JointValues | None = Field(
        default=None, description="all active joints in order, or by joint/group name"
    )
    qvel: JointValues | None = None


class Camera(StrictModel):
    """A camera mounted on a link."""

    mount: LinkName = Field(description="the link the camera is mounted on")
    pose: Pose = Field(default_factory=Pose, description="pose relative to the mount link")
    width: Annotated[int, Field(gt=0, le=16384)]
    height: Annotated[int, Field(gt=0, le=16384)]
    fov: Number | None = Field(default=None, description="vertical field of view in radians")
    intrinsic: (
        Annotated[
            list[Annotated[list[Number], Field(min_length=3, max_length=3)]],
            Field(min_length=3, max_length=3),
        ]
        | None
    ) = Field(default=None, description="3x3 intrinsic matrix, instead of fov")
    near: Number = 0.01
    far: Number = 100.0
    shader_pack: Literal["minimal", "default", "rt", "rt-med", "rt-fast"] = "minimal"


class CollisionRule(StrictModel):
    """Set one collision-group bit on some links (``link.set_collision_group_bit``)."""

    links: LinkPatterns = Field(description="link names or globs")
    group: Annotated[int, Field(ge=0, le=3)] = Field(description="collision group index, 0 to 3")
    bit: Annotated[int, Field(ge=0, le=31)] = Field(description="bit index, 0 to 31")
    value: Literal[0, 1] = 1


ControlMode = ControllerName | dict[str, ControllerName | StrictBool]
"""A single controller name, or ``{group: controller, ..., balance_passive_force: bool}``."""


class Spec(StrictModel):
    """A robot for ManiSkill, version 1."""

    robospec: Literal[1] = Field(description="spec format version")
    uid: Annotated[str, Field(pattern=UID_PATTERN)] = Field(
        description="the agent uid passed to gym.make(robot_uids=...)"
    )
    override: bool = Field(
        default=False,
        description="replace an agent already registered under this uid (e.g. ManiSkill's "
        "'panda', so tasks that choose poses by uid use this robot)",
    )
    extends: PythonRef | None = Field(
        default=None,
        description="a Python agent class to subclass ('module:Class'); the spec then "
        "overrides only the data it declares",
        examples=["mani_skill.agents.robots.panda.panda:Panda"],
    )
    class_name: Annotated[str, Field(pattern=CLASS_NAME_PATTERN)] | None = Field(
        default=None, description="Python class name; default: derived from uid"
    )
    description: Description | None = Field(
        default=None, description="the robot description; optional only with `extends`"
    )
    loader: Loader = Field(default_factory=Loader)
    materials: dict[Annotated[str, Field(pattern=NAME_PATTERN)], Material] = Field(
        default_factory=dict
    )
    links: dict[LinkPattern, LinkRule] = Field(
        default_factory=dict, description="link rules by name or glob; each must match a link"
    )
    groups: dict[Annotated[str, Field(pattern=NAME_PATTERN)], GroupSelection] = Field(
        default_factory=dict, description="named joint selections"
    )
    passive_joints: JointSelection | None = Field(
        default=None, description="joints no control mode needs to drive"
    )
    keyframes: dict[Annotated[str, Field(pattern=NAME_PATTERN)], Keyframe] = Field(
        default_factory=dict
    )
    controllers: dict[Annotated[str, Field(pattern=NAME_PATTERN)], ControllerConfig] = Field(
        default_factory=dict, description="controller configs, defined once, reused by modes"
    )
    control_modes: dict[Annotated[str, Field(pattern=NAME_PATTERN)], ControlMode] = Field(
        default_factory=dict,
        description="ordered; the first is the default. Required unless `extends` gives them",
    )
    cameras: dict[Annotated[str, Field(pattern=NAME_PATTERN)], Camera] = Field(default_factory=dict)
    collision_rules: list[CollisionRule] = Field(default_factory=list)
    never_collide: list[LinkPatterns] = Field(
        default_factory=list,
        description="links that must never collide: each entry is a list of link names or "
        "globs, no two of which collide (a pair, or a clique); packed into the fewest "
        "collision-group bits",
        examples=[[["panda_link5", "panda_hand"], "panda_*finger"]],
    )
    scene_collision_bits: list[Annotated[int, Field(ge=0, le=31)]] = Field(
        default_factory=list,
        description="collision-group-2 bits the scenes this robot is used in set on their own "
        "objects; never_collide leaves them free (ManiSkill's bits 29-31 are always left free)",
    )
    tcp: LinkOrNamed | Tcp | None = Field(
        default=None, description="the tool centre point: a link, or a link/midpoint mapping"
    )
    named_links: dict[Member, NamedLink] = Field(
        default_factory=dict,
        description="agent attributes bound to links after loading (e.g. finger1_link)",
    )
    grasping: dict[Member, Grasping] = Field(
        default_factory=dict, description="two-finger grasp checks by method name (is_grasping)"
    )
    is_static: IsStatic | None = None
    is_standing: IsStanding | None = None
    is_fallen: IsFallen | None = None
    link_states: dict[Member, LinkState] = Field(
        default_factory=dict, description="properties reading link poses or velocities"
    )
    proprioception: list[LinkStateName] = Field(
        default_factory=list, description="link_states added to get_proprioception, in order"
    )
    disable_gravity: LinkSelection | None = Field(
        default=None, description="links that ignore gravity (e.g. all but a quadruped's root)"
    )
    drives: list[Drive] = Field(default_factory=list, description="closed-loop drives")
    hooks: Hooks = Field(default_factory=Hooks)
    checks: Checks = Field(
        default_factory=Checks, description="thresholds of `robospec check` for this robot"
    )

    @model_validator(mode="after")
    def _description_or_base(self) -> Spec:
        if self.extends is None and self.description is None:
            raise ValueError("give a description (or extend a Python agent class)")
        if self.extends is None and not self.control_modes:
            raise ValueError("give at least one control mode")
        return self
