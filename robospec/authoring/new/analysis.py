"""Everything ``robospec new`` reads from a robot description before it writes a line: the
kind of body (:mod:`robospec.kinematics.morphology`), the groups (:mod:`.groups`), and for MJCF
the actuators' gains (:mod:`.gains`) and the file's own keyframes. No simulation: that is
:mod:`.rest_pose`'s."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from robospec.authoring.description_file import DescriptionFile
from robospec.authoring.new.gains import Drive, actuator_drives
from robospec.authoring.new.groups import Groups, MimicLink, guess_groups
from robospec.authoring.new.joint_loads import Inertial, mjcf_inertials, urdf_inertials
from robospec.authoring.new.linkages import FoundLoop, find_loops
from robospec.description import Joint, RobotDescription
from robospec.description.numbers import finite_numbers
from robospec.geometry import IDENTITY, Quaternion
from robospec.kinematics.forward import KinematicModel, kinematics_of
from robospec.kinematics.mjcf_model import read_mjcf_model
from robospec.kinematics.morphology import Morphology, morphology

_HALF = math.sqrt(0.5)
# the turn that takes each horizontal principal axis (index, positive?) of a root frame to +z
_TO_Z_UP: dict[tuple[int, bool], Quaternion] = {
    (1, True): (_HALF, _HALF, 0.0, 0.0),  # a quarter turn about x: y to z
    (1, False): (_HALF, -_HALF, 0.0, 0.0),
    (0, True): (_HALF, 0.0, -_HALF, 0.0),  # a quarter turn about -y: x to z
    (0, False): (_HALF, 0.0, _HALF, 0.0),
}

PASSIVE_GROUP = "passive"
IMMOBILE_GROUP = "immobile"
LINKAGE_GROUP = "linkage"  # a closed loop's followers: passive, the loop moves them
GRIPPER_GROUP = "gripper"


@dataclass(frozen=True)
class RobotAnalysis:
    source: DescriptionFile
    body: Morphology
    groups: Groups
    drives: dict[str, Drive] = field(default_factory=dict)  # MJCF actuators, by joint
    kinematics: KinematicModel | None = None
    inertials: dict[str, Inertial] = field(default_factory=dict)  # by link, as SAPIEN loads them
    armature: dict[str, float] = field(default_factory=dict)  # MJCF joints' armature, by joint
    loops: tuple[FoundLoop, ...] = ()  # the closed loops the description shows (.linkages)
    # the <mimic> rules of the loops' followers, which the loops stand in for: what sets them
    # with their drivers at rest
    linkage_mimic: tuple[MimicLink, ...] = ()

    @property
    def description(self) -> RobotDescription:
        return self.source.description

    @property
    def has_passive(self) -> bool:
        return "passive" in self.groups.kinds.values()

    def feet(self) -> list[list[str]]:
        """For each leg, the links below its last joint (where it meets the ground)."""
        if self.kinematics is None:
            return []
        children: dict[str, list[str]] = {}
        child_of = {}
        for joint in self.kinematics.joints:
            children.setdefault(joint.parent, []).append(joint.child)
            child_of[joint.name] = joint.child
        found = []
        for leg in self.body.legs:
            link = child_of.get(leg.joints[-1]) if leg.joints else None
            if link is None:
                continue
            links, queue = [link], [link]
            while queue:
                below = children.get(queue.pop(), [])
                links.extend(below)
                queue.extend(below)
            found.append(links)
        return found

    def upright(self, qpos: Mapping[str, float]) -> Quaternion:
        """The rotation (w, x, y, z) that stands a floating robot on its feet in ManiSkill's
        z-up world: identity for a description written z-up; for one written y-up (graphics'
        and motion capture's convention: pybullet's DeepMimic humanoid), the turn that takes
        its up axis to z — else its rest keyframe lays it on its side. Its up axis: the
        principal axis of the root frame nearest the direction from its feet (the frames where
        its legs end) to its centre of mass, at ``qpos``."""
        if not self.body.floating or self.kinematics is None:
            return IDENTITY
        poses = self.kinematics.at(qpos).links
        feet = [poses[foot[0]][:3, 3].tolist() for foot in self.feet() if foot and foot[0] in poses]
        if not feet:
            return IDENTITY
        mass = 0.0
        moment = [0.0, 0.0, 0.0]
        for link, inertial in self.inertials.items():
            if link in poses and inertial.mass > 0:
                point = (poses[link][:3, :3] @ inertial.com + poses[link][:3, 3]).tolist()
                mass += inertial.mass
                moment = [moment[i] + inertial.mass * point[i] for i in range(3)]
        centre = [m / mass for m in moment] if mass > 0 else [0.0, 0.0, 0.0]
        up = [centre[i] - sum(f[i] for f in feet) / len(feet) for i in range(3)]
        axis = max(range(3), key=lambda i: abs(up[i]))
        if axis == 2 or abs(up[axis]) < 2 * max(abs(up[i]) for i in range(3) if i != axis):
            # z-up, or feet above the body at this pose (Minitaur's legs fold up at 0: a pose,
            # not a convention), or no clear axis: as written
            return IDENTITY
        return _TO_Z_UP[(axis, up[axis] > 0)]

    def loop_joined_pairs(self) -> tuple[tuple[str, str], ...]:
        """The pairs of links the loops join (with the links welded to them), sorted."""
        from robospec.resolve.mechanisms import loop_joined

        pairs = loop_joined(self.description, [loop.links for loop in self.loops])
        return tuple(sorted(tuple(sorted(pair)) for pair in pairs))  # type: ignore[misc]

    def probe_mimic(self, start: Mapping[str, float]) -> list[MimicLink]:
        """The joint couplings the rest-pose search keeps: the mimic groups', the loops'
        followers with their drivers where the description relates them, and every other
        joint of a loop held where it starts (the search must not open a loop)."""
        links = [*self.groups.mimic, *self.linkage_mimic]
        related = {m.follower for m in links}
        for loop in self.loops:
            for joint in loop.joints:
                if joint not in related and (joint != loop.driver or not self.linkage_mimic):
                    links.append(MimicLink(joint, joint, 0.0, start.get(joint, 0.0)))
                    related.add(joint)
        return links

    def start_qpos(self) -> dict[str, float]:
        """0 where the limits allow (or there are none), else mid-range; mimic followers follow
        their leader, clamped into their limits."""
        qpos = {j.name: safe_position(j.lower, j.upper) for j in self.description.active_joints}
        for link in (*self.groups.mimic, *self.linkage_mimic):
            joint = self.description.joint(link.follower)
            assert joint is not None
            value = qpos[link.leader] * link.multiplier + link.offset
            low = -math.inf if joint.lower is None else joint.lower
            high = math.inf if joint.upper is None else joint.upper
            qpos[link.follower] = min(max(value, low), high)
        return {name: float(round(value, 6)) + 0.0 for name, value in qpos.items()}


def safe_position(lower: float | None, upper: float | None) -> float:
    if lower is None or upper is None or lower <= 0.0 <= upper:
        return 0.0
    return (lower + upper) / 2


def analyse(source: DescriptionFile) -> RobotAnalysis:
    drives: dict[str, Drive] = {}
    inertials: dict[str, Inertial] = {}
    armature: dict[str, float] = {}
    indirect = False
    if source.kind == "mjcf":
        # (compiled by MuJoCo: the joints' attributes are the file's, the masses the URDF's)
        model = read_mjcf_model(source.mjcf or source.text, str(source.path))
        if model is not None:
            attributes = {joint.name: joint.attributes for joint, _ in model.joints()}
            drives, indirect = actuator_drives(source.description, attributes)
            inertials = urdf_inertials(source.text) if source.loader else mjcf_inertials(model)
            armature = {
                name: value[0]
                for name, values in attributes.items()
                if (value := finite_numbers(values.get("armature"), 1))
            }
    else:
        inertials = urdf_inertials(source.text)
    kinematics = kinematics_of(source.description, source.text, str(source.path))
    body = morphology(source.description, kinematics)
    groups = guess_groups(source.description, body)
    mocap = mocap_driven(source.description)
    if (drives or mocap) and not indirect:
        _set_apart_passive(groups, set(drives) | mocap)
    _set_apart_immobile(groups, source.description)
    analysis = RobotAnalysis(source, body, groups, drives, kinematics, inertials, armature)
    loops = find_loops(analysis, analysis.start_qpos())
    if not loops:
        return analysis
    kept = _set_apart_linkage(groups, loops)
    if source.kind != "mjcf" and any(j.mimic for j in source.description.joints):
        # the loops' followers follow the linkage, not a <mimic> PhysX would simulate alone
        source = dataclasses.replace(source, mends={**source.mends, "mimic": "controller"})
    return dataclasses.replace(analysis, source=source, loops=loops, linkage_mimic=kept)


def _set_apart_linkage(groups: Groups, loops: tuple[FoundLoop, ...]) -> tuple[MimicLink, ...]:
    """The loops' followers leave their groups for one ``linkage`` group (passive: the loop
    moves them); the loops' drivers make the gripper, one mimic controller where the model
    couples them (both sides of a Robotiq), as ManiSkill's Robotiq agents drive it. Returns
    the followers' mimic rules, which no controller keeps any more."""
    drivers = list(dict.fromkeys(loop.driver for loop in loops))
    followers = {j for loop in loops for j in loop.joints} - set(drivers)
    moved = followers | set(drivers)
    order = [j for joints in groups.groups.values() for j in joints]
    for name in list(groups.groups):
        kept = [j for j in groups.groups[name] if j not in moved]
        if kept:
            groups.groups[name] = kept
        else:
            del groups.groups[name]
            del groups.kinds[name]
    # the followers' rules: the linkage's own where its shape says them (a parallelogram),
    # else the description's couplings
    shaped = [MimicLink(f, loop.driver, m, o) for loop in loops for f, m, o in loop.follows]
    ruled = {m.follower for m in shaped}
    linkage = (
        *shaped,
        *(m for m in groups.mimic if m.follower in followers and m.follower not in ruled),
    )
    groups.mimic[:] = [m for m in groups.mimic if m.follower in drivers and m.leader in drivers] + [
        m for m in groups.mimic if m.follower not in moved and m.leader not in moved
    ]
    coupled = any(m.follower in drivers for m in groups.mimic)
    name = GRIPPER_GROUP
    while name in groups.groups:
        name += "_"
    groups.add(name, "mimic" if coupled else "gripper", sorted(drivers, key=order.index))
    groups.add(LINKAGE_GROUP, "linkage", sorted(followers, key=order.index))
    return linkage


def mocap_driven(description: RobotDescription) -> set[str]:
    """The joints between the root and a body welded to a mocap body: MuJoCo moves them by
    moving the mocap (gym-xarm's arm has no actuator), so they are driven, not passive."""
    parent_joint = {j.child: j for j in description.joints}
    driven: set[str] = set()
    for body in description.mocap_welds:
        while (joint := parent_joint.get(body)) is not None and joint.name not in driven:
            driven.add(joint.name)
            body = joint.parent
    return driven & set(description.active_joint_names)


def _set_apart_passive(groups: Groups, driven: set[str]) -> None:
    """Joints no actuator drives stay passive, as in MuJoCo: a group of nothing else becomes
    passive; the others give theirs to one ``passive`` group."""
    loose: list[str] = []
    for name in list(groups.groups):
        joints = groups.groups[name]
        idle = [j for j in joints if j not in driven]
        if not idle or groups.kinds[name] == "mimic":
            continue
        if len(idle) == len(joints):
            groups.kinds[name] = "passive"
        else:
            groups.groups[name] = [j for j in joints if j in driven]
            loose += idle
    if loose:
        name = PASSIVE_GROUP
        while name in groups.groups:
            name += "_"
        groups.add(name, "passive", loose)


def immobile_reason(joint: Joint) -> str | None:
    """Why ``joint`` cannot move (its limits are equal), or None. (An effort rating of 0 alone
    says nothing: descriptions write ``effort="0"`` for "not rated", ManiSkill's so100 among
    them, and their joints move.)"""
    if joint.lower is not None and joint.upper is not None and joint.lower == joint.upper:
        how = " and its effort rating is 0" if joint.effort == 0 else ""
        return f"its limits are equal ([{joint.lower:g}, {joint.upper:g}]){how}"
    return None


def _set_apart_immobile(groups: Groups, description: RobotDescription) -> None:
    """Joints that cannot move leave their groups for one ``immobile`` group, which a passive
    controller holds (a drive there could only push against the limits: with a [0, 0] range a
    step response can only fail). A mimic group keeps them: its leader moves them."""
    loose: list[str] = []
    for name in list(groups.groups):
        if groups.kinds[name] in ("mimic", "passive"):
            continue
        joints = groups.groups[name]
        stuck = [j for j in joints if (found := description.joint(j)) and immobile_reason(found)]
        if not stuck:
            continue
        kept = [j for j in joints if j not in stuck]
        if kept:
            groups.groups[name] = kept
        else:
            del groups.groups[name]
            del groups.kinds[name]
        loose += stuck
    if loose:
        name = IMMOBILE_GROUP
        while name in groups.groups:
            name += "_"
        groups.add(name, "immobile", loose)
