"""Frozen facts about a robot description (URDF or MJCF), each with its source line.

This is everything robospec needs to know about a robot to check a spec: nothing after the
resolve stage touches the XML again.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from robospec.geometry import Pose

JointType = Literal[
    "revolute", "continuous", "prismatic", "fixed", "floating", "planar", "free", "ball"
]
# Joint types that add degrees of freedom SAPIEN exposes in qpos (one per joint).
ACTIVE_JOINT_TYPES: frozenset[str] = frozenset({"revolute", "continuous", "prismatic"})


@dataclass(frozen=True)
class Mimic:
    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class Coupling:
    """MJCF: a joint the model ties to another, which ManiSkill's loader lets loose (it reads
    no ``<equality>`` or ``<tendon>``): ``follower = multiplier * leader + offset``, as a mimic
    controller holds it. ``line``: the element that ties them."""

    follower: str
    mimic: Mimic
    line: int
    what: str  # "tendon 'T_FFJ1c'", for messages


@dataclass(frozen=True)
class Closure:
    """MJCF: a closed loop the model states as an ``<equality>`` between two bodies, which
    ManiSkill's loader leaves open (a PhysX articulation is a tree). ``connect``: a point of
    ``first`` (``anchor``, in its frame) held on ``second`` where it is at the model's initial
    pose; ``weld``: the two frames held as they are there (``anchor`` in ``second``'s frame, as
    MuJoCo reads it). A site names its body and the point. ``line``: the element."""

    kind: Literal["connect", "weld"]
    first: str
    second: str
    anchor: tuple[float, float, float]
    line: int


@dataclass(frozen=True)
class Link:
    name: str
    line: int
    # the description gives it shapes to collide with: a URDF link's <collision>, the <geom>s of
    # the MJCF body it is (not a dummy link ManiSkill adds for a body's other joints)
    shaped: bool = False


@dataclass(frozen=True)
class Joint:
    name: str
    type: JointType
    parent: str
    child: str
    line: int
    lower: float | None = None  # None: unbounded (continuous joints, free MJCF joints)
    upper: float | None = None
    mimic: Mimic | None = None
    # <limit velocity= effort=> (URDF); None when the description does not give them
    velocity: float | None = None
    effort: float | None = None

    @property
    def is_active(self) -> bool:
        return self.type in ACTIVE_JOINT_TYPES


@dataclass(frozen=True)
class MeshFile:
    """A file a URDF's visual or collision names (a mesh, or a visual's texture)."""

    uri: str  # as the description writes it
    role: Literal["collision", "visual", "texture"]
    line: int
    # where robospec found it (absolute; package:// the ROS way), None when it did not
    path: str | None
    # the file SAPIEN's URDF loader opens for it from the description's folder, or None
    loader_path: str | None


@dataclass(frozen=True)
class FileKeyframe:
    """A keyframe the description itself defines (an MJCF ``<key>``), in ManiSkill's terms."""

    name: str  # the key's name, or "key<i>" (its index among the keys) when it has none
    line: int
    # each active joint of the robot -> its position, in qpos order (ManiSkill's zero: MuJoCo's
    # qpos minus the joint's ref)
    qpos: tuple[tuple[str, float], ...]
    # the free joint's part of the key: the world pose of the robot's root body (as a
    # keyframe's ``pose`` means it for an MJCF robot); None when the root is not free
    root_pose: Pose | None = None
    qvel: tuple[tuple[str, float], ...] = ()


@dataclass(frozen=True)
class Actuator:
    """An MJCF actuator. ManiSkill loads none (a spec's controllers drive the joints); these
    are the gains and ranges the model was tuned with."""

    name: str
    line: int
    type: str  # the element: position, motor, velocity, general, intvelocity, damper, ...
    joint: str | None  # the joint it drives; None for tendon, site and body transmissions
    # a position servo's gains: force = kp * (ctrl - q) - kv * qdot (general actuators whose
    # gain and bias make one count); None where the actuator is not one
    kp: float | None = None
    kv: float | None = None
    ctrl_range: tuple[float, float] | None = None  # when ctrl is limited
    force_range: tuple[float, float] | None = None  # when force is limited
    gear: float = 1.0


@dataclass(frozen=True)
class RobotDescription:
    """A parsed robot description.

    ``active_joints`` lists the joints in exactly the order SAPIEN/ManiSkill uses for qpos,
    so a keyframe written by joint name can be turned into the ordered array ManiSkill expects.
    """

    kind: Literal["urdf", "mjcf"]
    path: str  # the file as the user's spec names it after expansion (for messages)
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    active_joint_names: tuple[str, ...]
    root_link: str
    # True when the root is attached to the world by a floating/free joint (MJCF freejoint).
    floating_root: bool = False
    # a stand-in built from the spec's own names: the real file is not downloaded yet
    assumed: bool = False
    # group-2 collision bits ManiSkill's loader sets by itself, each with the links that carry
    # it: an SRDF's "Default" disable_collisions pairs (URDF), every body with its parent body
    # (MJCF). Links sharing one of these bits never collide with each other.
    loader_collision_bits: tuple[tuple[int, tuple[str, ...]], ...] = ()
    # the mesh and texture files a URDF names, when they were looked for (see description.meshes)
    mesh_files: tuple[MeshFile, ...] = ()
    # MJCF: the fixed joints ManiSkill makes, without a name, for bodies without joints
    unnamed_joints: tuple[Joint, ...] = ()
    # MJCF: the root body's pose in the world as MuJoCo places it (its free joint's qpos0), and
    # where that body's frame sits in ManiSkill's root link (identity when the loader skips it
    # as a mere wrapper). None for URDF.
    root_body_pose: Pose | None = None
    root_body_offset: Pose | None = None
    # MJCF: the model's <key> keyframes and actuators
    keyframes: tuple[FileKeyframe, ...] = ()
    actuators: tuple[Actuator, ...] = ()
    # MJCF: pairs of joints its <equality> or fixed <tendon>s tie together (robospec new drives
    # each pair with a pd_joint_pos_mimic controller, as it does a URDF's <mimic>)
    couplings: tuple[Coupling, ...] = ()
    # MJCF: the closed loops its <equality connect/weld> state (robospec new writes `loops`)
    closures: tuple[Closure, ...] = ()
    # MJCF: the robot's bodies a <weld> holds to a mocap body: the mocap moves them, and so
    # drives the joints between them and the root (robospec new gives those joints drives)
    mocap_welds: tuple[str, ...] = ()
    # MJCF: pairs of links (sorted) MuJoCo never lets collide (their geoms' contype and
    # conaffinity, a <contact><exclude>) and ManiSkill collides (robospec new declares them
    # never_collide where bits allow)
    filtered_pairs: tuple[tuple[str, str], ...] = ()
    # an MJCF compiled by MuJoCo: each joint's armature (the rotor inertia MuJoCo adds to its
    # degree of freedom; each hinge of a ball joint its own), which a URDF cannot say and the
    # agent sets through SAPIEN (PhysxArticulationJoint.set_armature)
    armature: tuple[tuple[str, float], ...] = ()
    _links_by_name: dict[str, Link] = field(default_factory=dict, repr=False, compare=False)
    _joints_by_name: dict[str, Joint] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._links_by_name.update({link.name: link for link in self.links})
        self._joints_by_name.update({joint.name: joint for joint in self.joints})

    def link(self, name: str) -> Link | None:
        return self._links_by_name.get(name)

    def joint(self, name: str) -> Joint | None:
        return self._joints_by_name.get(name)

    @property
    def link_names(self) -> tuple[str, ...]:
        return tuple(link.name for link in self.links)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(joint.name for joint in self.joints)

    def adjacent_pairs(self) -> frozenset[tuple[str, str]]:
        """Pairs of links (each sorted) joined by a joint: PhysX never collides a link with its
        parent in an articulation, whatever the collision groups say."""
        return frozenset(
            (min(j.parent, j.child), max(j.parent, j.child))
            for j in (*self.joints, *self.unnamed_joints)
            if j.parent and j.child and j.parent != j.child
        )

    @property
    def tree_joints(self) -> tuple[Joint, ...]:
        """Every joint that attaches a link to its parent, named or not, in link order."""
        order = {link.name: i for i, link in enumerate(self.links)}
        return tuple(
            sorted((*self.joints, *self.unnamed_joints), key=lambda j: order.get(j.child, 0))
        )

    @property
    def active_joints(self) -> tuple[Joint, ...]:
        return tuple(self._joints_by_name[name] for name in self.active_joint_names)
