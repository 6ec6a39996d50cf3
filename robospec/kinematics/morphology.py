"""What kind of body a robot description has, decided from the description alone: does it
stand on legs, drive on wheels, move on a planar base, or sit fixed where it is put?

The rules, in the order ``robospec new`` applies them:

* **planar base** — the first active joints from the root are a serial chain that slides
  along the root's x axis, slides along its y axis and turns about its z axis (prismatic,
  prismatic, revolute or continuous; ManiSkill's mobile robots move their base this way). The
  root stays fixed: those joints move it. It gets a base controller.
* **legs** — a *leg* is the chain of active joints that leads to one leaf link alone (from the
  last link where the tree branches towards other active joints, down to the leaf) with at least
  two active joints, whose joint or link names say leg (leg, hip, thigh, knee, calf, shank,
  shin, foot, toe, ankle, sole, paw, hoof, heel, femur, tibia, or the HAA/HFE/KFE of ANYmal-style
  names, the leaf's included) and none of which say hand (finger, thumb, grip, hand, palm).
* **wheels** — continuous joints whose joint or link name says wheel, caster, tire or tyre (the
  robot *rolls* when any link is named so, even on a fixed joint, as fetch's wheels are).
* **anchored** — the root link is a world frame by name (world, map, odom, ground): the
  description fixes itself to the world.
* **root slides** — the first active joint below the root, before the tree branches, is
  prismatic: the description moves the robot itself (half_cheetah's rootx, rootz, rooty).

The robot's root is *floating* (``fix_root_link: false``) when the MJCF root body has a free
joint; or, for a URDF, when nothing anchors it, no planar base or sliding root moves it, and it
has two or more legs or any wheels. (ManiSkill's MJCF loader welds the root of a model whose root
body has no free joint, whatever the agent asks: such a robot with legs stays fixed, and the
scaffold says to add the free joint.) A floating robot stands (or rolls) on the ground under
gravity, so it gets ``balance_passive_force: false`` in every control mode: ManiSkill's default
balances gravity and would hold it up in mid-air.

Legs are named by side: four legs ``fl``, ``fr``, ``rl``, ``rr`` (front/rear from the sign of
the leg's x in the root frame, left/right from its y, ROS's x-forward, y-left convention), two
legs ``left_leg`` and ``right_leg`` (``front_leg`` and ``rear_leg`` when both lie on the centre
line, as a planar walker's do), six legs ``fl``, ``ml``, ``rl``, ``fr``, ``mr``, ``rr`` —
unless every leg's joint names share a side token of their own (``FR``, ``LF``, ``hl``,
``left``; ``front_left`` becomes ``fl``), which is then the leg's name. Other counts, or legs
whose positions do not tell them apart, are ``leg1``, ``leg2``...
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from robospec.description import Joint, RobotDescription
from robospec.kinematics.tree import KinematicTree

if TYPE_CHECKING:
    from robospec.kinematics.forward import KinematicModel

# a leg word may carry one letter of side before it (half_cheetah's "bthigh", "ffoot"): "wheel"
# is no heel, "ship" no hip
_LEG_WORDS = re.compile(
    r"(?<![a-z])[fbhlrm]?(leg|hip|thigh|knee|calf|shank|shin|foot|feet|toe|ankle|sole|paw|hoof|heel"
    r"|femur|tibia|haa|hfe|kfe)",
    re.IGNORECASE,
)
_HAND_WORDS = re.compile(r"(?<![a-z])(finger|thumb|grip|hand|palm)", re.IGNORECASE)
WHEEL_WORDS = re.compile(r"(?<![a-z])(wheel|caster|tire|tyre)", re.IGNORECASE)
_WORLD_LINK = re.compile(r"^(world|map|odom|ground)$", re.IGNORECASE)

# side tokens a description writes into its leg joint names: FR, LF, hl, RH, left, l...
_SIDE_CODE = re.compile(r"^([fhrbm][lr]|[lr][fhrbm])$", re.IGNORECASE)
_FRONT_REAR = {"front": "f", "fore": "f", "rear": "r", "back": "r", "hind": "r", "middle": "m"}
_LEFT_RIGHT = {"left": "l", "right": "r"}
_BIPED = {"l": "left_leg", "left": "left_leg", "r": "right_leg", "right": "right_leg"}

# below this, a coordinate is on the robot's centre line: it tells no side
_CENTRE_TOLERANCE = 1e-4
_AXIS_TOLERANCE = 0.99


@dataclass(frozen=True)
class Leg:
    name: str  # the group name: fl, left_leg, LF's lf, leg1...
    joints: tuple[str, ...]  # active joints, in qpos order


@dataclass(frozen=True)
class Morphology:
    legs: tuple[Leg, ...] = ()
    wheels: tuple[str, ...] = ()  # the continuous joints of wheels
    rolls: bool = False  # it has wheels, turning or not (fetch's are fixed joints)
    planar_base: tuple[str, str, str] | None = None  # (x, y, yaw) joints
    anchored: bool = False
    free_joint: bool = False
    # the tree starts with a sliding joint: the description moves the robot itself
    # (half_cheetah's rootx, rootz, rooty)
    root_slides: bool = False
    # an MJCF: ManiSkill's loader welds its root in place unless the root body has a free joint
    mjcf: bool = False

    @property
    def walks_or_rolls(self) -> bool:
        """Legs or wheels, and nothing that holds or moves the root otherwise."""
        if self.anchored or self.planar_base is not None or self.root_slides:
            return False
        return len(self.legs) >= 2 or bool(self.wheels)

    @property
    def floating(self) -> bool:
        if self.mjcf:
            return self.free_joint
        return self.free_joint or self.walks_or_rolls

    @property
    def welded(self) -> bool:
        """An MJCF robot with legs or wheels whose root ManiSkill's loader will weld in place:
        its root body has no free joint."""
        return self.mjcf and not self.free_joint and self.walks_or_rolls

    @property
    def why_floating(self) -> str:
        if self.free_joint:
            return "the root body has a free joint"
        if len(self.legs) >= 2:
            return f"it stands on {len(self.legs)} legs and nothing fixes it to the world"
        return "it drives on its wheels and nothing fixes it to the world"


def morphology(description: RobotDescription, kinematics: KinematicModel | None) -> Morphology:
    tree = KinematicTree(description)
    wheels = tuple(j.name for j in description.active_joints if is_wheel(j))
    planar = _planar_base(description, tree, kinematics)
    taken = set(wheels) | set(planar or ())
    chains = [c for c in _leaf_chains(tree) if not set(c[0]) & taken]
    legs = [joints for joints, leaf in chains if _is_leg(description, joints, leaf)]
    return Morphology(
        legs=_name_legs(legs, kinematics),
        wheels=wheels,
        rolls=bool(wheels) or any(WHEEL_WORDS.search(link) for link in description.link_names),
        planar_base=planar,
        anchored=bool(_WORLD_LINK.match(description.root_link)),
        free_joint=description.floating_root,
        root_slides=_root_slides(tree),
        mjcf=description.kind == "mjcf",
    )


def _root_slides(tree: KinematicTree) -> bool:
    """Whether the first active joint below the root, before the tree branches, slides."""
    link = tree.root
    while len(tree.below.get(link, [])) == 1:
        joint = tree.below[link][0]
        if joint.is_active:
            return joint.type == "prismatic"
        link = joint.child
    return False


def is_wheel(joint: Joint) -> bool:
    return joint.type == "continuous" and bool(
        WHEEL_WORDS.search(joint.name) or WHEEL_WORDS.search(joint.child)
    )


def _leaf_chains(tree: KinematicTree) -> list[tuple[tuple[str, ...], str]]:
    """For each leaf link, the active joints that lead to it alone (root first), and the leaf;
    a chain two leaves share (a leg that ends in a toe and a sensor) is listed once."""
    actives_below = _actives_below(tree)
    chains: dict[tuple[str, ...], str] = {}
    for leaf in tree.leaves():
        chain: list[str] = []
        link = leaf
        while link in tree.up:
            joint = tree.up[link]
            parent = joint.parent
            if joint.is_active:
                chain.append(joint.name)
            # the parent branches towards other active joints: the chain is this leaf's no more
            branches = [
                j for j in tree.below.get(parent, []) if j.is_active or actives_below[j.child]
            ]
            if len(branches) > 1:
                break
            link = parent
        if chain:
            chains.setdefault(tuple(reversed(chain)), leaf)
    # a side branch (a rotor, a sensor) cut off part of a chain: keep the whole chain only
    return [
        (joints, leaf)
        for joints, leaf in chains.items()
        if not any(len(other) > len(joints) and other[: len(joints)] == joints for other in chains)
    ]


def _actives_below(tree: KinematicTree) -> dict[str, bool]:
    """Link -> whether an active joint lies anywhere below it."""
    result: dict[str, bool] = {}
    for row in reversed(tree.rows()):
        result[row.link] = any(
            j.is_active or result.get(j.child, False) for j in tree.below.get(row.link, [])
        )
    return result


def _is_leg(description: RobotDescription, chain: tuple[str, ...], leaf: str) -> bool:
    if len(chain) < 2:
        return False
    names = [leaf]
    for name in chain:
        joint = description.joint(name)
        assert joint is not None
        names += [joint.name, joint.child]
    return any(_LEG_WORDS.search(n) for n in names) and not any(
        _HAND_WORDS.search(n) for n in names
    )


def _planar_base(
    description: RobotDescription, tree: KinematicTree, kinematics: KinematicModel | None
) -> tuple[str, str, str] | None:
    active = description.active_joints
    if len(active) < 3 or kinematics is None:
        return None
    axes = kinematics.at().axes
    first: list[Joint] = []
    # the serial chain of active joints from the root, up to three
    link = description.root_link
    while len(first) < 3:
        below = tree.below.get(link, [])
        moving = [j for j in below if j.is_active]
        if len(moving) > 1 or (not moving and len(below) != 1):
            return None
        joint = moving[0] if moving else below[0]
        if joint.is_active:
            first.append(joint)
        link = joint.child
    x = y = yaw = None
    for joint in first:
        if joint.name not in axes:
            return None
        axis = axes[joint.name].direction
        if joint.type == "prismatic" and abs(axis[0]) > _AXIS_TOLERANCE:
            x = joint.name
        elif joint.type == "prismatic" and abs(axis[1]) > _AXIS_TOLERANCE:
            y = joint.name
        elif joint.type in ("revolute", "continuous") and abs(axis[2]) > _AXIS_TOLERANCE:
            yaw = joint.name
    if x is None or y is None or yaw is None:
        return None
    return (x, y, yaw)


def _name_legs(
    legs: Sequence[tuple[str, ...]], kinematics: KinematicModel | None
) -> tuple[Leg, ...]:
    if len(legs) < 2:
        return ()
    names = _own_names(legs) or _names_by_position(legs, kinematics)
    if names is None:
        names = [f"leg{i}" for i in range(1, len(legs) + 1)]
    return tuple(Leg(name, joints) for name, joints in zip(names, legs, strict=True))


def _own_names(legs: Sequence[tuple[str, ...]]) -> list[str] | None:
    """The side every leg's joint names share (``FR_hip_joint``, ``leg_left_1_joint``), when
    each leg has exactly one and no two legs the same."""
    names = []
    for leg in legs:
        sides = set.intersection(*(set(_side_tokens(joint)) for joint in leg))
        if len(sides) != 1:
            return None
        names.append(sides.pop())
    if len(set(names)) != len(names):
        return None
    if len(legs) == 2 and all(name in _BIPED for name in names):
        return [_BIPED[name] for name in names]
    if any(name in _BIPED for name in names):
        return None  # a lone "left" among four legs says too little
    return names


def _side_tokens(name: str) -> list[str]:
    parts = [p.lower() for p in re.split(r"[^A-Za-z0-9]+", name) if p]
    tokens = [p for p in parts if _SIDE_CODE.match(p) or p in _BIPED]
    front_rear = [_FRONT_REAR[p] for p in parts if p in _FRONT_REAR]
    left_right = [_LEFT_RIGHT[p] for p in parts if p in _LEFT_RIGHT]
    if len(front_rear) == 1 and len(left_right) == 1:
        return [front_rear[0] + left_right[0]]
    return tokens


def _names_by_position(
    legs: Sequence[tuple[str, ...]], kinematics: KinematicModel | None
) -> list[str] | None:
    if kinematics is None:
        return None
    # where each leg's first joint holds it, at zero: its child link's origin
    poses = kinematics.at().links
    places = []
    for leg in legs:
        joint = kinematics.joint(leg[0])
        if joint is None or joint.child not in poses:
            return None
        x, y, z = poses[joint.child][:3, 3].tolist()
        places.append((x, y, z))
    if len(legs) == 2 and all(abs(y) < _CENTRE_TOLERANCE for _, y, _ in places):
        (x1, _, _), (x2, _, _) = places
        if abs(x1 - x2) < _CENTRE_TOLERANCE:
            return None
        return ["front_leg", "rear_leg"] if x1 > x2 else ["rear_leg", "front_leg"]
    if any(abs(y) < _CENTRE_TOLERANCE for _, y, _ in places):
        return None
    side = ["l" if y > 0 else "r" for _, y, _ in places]
    if len(legs) == 2:
        names = [_BIPED[s] for s in side]
    elif len(legs) in (4, 6):
        names = []
        rows = "fr" if len(legs) == 4 else "fmr"
        for index, (x, _, _) in enumerate(places):
            same_side = sorted(
                (p[0] for p, s in zip(places, side, strict=True) if s == side[index]), reverse=True
            )
            if len(same_side) != len(rows) or len(set(same_side)) != len(same_side):
                return None
            names.append(rows[same_side.index(x)] + side[index])
    else:
        return None
    return names if len(set(names)) == len(names) else None
