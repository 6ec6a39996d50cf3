"""Guess joint groups for a scaffolded spec from the description alone.

Rules, in order (each joint lands in exactly one group; every active joint lands in one):

* **mimic** — URDF ``<mimic>`` pairs between active joints, chains collapsed onto the joint that
  leads them (``q = m·q_leader + o``). They get a ``pd_joint_pos_mimic`` controller: PhysX mimic
  joints go NaN within a few steps, the controller is the stable route.
* **base** — a planar base (x, y and yaw joints at the root,
  :mod:`robospec.kinematics.morphology`): a base controller. Else the active joints that start
  the tree (before any other active joint) whose names say base/root/odom: a mobile root,
  driven by joint velocity.
* **wheels** — continuous joints named like wheels or casters: joint velocity.
* **legs** — one group per leg (:mod:`robospec.kinematics.morphology`), named by its side:
  ``fl``, ``fr``, ``rl``, ``rr``, ``left_leg``, ``right_leg``, or the side the description's
  names give.
* **gripper** — joints named like fingers, grippers, hands or jaws, and prismatic joints that
  come in sibling pairs (two fingers on one link). Without an arm they are the ``hand``.
* **arm** — the longest serial chain of the remaining joints from the root to a leaf. When the
  longest chains tie (a hand of identical fingers, a humanoid's two arms), their shared joints
  are the ``body`` and each chain a group of its own.
* the rest — one group per branch, named from its joints' common prefix (``head``; a bare side
  becomes ``left_arm``), else ``finger1``, ``finger2``... when there is no arm, ``branch1``...
  otherwise.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from robospec.description import Joint, RobotDescription
from robospec.importer.groups import common_prefix
from robospec.kinematics.morphology import Morphology, is_wheel, morphology
from robospec.kinematics.tree import KinematicTree
from robospec.model.names import NAME_PATTERN

# words that start a name part ("l_gripper_finger_joint", "thumb_q1"), not any substring:
# "steering" is no ring, "multiple" no tip
_GRIPPER_WORDS = re.compile(
    r"(?<![a-z])(finger|grip|hand|thumb|index|middle|ring|pinky|little|claw|jaw|knuckle|palm"
    r"|tip)",
    re.IGNORECASE,
)
# a lower-case letter then a capital starts a word too ("jointGripper", Unitree Z1's)
_CAMEL = re.compile(r"(?<=[a-z])(?=[A-Z])")


def _words(name: str) -> str:
    """``name`` with its camel-case words set apart, as the word patterns read names."""
    return _CAMEL.sub("_", name)


_MOBILE_ROOT = re.compile(r"(?<![a-z])(base|root|odom|world|mobile)", re.IGNORECASE)
_ARM_WORDS = re.compile(r"(?<![a-z])(shoulder|elbow|wrist|arm)", re.IGNORECASE)
_BARE_SIDES = {"l": "left", "left": "left", "r": "right", "right": "right"}
_SIDE_WORDS = {
    *_BARE_SIDES,
    "front",
    "rear",
    "back",
    "fl",
    "fr",
    "rl",
    "rr",
    "lf",
    "rf",
    "lh",
    "rh",
}
_NAME = re.compile(NAME_PATTERN)
_GENERIC = {"", "joint", "link", "j", "l", "revolute", "prismatic"}


@dataclass(frozen=True)
class MimicLink:
    follower: str
    leader: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass
class Groups:
    """Group name -> joints (qpos order), in the order the spec lists them."""

    groups: dict[str, list[str]] = field(default_factory=dict)
    # name -> arm|gripper|mimic|base (a mobile root by joint velocity)|planar_base|wheels|leg|other
    kinds: dict[str, str] = field(default_factory=dict)
    mimic: list[MimicLink] = field(default_factory=list)

    def add(self, name: str, kind: str, joints: list[str]) -> None:
        if joints:
            self.groups[name] = joints
            self.kinds[name] = kind


def mimic_links(description: RobotDescription) -> list[MimicLink]:
    """Mimic relations between active joints, each follower mapped onto the joint leading its
    chain (a -> b -> c becomes a -> c with the composed multiplier and offset): a URDF's
    ``<mimic>``, and the joints an MJCF's equalities and tendons couple (ManiSkill's loader
    drops those couplings, and the follower would hang loose without a mimic controller)."""
    active = {j.name: j for j in description.active_joints}
    rules = {j.name: j.mimic for j in description.active_joints if j.mimic is not None}
    for coupling in description.couplings:
        rules.setdefault(coupling.follower, coupling.mimic)
    out: list[MimicLink] = []
    for joint in description.active_joints:
        multiplier, offset, leader = 1.0, 0.0, joint
        seen = {joint.name}
        while (m := rules.get(leader.name)) is not None and m.joint in active:
            offset = multiplier * m.offset + offset
            multiplier = multiplier * m.multiplier
            leader = active[m.joint]
            if leader.name in seen:  # a mimic cycle: nobody leads it
                break
            seen.add(leader.name)
        rule = rules.get(leader.name)
        leads = rule is None or rule.joint not in active  # not in a cycle
        if leader is not joint and leads:
            out.append(MimicLink(joint.name, leader.name, multiplier, offset))
    return out


def guess_groups(description: RobotDescription, body: Morphology | None = None) -> Groups:
    """The groups of ``description``; ``body`` is its
    :func:`~robospec.kinematics.morphology.morphology` (made without forward kinematics when not
    given: legs then go by their names only)."""
    body = body if body is not None else morphology(description, None)
    active = list(description.active_joints)
    order = {j.name: i for i, j in enumerate(active)}
    tree = KinematicTree(description)
    mimic = mimic_links(description)
    in_mimic = {m.follower for m in mimic} | {m.leader for m in mimic}

    planar = [name for name in body.planar_base or () if name not in in_mimic]
    taken = set(in_mimic) | set(planar)
    wheels = [j for j in body.wheels if j not in taken]
    taken |= set(wheels)
    base = [j.name for j in active if j.name not in taken and _is_mobile_root(tree, j)]
    taken |= set(base)
    legs = [leg for leg in body.legs if not set(leg.joints) & taken]
    taken |= {joint for leg in legs for joint in leg.joints}
    gripper = [j.name for j in active if j.name not in taken and _is_gripper(description, j)]
    taken |= set(gripper)
    leader = {m.follower: m.leader for m in mimic}
    # fingers hang from a palm, coupled or named as a gripper's or not: the chains that are
    # not legs, wheels or a base
    palm = bool(_palms(_chains(tree, taken - in_mimic - set(gripper)), leader))
    arm, trunk = _arm_chain(tree, taken, leader)
    taken |= set(arm)
    rest = [j for j in active if j.name not in taken]

    result = Groups(mimic=mimic)
    reserved = set(description.joint_names) | set(description.link_names)
    if planar:
        result.add("base", "planar_base", planar)
    else:
        result.add("base", "base", base)
    result.add("wheels", "wheels", sorted(wheels, key=order.__getitem__))
    for leg in legs:
        result.add(leg.name, "leg", list(leg.joints))
    result.add("body" if trunk else "arm", "arm", arm)
    hand = "gripper" if arm and not trunk and not palm else "hand"
    if gripper and in_mimic:
        result.add(hand, "gripper", gripper)
        result.add(f"{hand}_mimic", "mimic", sorted(in_mimic, key=order.__getitem__))
    elif in_mimic:
        result.add(hand, "mimic", sorted(in_mimic, key=order.__getitem__))
    else:
        result.add(hand, "gripper", gripper)
    for name, joints in _branches(description, tree, rest, reserved | set(result.groups)):
        result.add(name, "other", joints)
    # a group named like a joint or link would shadow it: rename, keeping the kind
    for name in [n for n in result.groups if n in reserved]:
        new = _unique(f"{name}_group", reserved | set(result.groups))
        result.groups = {new if k == name else k: v for k, v in result.groups.items()}
        result.kinds = {new if k == name else k: v for k, v in result.kinds.items()}
    return result


def _is_mobile_root(tree: KinematicTree, joint: Joint) -> bool:
    """A prismatic joint first, then only base-like active joints down to this one."""
    if is_wheel(joint):
        return False
    path = [j for j in tree.root_path(joint.child) if j.is_active]
    return path[0].type == "prismatic" and all(
        _MOBILE_ROOT.search(j.name) and not _GRIPPER_WORDS.search(_words(j.name)) for j in path
    )


def _is_gripper(description: RobotDescription, joint: Joint) -> bool:
    if _GRIPPER_WORDS.search(_words(joint.name)):
        return True
    if joint.type != "prismatic":
        return False
    siblings = [
        j
        for j in description.active_joints
        if j.parent == joint.parent and j.type == "prismatic" and j.name != joint.name
    ]
    return len(siblings) == 1


# chains parting this many independent ways or more at one joint hang from a palm: fingers (a
# torso parts three ways, into two arms and a head; a gripper's linkage, however many bars,
# one way: its bars follow one leader)
PALM_BRANCHES = 4


def _chains(tree: KinematicTree, taken: set[str]) -> list[list[str]]:
    """Each leaf's active joints from the root, those in ``taken`` left out."""
    chains = [
        [j.name for j in tree.root_path(leaf) if j.is_active and j.name not in taken]
        for leaf in tree.leaves()
    ]
    return [c for c in chains if c]


def _palms(chains: list[list[str]], leader: dict[str, str]) -> set[tuple[str, ...]]:
    """The joints above each palm (as a chain's head) where ``chains`` part into
    :data:`PALM_BRANCHES` or more ways that no mimic coupling joins (``leader``: a follower's
    leader)."""
    ways: dict[tuple[str, ...], set[str]] = {}
    for chain in chains:
        for k, joint in enumerate(chain):
            ways.setdefault(tuple(chain[:k]), set()).add(leader.get(joint, joint))
    return {head for head, nexts in ways.items() if len(nexts) >= PALM_BRANCHES}


def _arm_chain(
    tree: KinematicTree, taken: set[str], leader: dict[str, str]
) -> tuple[list[str], bool]:
    """The arm's joints, and whether they are only the trunk that tied chains share."""
    chains = _chains(tree, taken)
    if not chains:
        return [], False
    longest = max(len(c) for c in chains)
    best = [c for c in chains if len(c) == longest]
    # identical fingers hanging off one link (a hand): no chain is the arm
    if len({tuple(c) for c in best}) > 1:
        return _common_head(best), True
    arm = best[0]
    # a hand whose longest finger is its thumb (the Shadow hand's has five joints, the others
    # four): the longest chain runs through the palm into the thumb; the arm ends at the palm
    palms = [len(head) for head in _palms(chains, leader) if tuple(arm[: len(head)]) == head]
    return (arm[: min(palms)] if palms else arm), False


def _common_head(chains: list[list[str]]) -> list[str]:
    head: list[str] = []
    for names in zip(*chains, strict=False):
        if len(set(names)) != 1:
            break
        head.append(names[0])
    return head


def _branches(
    description: RobotDescription, tree: KinematicTree, joints: list[Joint], taken: set[str]
) -> list[tuple[str, list[str]]]:
    """Group the leftover joints by the first leftover joint on their path from the root;
    branches that all hang off one link (a palm) are fingers."""
    names = {j.name for j in joints}
    by_head: dict[str, list[str]] = {}
    for joint in joints:
        head = next(j.name for j in tree.root_path(joint.child) if j.name in names)
        by_head.setdefault(head, []).append(joint.name)
    # single joints that differ only by side (left_steering_hinge_joint, right_...) are one
    # group, named by what they share
    pairs: dict[str, list[str]] = {}
    for head, members in by_head.items():
        if len(members) == 1:
            pairs.setdefault(_without_sides(head), []).append(head)
    merged: dict[str, str] = {}
    for stem, heads in pairs.items():
        if len(heads) > 1 and stem:
            for head in heads[1:]:
                by_head[heads[0]] += by_head.pop(head)
            merged[heads[0]] = stem
    out: list[tuple[str, list[str]]] = []
    parents = {description.joint(head).parent for head in by_head}  # type: ignore[union-attr]
    fingers = len(by_head) > 1 and len(parents) == 1 and max(map(len, by_head.values())) <= 4
    fallback = "finger" if fingers else "branch"
    used = set(taken)
    for index, (head, members) in enumerate(by_head.items(), start=1):
        name = merged.get(head) or _prefix_name(members)
        if name in _BARE_SIDES and any(_ARM_WORDS.search(m) for m in members):
            name = f"{_BARE_SIDES[name]}_arm"  # "left_shoulder_pitch_joint"...: not just "left"
        if len(name) < 3 or name in _GENERIC or name in used or not _NAME.match(name):
            name = _unique(f"{fallback}{index}", used)
        used.add(name)
        out.append((name, members))
    return out


def _without_sides(name: str) -> str:
    """``name`` without its side words and the words joint/link, as a group name."""
    parts = [p for p in re.split(r"[^A-Za-z0-9]+", name.lower()) if p]
    kept = [p for p in parts if p not in _SIDE_WORDS and p not in ("joint", "link", "j")]
    return "_".join(kept) if len(kept) < len(parts) else ""


def _prefix_name(members: list[str]) -> str:
    stem = re.sub(r"[^A-Za-z0-9_]+", "_", common_prefix(members))
    stem = re.sub(r"(_?joint|_?link)?[_\d]*$", "", stem, flags=re.IGNORECASE)
    stem = re.sub(r"^(joint|link)_?", "", stem, flags=re.IGNORECASE)
    return stem.strip("_").lower()


def _unique(name: str, used: set[str]) -> str:
    candidate, n = name, 2
    while candidate in used:
        candidate, n = f"{name}_{n}", n + 1
    return candidate
