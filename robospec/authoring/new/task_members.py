"""What ManiSkill's tasks call on an agent, for the grippers and hands ``robospec new``
recognises: ``tcp``, ``grasping`` (``is_grasping``) and ``is_static`` over the arm, so that a
scaffolded arm with a gripper runs ``PickCube-v1`` as written.

* **Fingers.** Of a linkage gripper (two closed loops), the fingertip of each loop's finger.
  In a gripper or hand group (or a mimic group), two joints that hang from the same
  link are two fingers, each the last link of the chain its joint carries where both carry
  one (a knuckle that carries one finger, swung parallel: the finger); of several such pairs,
  the two whose fingers lie farthest apart (a three-finger hand: the most opposed). A gripper
  of one moving jaw closes it against the link it hangs from (SO-101's fixed jaw). A hand of
  finger chains (``finger1``, ``finger2``...) uses the tips of its two chains that lie
  farthest apart.
* **Opening.** Each finger opens along the way its joint moves it: both finger joints are
  nudged each way from the rest pose, and the nudge that puts the fingers' centres of mass
  farthest apart opens them; each finger's opening axis is its centre's move under that nudge,
  in its own frame at rest, to the nearest axis (at a closed rest pose the centres coincide and
  say nothing). A finger no joint moves (a fixed jaw), or whose move does not part the fingers
  (its centre on its joint's axis, fingers side by side that curl), opens away from the other.
* **tcp.** A link named like a tool centre point, as conventions name one (:data:`TCP_NAMES`,
  best first: ``tcp``, ``*_tcp``, ``grasp_frame``; ``ee_link``, ``eef``, ``end_effector``,
  ``tool_frame``; ``tool0``), welded (fixed joints) to the fingers' parent; else the midpoint
  of the two fingers, oriented as their parent link, which ``self.tcp`` is bound to. A robot
  without a gripper gets its tcp-named link, where it has one (the deepest of the best-named).
* **is_static** over the arm groups; with none (two arms, each a group of its own), over the
  groups that carry the fingers.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from robospec.authoring.new.analysis import RobotAnalysis

if TYPE_CHECKING:
    import numpy as np

# what conventions name a tool centre point, best first: a name of the first kind says tcp;
# an end effector's frame; a tool flange (ROS-Industrial's tool0), the tcp of a bare arm
# (whole words of the name: after its start or a separator, `_` or a namespace's `/`)
TCP_NAMES = tuple(
    re.compile(rf"(?<![a-z0-9])({words})(?![a-z])", re.IGNORECASE)
    for words in (
        r"tcp|tool_?cent(?:er|re)_?point|grasp\w*|gripper_cent(?:er|re)",
        r"ee|eef|ee_link|ee_gripper|end_?effector|tool_?frame",
        r"tool0",
    )
)
GRIPPING_KINDS = ("gripper", "mimic")
ARM_KINDS = ("arm",)
AXES = ("+x", "-x", "+y", "-y", "+z", "-z")
DISTANCE_DIGITS = 9  # metres: distances between fingers are compared to a nanometre


@dataclass(frozen=True)
class Fingers:
    links: tuple[str, str]
    parent: str  # the link both hang from (the palm, the hand)
    openings: tuple[str, str]  # each finger's opening axis, in its own frame
    # the frames the tcp is the midpoint of, where they are not the fingers (fingertip frames
    # without collision shapes, welded below them)
    tips: tuple[str, str] | None = None


def task_members(analysis: RobotAnalysis, qpos: Mapping[str, float]) -> dict[str, Any]:
    """The spec sections (``tcp``, ``grasping``, ``is_static``) for the robot, those it can
    tell; empty when it recognises no gripper."""
    model = analysis.kinematics
    if model is None:
        return {}
    poses = model.at(qpos).links
    fingers = _fingers(analysis, poses, qpos)
    out: dict[str, Any] = {}
    if fingers is None:
        named = _tcp_link(analysis, None)
        if named is not None:
            out["tcp"] = named
        return out
    tcp = _tcp_link(analysis, fingers.parent)
    # a midpoint tcp still binds self.tcp to a link (PushCube-v1 reads agent.tcp.pose): the
    # fingers' parent
    out["tcp"] = (
        tcp
        if tcp is not None
        else {
            "link": fingers.parent,
            "midpoint": list(fingers.tips or fingers.links),
            "orientation": fingers.parent,
        }
    )
    out["grasping"] = {
        "is_grasping": {
            "fingers": [
                {"link": link, "opening": opening}
                for link, opening in zip(fingers.links, fingers.openings, strict=True)
            ]
        }
    }
    arms = [name for name, kind in analysis.groups.kinds.items() if kind in ARM_KINDS]
    if not arms:  # two arms, each a group of its own (Baxter's): the one the fingers hang from
        arms = _groups_above(analysis, fingers.parent)
    if arms:
        out["is_static"] = {"joints": arms[0] if len(arms) == 1 else arms}
    return out


def _groups_above(analysis: RobotAnalysis, link: str) -> list[str]:
    """The groups (a gripper's and a mimic group's left out) with a joint between the root and
    ``link``, in the spec's order."""
    model = analysis.kinematics
    assert model is not None
    above = {joint.child: joint for joint in model.joints}
    carried = set()
    while link in above:
        carried.add(above[link].name)
        link = above[link].parent
    return [
        name
        for name, joints in analysis.groups.groups.items()
        if analysis.groups.kinds[name] not in GRIPPING_KINDS and carried & set(joints)
    ]


def _loop_fingers(
    analysis: RobotAnalysis, poses: Mapping[str, np.ndarray], qpos: Mapping[str, float]
) -> Fingers | None:
    """A linkage gripper's fingers: of each of two closed loops, the link that carries more
    below it, else the deeper one (the finger, not the knuckle that holds it parallel), as its
    fingertip: the link at the end of its welded chain (a pad)."""
    model = analysis.kinematics
    assert model is not None
    children: dict[str, list[str]] = {}
    welded: dict[str, list[str]] = {}
    for joint in model.joints:
        children.setdefault(joint.parent, []).append(joint.child)
        if joint.type == "fixed":
            welded.setdefault(joint.parent, []).append(joint.child)

    def size(link: str) -> int:
        return 1 + sum(size(child) for child in children.get(link, []))

    above_link = {joint.child: joint.parent for joint in model.joints}

    def depth(link: str) -> int:
        return 0 if link not in above_link else 1 + depth(above_link[link])

    shaped = shaped_links(analysis)
    tips, ends, drivers = [], [], []
    for loop in analysis.loops[:2]:
        drivers.append(loop.driver)
        # on a tie (a pad that is a geom of its finger, as robosuite's Robotiq grippers have
        # them), the link further down the tree: the coupler hangs from the crank
        finger = max(loop.links, key=lambda link: (size(link), depth(link)))
        chain = [finger]
        while len(welded.get(chain[-1], [])) == 1:
            chain.append(welded[chain[-1]][0])
        # the grasp check's finger closes on the cube: of the chain, the last link with
        # collision shapes (a fingertip frame welded below the finger has none: gym-xarm's)
        tips.append(next((link for link in reversed(chain) if link in shaped), chain[-1]))
        ends.append(chain[-1])
    if len(tips) < 2:
        return None
    above = {joint.child: joint.parent for joint in model.joints}

    def ancestors(link: str) -> list[str]:
        out = []
        while link in above:
            link = above[link]
            out.append(link)
        return out

    parent = next((n for n in ancestors(tips[0]) if n in set(ancestors(tips[1]))), model.root)
    a, b = tips
    openings = _openings(analysis, poses, qpos, a, b, (drivers[0], drivers[1]))
    frames = (ends[0], ends[1])
    return Fingers((a, b), parent, openings, None if frames == (a, b) else frames)


def shaped_links(analysis: RobotAnalysis) -> set[str]:
    """The links with collision shapes as the description states them (``Link.shaped``: a
    URDF's links with a ``<collision>``, MuJoCo's compiled one's for ``loader: mujoco``, an
    MJCF's bodies with a geom)."""
    return {link.name for link in analysis.description.links if link.shaped}


def _fingers(
    analysis: RobotAnalysis, poses: Mapping[str, np.ndarray], qpos: Mapping[str, float]
) -> Fingers | None:
    model = analysis.kinematics
    assert model is not None
    if len(analysis.loops) >= 2:
        return _loop_fingers(analysis, poses, qpos)
    joints = {j.name: j for j in model.joints}
    gripping = [
        [joints[n] for n in analysis.groups.groups[name] if n in joints]
        for name, kind in analysis.groups.kinds.items()
        if kind in GRIPPING_KINDS or name.startswith(("gripper", "hand"))
    ]
    children: dict[str, list[str]] = {}
    for joint in model.joints:
        children.setdefault(joint.parent, []).append(joint.child)

    swinging = {joint.child for joint in model.joints if joint.type != "fixed"}

    def tip(link: str) -> str:
        # a finger that carries a chain of one link after another, each swinging on a joint
        # (a knuckle and the finger it swings parallel: the xArm gripper's), closes with the
        # chain's last link; a pad welded to its finger is the finger still (ManiSkill's Panda
        # grasps with panda_leftfinger, not its pad)
        while len(children.get(link, [])) == 1 and children[link][0] in swinging:
            link = children[link][0]
        return link

    def chain_ends(a: str, b: str) -> tuple[str, str]:
        # both fingers' chains, or neither: a knuckle beside a bar that carries nothing (PR2's
        # parallel links) is no pair with the other side's fingertip
        if children.get(a) and children.get(b) and (tip(a) != a) == (tip(b) != b):
            return tip(a), tip(b)
        return a, b

    pairs = []
    for group in gripping:
        for i, a in enumerate(group):
            for b in group[i + 1 :]:
                if a.parent == b.parent and a.child != b.child:
                    pairs.append((*chain_ends(a.child, b.child), a.parent))
    if not pairs:
        for group in gripping:
            if len(group) == 1:  # one jaw closing against the link it hangs from
                pairs.append((group[0].child, group[0].parent, group[0].parent))
    if not pairs:
        hand = _finger_tips(analysis, poses)
        if hand is not None:
            pairs.append(hand)
    if not pairs:
        return None
    left, right, parent = max(pairs, key=lambda pair: _distance(analysis, poses, pair[0], pair[1]))
    return Fingers((left, right), parent, _openings(analysis, poses, qpos, left, right))


def _finger_tips(
    analysis: RobotAnalysis, poses: Mapping[str, np.ndarray]
) -> tuple[str, str, str] | None:
    """A hand of finger chains: the tips of the two chains farthest apart, and the link the
    chains hang from (its palm)."""
    model = analysis.kinematics
    assert model is not None
    chains = [
        analysis.groups.groups[name]
        for name, kind in analysis.groups.kinds.items()
        if name.startswith("finger") and kind not in ARM_KINDS
    ]
    if len(chains) < 2:
        return None
    joints = {j.name: j for j in model.joints}
    children: dict[str, list[str]] = {}
    for joint in model.joints:
        children.setdefault(joint.parent, []).append(joint.child)
    tips = []
    for chain in chains:
        last = joints.get(chain[-1])
        first = joints.get(chain[0])
        if last is None or first is None:
            continue
        tip = last.child
        while len(children.get(tip, [])) == 1:  # a fixed fingertip link below it
            tip = children[tip][0]
        tips.append((tip, first.parent))
    if len(tips) < 2:
        return None
    best = max(
        ((a, b) for i, a in enumerate(tips) for b in tips[i + 1 :]),
        key=lambda pair: _distance(analysis, poses, pair[0][0], pair[1][0]),
    )
    return best[0][0], best[1][0], best[0][1]


def gripper_fingers(analysis: RobotAnalysis, qpos: Mapping[str, float]) -> Fingers | None:
    """The two fingers of the gripper ``new`` recognises (the rules above), at ``qpos``."""
    if analysis.kinematics is None:
        return None
    return _fingers(analysis, analysis.kinematics.at(qpos).links, qpos)


def finger_joint(analysis: RobotAnalysis, link: str) -> str | None:
    """The joint that moves a finger: the nearest moving joint above it (None: none does)."""
    model = analysis.kinematics
    assert model is not None
    moving = {j.child: j.name for j in model.joints if j.type != "fixed"}
    return _moving_joint_above(model, moving, link)


def finger_centre(
    analysis: RobotAnalysis, poses: Mapping[str, np.ndarray], link: str
) -> np.ndarray:
    """A link's centre of mass at ``poses`` (its frame's origin when it has no inertial)."""
    return _centre(analysis, poses, link)


def _centre(analysis: RobotAnalysis, poses: Mapping[str, np.ndarray], link: str) -> np.ndarray:
    """A link's centre of mass at rest (its frame's origin when it has no inertial)."""
    pose = poses[link]
    found = analysis.inertials.get(link)
    return pose[:3, :3] @ found.com + pose[:3, 3] if found is not None else pose[:3, 3]


def _distance(analysis: RobotAnalysis, poses: Mapping[str, np.ndarray], a: str, b: str) -> float:
    """How far apart two links' centres are, to a nanometre: the two hands of a symmetric robot
    (Baxter's grippers) are equally far apart, and the first in the tree's order is taken, not
    the one that rounding puts a femtometre ahead."""
    pa, pb = _centre(analysis, poses, a), _centre(analysis, poses, b)
    return round(math.dist(pa.tolist(), pb.tolist()), DISTANCE_DIGITS)


NUDGE = 0.01  # rad (or m) each finger joint is moved to see which way it opens


def _openings(
    analysis: RobotAnalysis,
    poses: Mapping[str, np.ndarray],
    qpos: Mapping[str, float],
    a: str,
    b: str,
    drivers: tuple[str, str] | None = None,
) -> tuple[str, str]:
    """Each finger's opening axis: how the joint moving it carries it as the fingers part,
    from the rest pose ``qpos`` (``poses``). A linkage's finger moves as its loop's
    ``drivers`` move the linkage, its followers with them (robosuite's Robotiq pads, which
    their own joints alone would turn about the pin instead)."""
    model = analysis.kinematics
    assert model is not None
    moving = {j.child: j.name for j in model.joints if j.type != "fixed"}
    joints = list(drivers or [_moving_joint_above(model, moving, link) for link in (a, b)])
    rest = dict(qpos)
    best: tuple[float, Mapping[str, np.ndarray]] | None = None
    for signs in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        nudged = dict(rest)
        for joint, sign in zip(joints, signs, strict=True):
            if joint is not None:
                nudged[joint] = qpos.get(joint, 0.0) + sign * NUDGE
        for rule in analysis.linkage_mimic:  # the loops' followers follow their drivers
            if rule.leader in joints:
                nudged[rule.follower] = nudged[rule.leader] * rule.multiplier + rule.offset
        moved = model.at(nudged).links
        apart = _distance(analysis, moved, a, b)
        if best is None or apart > best[0] + 1e-12:
            best = (apart, moved)
    assert best is not None
    parted, moved = best[0] - _distance(analysis, poses, a, b), best[1]
    out = []
    for link, other, joint in ((a, b, joints[0]), (b, a, joints[1])):
        start = _centre(analysis, poses, link)
        end = _centre(analysis, moved, link) if joint is not None else start
        if not _parts(start, end, parted):
            # a fixed jaw, a finger whose centre lies on its joint's axis, fingers side by side
            # that curl rather than part: away from the other finger
            start, end = _centre(analysis, poses, other), start
        out.append(_nearest_axis(poses[link], end - start))
    return out[0], out[1]


def _parts(start: np.ndarray, end: np.ndarray, parted: float) -> bool:
    """Whether a finger's move from ``start`` to ``end`` is what parts the fingers by
    ``parted``: a move of the fingers towards or away from each other changes their distance
    by as much as it moves them (a curl beside the other finger, to second order only)."""
    moved = math.dist(start.tolist(), end.tolist())
    return moved > 1e-9 and parted >= moved / 2


def _moving_joint_above(model: Any, moving: Mapping[str, str], link: str) -> str | None:
    """The nearest joint above ``link`` that moves (a fingertip welded to its finger: the
    finger's)."""
    above = {j.child: j.parent for j in model.joints}
    while link in above:
        if link in moving:
            return moving[link]
        link = above[link]
    return None


def _nearest_axis(pose: np.ndarray, direction: np.ndarray) -> str:
    """The axis of ``pose``'s frame nearest ``direction`` (given in the root frame)."""
    local = (pose[:3, :3].T @ direction).tolist()
    index = max(range(3), key=lambda i: abs(local[i]))
    return AXES[2 * index + (0 if local[index] >= 0 else 1)]


def _tcp_link(analysis: RobotAnalysis, parent: str | None) -> str | None:
    """The link named most like a tool centre point (:data:`TCP_NAMES`): of the links welded
    to ``parent`` (fixed joints up and down from it), the nearest; with no ``parent``, of all
    the robot's links, the deepest (the end of the arm), and none where two branches tie."""
    model = analysis.kinematics
    assert model is not None
    up = {j.child: j for j in model.joints}
    if parent is not None:
        top = parent
        while top in up and up[top].type == "fixed":
            top = up[top].parent
        fixed_below: dict[str, list[str]] = {}
        for joint in model.joints:
            if joint.type == "fixed":
                fixed_below.setdefault(joint.parent, []).append(joint.child)
        welded, queue = [], [top]
        while queue:
            link = queue.pop(0)
            welded.append(link)
            queue.extend(fixed_below.get(link, []))
        # nearest first: the parent's own welded links by how far they hang from it
        candidates = sorted(welded, key=lambda link: _welds_between(up, link, parent))
    else:
        links = {model.root, *up}
        candidates = sorted(links, key=lambda link: (-_depth(up, link), link))
    for names in TCP_NAMES:
        found = [link for link in candidates if names.search(link)]
        if parent is None and len(found) > 1 and _depth(up, found[0]) == _depth(up, found[1]):
            return None  # two arms, or two frames as deep: which one is for the user to say
        if found:
            return found[0]
    return None


def _depth(up: Mapping[str, Any], link: str) -> int:
    depth = 0
    while link in up:
        link, depth = up[link].parent, depth + 1
    return depth


def _welds_between(up: Mapping[str, Any], link: str, parent: str) -> int:
    """How many joints lie between ``link`` and ``parent`` in one welded body."""
    a, b = _depth(up, link), _depth(up, parent)
    return abs(a - b)
