"""The spec, version 1: everything a ManiSkill ``BaseAgent`` subclass declares, as data.

Pure data and local rules only: no file is read here. References into the robot description
(joint and link names) are bound later, in :mod:`robospec.resolve`.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, StrictBool, model_validator

from robospec.diagnostics.codes import MJCF_JOINT_ATTRIBUTES
from robospec.model import rules
from robospec.model.check_settings import Checks
from robospec.model.common import (
    GroupSelection,
    JointSelection,
    LinkPatterns,
    LinkSelection,
    Number,
    Pose,
    StrictModel,
    ValueByName,
    Vector3,
)
from robospec.model.controllers import ControllerConfig
from robospec.model.mechanisms import Loop, MobileBase, Touch
from robospec.model.members import (
    Drive,
    Grasping,
    Hooks,
    IsFallen,
    IsStanding,
    IsStatic,
    LinkState,
    Member,
    NamedLink,
    PythonName,
    PythonRef,
    Reset,
    Tcp,
)
from robospec.model.mends import Mends
from robospec.model.names import NAME_PATTERN, PREFIX_PATTERN, UID_PATTERN
from robospec.model.refs import (
    ControllerName,
    JointPattern,
    LinkName,
    LinkOrNamed,
    LinkPattern,
    LinkStateName,
    MaterialName,
    MountLink,
)

ScalarArg = str | int | float | bool


class Description(StrictModel, rules.DescriptionBehaviour):
    """The robot description file: exactly one of `urdf`, `mjcf` or `xacro`. Relative paths
    are taken against the spec file's folder; `{maniskill_assets}` stands for ManiSkill's
    bundled asset folder."""

    urdf: str | None = Field(
        default=None,
        description="A URDF file.",
        examples=["{maniskill_assets}/robots/panda/panda_v2.urdf"],
    )
    mjcf: str | None = Field(
        default=None,
        description="A MuJoCo MJCF file.",
        examples=["{maniskill_assets}/robots/humanoid/humanoid.xml"],
    )
    xacro: str | None = Field(
        default=None,
        description="A xacro file, expanded to URDF with `args` (expanding runs the file's "
        "code, in a child process with limits).",
        examples=["robots/twolink/twolink.urdf.xacro"],
    )
    args: dict[
        str,
        Annotated[
            ScalarArg,
            Field(description="The value of one xacro argument.", examples=[0.35]),
        ],
    ] = Field(
        default_factory=dict,
        description="Arguments for a xacro description (name := value).",
        examples=[{"prefix": "twolink_", "link_length": 0.35}],
    )
    packages: dict[
        str,
        Annotated[
            str,
            Field(
                description="The folder of one ROS package (the one holding its package.xml "
                "and meshes): relative to this spec file, or starting with "
                "`{maniskill_assets}`.",
                examples=["../kuka_description/kuka_kr16"],
            ),
        ],
    ] = Field(
        default_factory=dict,
        description="Where the ROS packages the description names are (`package://NAME/...` "
        "mesh URIs, xacro's `$(find NAME)`), by package name. Needed only for packages "
        "robospec does not find by itself, looking from the description's folder up for a "
        "folder whose package.xml names the package, or a folder of that name holding the "
        "files.",
        examples=[{"kuka_kr16_support": "../kuka_description/kuka_kr16"}],
    )
    download: list[Annotated[str, Field(pattern=NAME_PATTERN)]] = Field(
        default_factory=list,
        description="ManiSkill asset download ids (`register_agent(asset_download_ids=...)`); "
        "a spec whose description is not downloaded yet is checked without it.",
        examples=[["unitree_g1"]],
    )
    mend: Mends | None = Field(
        default=None,
        description="Mends robospec applies to a derived copy of the description (the file "
        "itself is never written), by class: what the loaders would stop at or read wrongly, "
        "each change reported where it was made. `robospec new` writes the ones a robot needs.",
        examples=[{"inertia": "diagonal", "transmissions": "drop"}],
    )
    loader: Literal["maniskill", "mujoco"] | None = Field(
        default=None,
        description="How an MJCF becomes the robot: `maniskill` (the default), ManiSkill's "
        "own MJCF loader; `mujoco`, compiled by MuJoCo and written as a derived URDF that "
        "ManiSkill's URDF loader reads, with MuJoCo's masses and inertias, every body and "
        "ball joints (what a URDF cannot carry is a warning, RS791).",
        examples=["mujoco"],
    )
    sites: list[Annotated[str, Field(min_length=1)]] = Field(
        default_factory=list,
        description="With `loader: mujoco`: MJCF sites of the robot's bodies written as links "
        "of their own, fixed to their body where the site sits (1 g each), so the spec can "
        "name them where it names a link: the `tcp`, a camera's `mount`, a named link.",
        examples=[["grasp"]],
    )

    _exactly_one = model_validator(mode="after")(rules.one_description)


class Loader(StrictModel):
    """How ManiSkill loads the articulation (BaseAgent class attributes)."""

    fix_root_link: bool = Field(
        default=True,
        description="Fix the root link in place; false for robots that stand or fall freely "
        "(humanoids, quadrupeds).",
        examples=[True],
    )
    load_multiple_collisions: bool = Field(
        default=False,
        description="Load collision meshes made of several convex parts as multiple shapes.",
        examples=[True],
    )
    disable_self_collisions: bool = Field(
        default=False,
        description="Disable all collisions between the robot's own links.",
        examples=[True],
    )


class Material(StrictModel):
    """A physical material: PhysX friction and restitution, given to links by `links` rules."""

    static_friction: Number = Field(
        description="Friction coefficient while surfaces stick.", examples=[2.0]
    )
    dynamic_friction: Number = Field(
        description="Friction coefficient while surfaces slide.", examples=[2.0]
    )
    restitution: Number = Field(
        default=0.0,
        description="Bounciness, from 0 (none) to 1 (perfectly elastic).",
        examples=[0.0],
    )


class LinkRule(StrictModel):
    """Physical properties for the links a name or glob matches."""

    material: MaterialName | None = Field(
        default=None,
        description="A material from `materials` for the links' collision shapes.",
        examples=["gripper"],
    )
    patch_radius: Number | None = Field(
        default=None,
        description="Radius of the contact patch used for torsional friction, in m.",
        examples=[0.1],
    )
    min_patch_radius: Number | None = Field(
        default=None,
        description="Smallest contact patch radius for torsional friction, in m.",
        examples=[0.1],
    )
    density: Number | None = Field(
        default=None,
        description="Density of the links' collision shapes, in kg/m³.",
        examples=[1000],
    )


JointValue = Annotated[
    Number | list[Number],
    Field(
        description="One value for every joint selected, or one per joint in order.",
        examples=[0.04, [0, "pi/8"]],
    ),
]
# the map first: yaml-language-server blames a failing anyOf on its first branch, and a
# misspelled joint key should be reported as that, not as "not a list"
JointValues = dict[JointPattern, JointValue] | list[Number]


class Keyframe(StrictModel):
    """A named robot state: root pose, joint positions and velocities."""

    pose: Pose = Field(
        default_factory=Pose,
        description="The pose of the robot's root in the world.",
        examples=[{"p": [0, 0, 0]}],
    )
    qpos: JointValues | None = Field(
        default=None,
        description="Joint positions: all active joints in order, or by joint, group or glob name.",
        examples=[{"arm": [0, "pi/8", 0, "-5*pi/8", 0, "3*pi/4", "pi/4"], "gripper": 0.04}],
    )
    qvel: JointValues | None = Field(
        default=None,
        description="Joint velocities, written like `qpos`; default: zero.",
        examples=[{"arm": 0.0}],
    )


Matrix3 = Annotated[list[Vector3], Field(min_length=3, max_length=3)]


class Camera(StrictModel):
    """A camera mounted on a link."""

    mount: LinkName = Field(
        description="The link the camera is mounted on; it moves with it.",
        examples=["camera_link"],
    )
    pose: Pose = Field(
        default_factory=Pose,
        description="The camera's pose relative to the mount link (x forward, z up).",
        examples=[{"p": [0, 0, 0], "q": [1, 0, 0, 0]}],
    )
    width: Annotated[int, Field(gt=0, le=16384)] = Field(
        description="Image width in pixels.", examples=[128]
    )
    height: Annotated[int, Field(gt=0, le=16384)] = Field(
        description="Image height in pixels.", examples=[128]
    )
    fov: Number | None = Field(
        default=None,
        description="Vertical field of view in radians; give this or `intrinsic`.",
        examples=["pi/2"],
    )
    intrinsic: Matrix3 | None = Field(
        default=None,
        description="The 3x3 intrinsic matrix, instead of `fov`.",
        examples=[[[64, 0, 64], [0, 64, 64], [0, 0, 1]]],
    )
    near: Number = Field(default=0.01, description="Near clipping plane, in m.", examples=[0.01])
    far: Number = Field(default=100.0, description="Far clipping plane, in m.", examples=[100])
    shader_pack: Literal["minimal", "default", "rt", "rt-med", "rt-fast"] = Field(
        default="minimal",
        description="SAPIEN's shader pack: `minimal` is fastest; `rt*` are ray traced.",
        examples=["default"],
    )


class CollisionRule(StrictModel):
    """Set one collision-group bit on some links (`link.set_collision_group_bit`), e.g. so a
    mobile base does not collide with the ground."""

    links: LinkPatterns = Field(
        description="The links: names, globs, or a list of them.",
        examples=[["l_wheel_link", "r_wheel_link"]],
    )
    group: Annotated[int, Field(ge=0, le=3)] = Field(
        description="Collision group index, 0 to 3.", examples=[2]
    )
    bit: Annotated[int, Field(ge=0, le=31)] = Field(
        description="Bit index within the group, 0 to 31.", examples=[30]
    )
    value: Literal[0, 1] = Field(
        default=1, description="The value to set the bit to.", examples=[1]
    )


class Part(StrictModel, rules.PartBehaviour):
    """Another robot mounted on this one, e.g. a gripper or a hand on an arm: a spec (its
    groups, controllers, keyframes, tcp, grasping, materials and link rules come along) or a
    bare description, fixed to a link of this robot. robospec writes the combined description;
    a name of the part that this robot already has is prefixed (and the prefix reported)."""

    spec: str | None = Field(
        default=None,
        description="The part's spec file (YAML or TOML), relative to this spec file.",
        examples=["ability_hand_right.yaml"],
    )
    description: Description | None = Field(
        default=None,
        description="The part's description, when it has no spec: its joints are then driven "
        "by this spec's controllers.",
        examples=[{"urdf": "{maniskill_assets}/robots/ability_hand/ability_hand_right.urdf"}],
    )
    at: MountLink = Field(
        description="The link of this robot (or of another part) the part is fixed to.",
        examples=["link7"],
    )
    pose: Pose = Field(
        default_factory=Pose,
        description="Where the part's root link sits in the frame of `at`.",
        examples=[{"p": [0, 0, 0], "rpy": [0, 0, "pi/2"]}],
    )
    joint: Annotated[str, Field(pattern=NAME_PATTERN)] | None = Field(
        default=None,
        description="The name of the fixed joint that mounts the part; default: `<part>_mount`.",
        examples=["hand_joint"],
    )
    fold_frames: bool = Field(
        default=False,
        description="Leave out the empty frames at the seam, as hand-made combinations do: a "
        "mount link that is an empty leaf frame (a flange such as `link_eef` or `tool0`) gives "
        "its place to the part, its joint now holding the part's root; a root that is an "
        "empty frame fixed to one link is left out, that link mounted instead. Their poses go "
        "into the mounting joint (SAPIEN would give each empty link 1e-6 kg).",
        examples=[True],
    )
    prefix: Annotated[str, Field(pattern=PREFIX_PATTERN)] | None = Field(
        default=None,
        description="What goes before each name of the part that the robot already has "
        "(links, joints, controllers, ...); default: `<part>_`. Names that do not clash are "
        "kept as they are.",
        examples=["hand_"],
    )
    mode: Annotated[str, Field(pattern=NAME_PATTERN)] | None = Field(
        default=None,
        description="The part's control mode whose controllers join each of this robot's "
        "control modes (a mode that already drives the part's joints is left as it is); "
        "default: the part's first.",
        examples=["pd_joint_delta_pos"],
    )

    _spec_or_description = model_validator(mode="after")(rules.one_part_source)


class Simulation(StrictModel):
    """How the robot simulates beyond its description: PhysX settings the agent applies to
    its own shapes, and the sim config it recommends for `gym.make` (`robospec optimize
    --profile fast` writes this section)."""

    profile: Literal["fast"] | None = Field(
        default=None,
        description="The `robospec optimize` profile that wrote this spec, which changes how "
        "the robot collides for speed (see docs/optimize.md); informational.",
        examples=["fast"],
    )
    category: Literal["manipulation", "locomotion"] | None = Field(
        default=None,
        description="What the robot is for, which the recommended solver iterations follow: "
        "manipulation (15 or more) or locomotion (about 4).",
        examples=["manipulation"],
    )
    contact_offset: Annotated[Number, Field(gt=0)] | None = Field(
        default=None,
        description="PhysX contact offset of every collision shape of the robot, in m, set "
        "by the agent after loading (ManiSkill's scenes give every shape 0.02). Two shapes "
        "make contacts once they are nearer than the sum of their offsets: a small offset "
        "stops neighbouring links that never touch from making contacts.",
        examples=[0.002],
    )
    solver_position_iterations: Annotated[int, Field(ge=1, le=255)] | None = Field(
        default=None,
        description="The PhysX solver position iterations recommended for this robot "
        "(`sim_config_for(uid)`; ManiSkill's default is 15).",
        examples=[4],
    )
    solver_velocity_iterations: Annotated[int, Field(ge=0, le=255)] | None = Field(
        default=None,
        description="The PhysX solver velocity iterations recommended for this robot "
        "(`sim_config_for(uid)`; ManiSkill's default is 1).",
        examples=[1],
    )
    armature: dict[JointPattern, Annotated[ValueByName, Field(ge=0)]] = Field(
        default_factory=dict,
        description="Rotor inertia added to joints (kg m², kg for a slide), by joint name, "
        "glob or group, set by the agent after loading through SAPIEN (a URDF has no element "
        "for it). An MJCF with `loader: mujoco` brings its joints' armature without this; "
        "values here replace it.",
        examples=[{"panda_joint*": 0.1}],
    )


_GRIPPER_MATERIAL = {"static_friction": 2.0, "dynamic_friction": 2.0, "restitution": 0.0}
_FINGER = {"material": "gripper", "patch_radius": 0.1, "min_patch_radius": 0.1}
_REST = {"qpos": {"arm": [0, "pi/8", 0, "-5*pi/8", 0, "3*pi/4", "pi/4"], "gripper": 0.04}}
_ARM_POS = {
    "type": "pd_joint_pos",
    "joints": "arm",
    "lower": None,
    "upper": None,
    "stiffness": 1e3,
    "damping": 1e2,
    "force_limit": 100,
    "normalize_action": False,
}
_HAND_CAMERA = {
    "mount": "camera_link",
    "pose": {"p": [0, 0, 0], "q": [1, 0, 0, 0]},
    "width": 128,
    "height": 128,
    "fov": "pi/2",
}
_GRASP = {
    "fingers": [
        {"link": "finger1_link", "opening": "+y"},
        {"link": "finger2_link", "opening": "-y"},
    ],
    "min_force": 0.5,
    "max_angle": 85,
}
_TIP_POSES = {"links": "tip_links", "quantity": "pose", "stack_dim": -2}
_LOOP = {
    "links": ["left_inner_knuckle", "left_inner_finger"],
    "at": [[0, 0.0376, 0.043], [0, -0.0179, 0.0065]],
}
# examples from the Panda spec (specs/maniskill/panda.yaml) and the zoo, shown by editors


ModeEntry = Annotated[
    ControllerName | StrictBool,
    Field(
        description="The controller for this part of the robot (or, under "
        "balance_passive_force, whether to balance passive forces).",
        examples=["arm_pos"],
    ),
]
ControlMode = ControllerName | dict[str, ModeEntry]
"""A single controller name, or ``{group: controller, ..., balance_passive_force: bool}``."""

Name = Annotated[str, Field(pattern=NAME_PATTERN)]


MaterialEntry = Annotated[
    Material,
    Field(description="A material, referred to by its name.", examples=[_GRIPPER_MATERIAL]),
]

LinkRuleEntry = Annotated[
    LinkRule,
    Field(description="Properties for the links this name or glob matches.", examples=[_FINGER]),
]

GroupEntry = Annotated[
    GroupSelection,
    Field(
        description="The joints of one group: names, globs, other groups, or {all_but: ...}.",
        examples=["panda_joint[1-7]"],
    ),
]

KeyframeEntry = Annotated[Keyframe, Field(description="A robot state by name.", examples=[_REST])]

ControlModeEntry = Annotated[
    ControlMode,
    Field(
        description="One controller, or {name: controller, ...} with optional "
        "balance_passive_force: true/false.",
        examples=[{"arm": "arm_pos", "gripper": "gripper"}],
    ),
]

CameraEntry = Annotated[Camera, Field(description="A camera by its uid.", examples=[_HAND_CAMERA])]

NeverCollideEntry = Annotated[
    LinkPatterns,
    Field(
        description="Links no two of which collide: a pair, a glob, or a list of names and globs.",
        examples=[["panda_link5", "panda_hand"]],
    ),
]

# a ManiSkill task id ("PickCube-v1") or a folder of them ("tabletop")
TaskName = Annotated[
    str,
    Field(
        pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,99}$",
        description="A ManiSkill task id, or the folder of tasks under mani_skill/envs/tasks.",
        examples=["PickCube-v1", "tabletop"],
    ),
]
NamedLinkEntry = Annotated[
    NamedLink, Field(description="A link, or a list of links.", examples=["panda_leftfinger"])
]

GraspingEntry = Annotated[
    Grasping, Field(description="A grasp check by its method name.", examples=[_GRASP])
]

PartEntry = Annotated[
    Part,
    Field(
        description="A robot mounted on this one, by a name of its own.",
        examples=[{"spec": "ability_hand_right.yaml", "at": "link7"}],
    ),
]

LinkStateEntry = Annotated[
    LinkState,
    Field(description="A property reading link poses or velocities.", examples=[_TIP_POSES]),
]


class Spec(StrictModel):
    """A robot for ManiSkill, version 1: a robospec spec compiles to a registered ManiSkill
    agent (a `BaseAgent` subclass)."""

    robospec: Literal[1] = Field(description="The spec format version; always 1.", examples=[1])
    uid: Annotated[str, Field(pattern=UID_PATTERN)] = Field(
        description="The agent uid passed to gym.make(robot_uids=...).", examples=["rs_panda"]
    )
    override: bool = Field(
        default=False,
        description="Replace an agent already registered under this uid (e.g. ManiSkill's "
        "'panda', so tasks that choose poses by uid use this robot).",
        examples=[True],
    )
    extends: PythonRef | None = Field(
        default=None,
        description="A Python agent class to subclass ('module:Class'); the spec then "
        "overrides only the data it declares.",
        examples=["mani_skill.agents.robots.panda.panda:Panda"],
    )
    class_name: PythonName | None = Field(
        default=None,
        description="The Python class name; default: derived from uid.",
        examples=["RsPanda"],
    )
    description: Description | None = Field(
        default=None,
        description="The robot description file; optional only with `extends`.",
        examples=[{"urdf": "{maniskill_assets}/robots/panda/panda_v2.urdf"}],
    )
    parts: dict[Name, PartEntry] = Field(
        default_factory=dict,
        description="Robots mounted on this one (a gripper or a hand on an arm), each a spec "
        "or a description fixed to a link; robospec writes the combined description.",
        examples=[{"hand": {"spec": "ability_hand_right.yaml", "at": "link7"}}],
    )
    loader: Loader = Field(
        default_factory=Loader,
        description="How ManiSkill loads the articulation.",
        examples=[{"fix_root_link": True, "disable_self_collisions": False}],
    )
    materials: dict[
        Name,
        MaterialEntry,
    ] = Field(
        default_factory=dict,
        description="Physical materials by name, for `links` rules to use.",
        examples=[{"gripper": _GRIPPER_MATERIAL}],
    )
    links: dict[
        LinkPattern,
        LinkRuleEntry,
    ] = Field(
        default_factory=dict,
        description="Link rules by link name or glob; each must match a link.",
        examples=[{"panda_*finger": _FINGER}],
    )
    groups: dict[
        Name,
        GroupEntry,
    ] = Field(
        default_factory=dict,
        description="Named joint selections, usable wherever joints are named.",
        examples=[
            {"arm": "panda_joint[1-7]", "gripper": ["panda_finger_joint1", "panda_finger_joint2"]}
        ],
    )
    passive_joints: JointSelection | None = Field(
        default=None,
        description="Joints no control mode needs to drive (otherwise an undriven joint is "
        "an error).",
        examples=[["caster_joint"]],
    )
    keyframes: dict[Name, KeyframeEntry] = Field(
        default_factory=dict,
        description="Named robot states (root pose, joint positions and velocities).",
        examples=[{"rest": _REST}],
    )
    reset: Reset = Field(
        default_factory=Reset,
        description="Where every episode starts: the keyframe the agent resets its joints to "
        "(ManiSkill's tasks reset only the robots they know), with optional noise.",
        examples=[{"keyframe": "rest", "qpos_noise": 0.02, "noise_joints": "arm"}],
    )
    controllers: dict[
        Name,
        Annotated[
            ControllerConfig,
            Field(
                description="A controller config; `type` says which ManiSkill controller, "
                "`extends` builds on another controller.",
                examples=[_ARM_POS],
            ),
        ],
    ] = Field(
        default_factory=dict,
        description="Controller configs by name, defined once and reused by control modes.",
        examples=[{"arm_pos": _ARM_POS}],
    )
    control_modes: dict[
        Name,
        ControlModeEntry,
    ] = Field(
        default_factory=dict,
        description="Control modes by name, in order; the first is the default. Required "
        "unless `extends` gives them.",
        examples=[{"pd_joint_pos": {"arm": "arm_pos", "gripper": "gripper"}}],
    )
    cameras: dict[Name, CameraEntry] = Field(
        default_factory=dict,
        description="Cameras by uid, each mounted on a link.",
        examples=[{"hand_camera": _HAND_CAMERA}],
    )
    collision_rules: list[CollisionRule] = Field(
        default_factory=list,
        description="Collision-group bits to set on links, e.g. so wheels ignore the ground.",
        examples=[[{"links": ["l_wheel_link", "r_wheel_link"], "group": 2, "bit": 30}]],
    )
    never_collide: list[NeverCollideEntry] = Field(
        default_factory=list,
        description="Links that must never collide: each entry is a list of link names or "
        "globs, no two of which collide (a pair, or a clique); packed into the fewest "
        "collision-group bits.",
        examples=[[["panda_link5", "panda_hand"], "panda_*finger"]],
    )
    scene_collision_bits: list[Annotated[int, Field(ge=0, le=31)]] = Field(
        default_factory=list,
        description="Collision-group-2 bits the scenes this robot is used in set on their own "
        "objects; never_collide leaves them free (ManiSkill's bits 29-31 are always left free).",
        examples=[[28]],
    )
    tcp: LinkOrNamed | Tcp | None = Field(
        default=None,
        description="The tool centre point: a link, or a link/midpoint mapping.",
        examples=["panda_hand_tcp"],
    )
    named_links: dict[
        Member,
        NamedLinkEntry,
    ] = Field(
        default_factory=dict,
        description="Agent attributes bound to links after loading (e.g. finger1_link).",
        examples=[{"finger1_link": "panda_leftfinger", "finger2_link": "panda_rightfinger"}],
    )
    grasping: dict[Member, GraspingEntry] = Field(
        default_factory=dict,
        description="Two-finger grasp checks by method name (e.g. is_grasping).",
        examples=[{"is_grasping": _GRASP}],
    )
    is_static: IsStatic | None = Field(
        default=None,
        description="Defines `is_static(threshold)`: the selected joints are nearly still.",
        examples=[{"joints": "arm", "threshold": 0.2}],
    )
    is_standing: IsStanding | None = Field(
        default=None,
        description="Defines `is_standing()`: the root is in a height band (and upright).",
        examples=[{"height": {"above": 0.5, "below": 1.0}}],
    )
    is_fallen: IsFallen | None = Field(
        default=None,
        description="Defines `is_fallen()`: the root is low, or some links touch something.",
        examples=[{"height": {"below": 0.3}}],
    )
    link_states: dict[
        Member,
        LinkStateEntry,
    ] = Field(
        default_factory=dict,
        description="Properties reading link poses or velocities, by name.",
        examples=[{"tip_poses": _TIP_POSES}],
    )
    proprioception: list[LinkStateName] = Field(
        default_factory=list,
        description="`link_states` entries added to get_proprioception, in order.",
        examples=[["tip_poses"]],
    )
    disable_gravity: LinkSelection | None = Field(
        default=None,
        description="Links that ignore gravity (e.g. all but a quadruped's root).",
        examples=[{"all_but": "base_link"}],
    )
    drives: list[Drive] = Field(
        default_factory=list,
        description="Drives that close kinematic loops between two links (e.g. a Robotiq "
        "gripper's linkage).",
        examples=[[{"parent": "left_outer_finger", "child": "left_inner_finger_pad"}]],
    )
    loops: dict[
        Name,
        Annotated[
            Loop,
            Field(
                description="A closed loop by name: two links and where they meet.",
                examples=[_LOOP],
            ),
        ],
    ] = Field(
        default_factory=dict,
        description="Closed kinematic loops (a four-bar gripper's linkages, MJCF `connect` "
        "and `weld` equalities), each closed by a drive after loading; the loops' joints no "
        "controller drives are passive.",
        examples=[{"left_linkage": _LOOP}],
    )
    mobile_base: MobileBase | None = Field(
        default=None,
        description="A drivable planar base: x and y slides and a z hinge added above the base "
        "link in a derived copy of the description, a `pd_base_vel` controller in every "
        "control mode, the wheels out of the floor's collisions.",
        examples=[{"link": "base_link", "wheels": "*_wheel_link"}],
    )
    touch: Touch | None = Field(
        default=None,
        description="Force-sensing links: defines `get_fsr_impulse()` and "
        "`get_fsr_obj_impulse(obj)`, and optionally adds the readings to the proprioception.",
        examples=[{"links": ["link_base_fsr", "link_3.0_tip_fsr"], "proprioception": True}],
    )
    hooks: Hooks = Field(
        default_factory=Hooks,
        description="Python functions and members for what no declaration covers.",
        examples=[{"after_init": "my_robots.hooks:after_init"}],
    )
    tasks: list[TaskName] = Field(
        default_factory=list,
        description="ManiSkill tasks the robot is meant for: task ids, or a folder of them "
        "(`tabletop`). `robospec validate` says which agent members they call that the spec "
        "does not define; `robospec check --task` runs them.",
        examples=[["PickCube-v1", "PushCube-v1"]],
    )
    simulation: Simulation = Field(
        default_factory=Simulation,
        description="PhysX settings for the robot's own shapes and the sim config it "
        "recommends (`sim_config_for(uid)`).",
        examples=[{"contact_offset": 0.002, "solver_position_iterations": 15}],
    )
    checks: Checks = Field(
        default_factory=Checks,
        description="Thresholds of `robospec check` for this robot.",
        examples=[{"keyframe_hold": {"pin_root": True}}],
    )
    silence: list[Annotated[str, Field(pattern=r"^RS[0-9]{3}$")]] = Field(
        default_factory=list,
        description="Warning codes not to report for this spec, where the warned-of thing is "
        "meant (the ground's collision bits on a mobile base, say), by validate and the other "
        "commands, check's simulation included; an error cannot be silenced.",
        examples=[[MJCF_JOINT_ATTRIBUTES]],
    )

    _description_or_base = model_validator(mode="after")(rules.description_or_base)
