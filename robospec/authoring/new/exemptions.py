"""Collision exemptions: the pairs of links ``robospec new`` declares ``never_collide``, each
for a reason found over the robot's kinematic tree (:class:`robospec.kinematics.tree.KinematicTree`)
and what the simulation says of it (which links have collision shapes, where hinges turn, which
pairs touch at a pose):

* :func:`overlapping`: pairs the rest-pose search found touching in every pose it tried, their
  shapes overlapping where they are joined (or coarse shapes);
* :func:`shapeless_neighbours`: pairs joined only through links without collision shapes;
* :func:`nesting_yokes`: the two ends of a universal joint, nested round its cross;
* :func:`welded_neighbours`: pairs welded together, or across a joint over whose range they
  never touch;
* :func:`mechanism_pairs`: parts of one mimic mechanism that its coupling keeps apart;
* :func:`pinned_pairs`: parts of one mimic mechanism that touch in every pose of it, where the
  description cuts its closed linkage open;
* :func:`filtered_cliques`: the links an MJCF's own collision filters keep apart.

PhysX leaves out only the contacts of a link and its parent; every pair here it collides, and
each reason is a case where that collision is not the robot's (:func:`physx_exemptions` finds
the middle four in the probe's child process, in the order the scaffold's comment names them).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterator, Mapping, Sequence
from dataclasses import dataclass

from robospec.authoring.new.joint_space import NEIGHBOURS, JointSpace
from robospec.authoring.new.pose_search import Contacts, ContactsAt, Pair
from robospec.description import RobotDescription
from robospec.geometry import Vector, cross
from robospec.kinematics.tree import KinematicTree
from robospec.resolve.collision_packing import FREE_BITS, clique_pairs, pack

# after this many poses, a pair that touched in every one overlaps whatever joins it: coarse
# collision shapes (iCub's boxes: its head and shoulder touch 59 mm deep in every pose), which
# PhysX pushes apart with all its might at the first step
THOROUGH = 100
# poses of a joint (a mimic coupling's leader), evenly over its range, in which the links it
# moves must not touch to be kept apart (mechanism_pairs, welded_neighbours)
MECHANISM_SAMPLES = 9
# m: how close two hinge axes pass for them to meet at one point (a spherical joint's axes,
# written with the same origin, meet to rounding)
MEET = 1e-4
HINGES = frozenset({"revolute", "continuous"})

# why robospec new exempts a pair, in a few words: the scaffold's header gives each
# never_collide entry its own (:func:`overlap_reason`; :func:`physx_exemptions`' kinds)
OVERLAPPING_WHY = "touch in every pose tried: their shapes overlap at the joint"
COARSE_WHY = "touch in every pose tried: coarse collision shapes"
ADJACENT_WHY = {
    "shapeless": "joined only through links without collision shapes",
    "yoke": "the ends of a universal joint, nested round its cross",
    "welded": "welded together, or across a joint over whose range they never touch",
    "mechanism": "parts of one mimic mechanism, kept apart by its coupling",
    "pinned": "parts of one mimic mechanism, pinned together where its closed linkage is cut",
}

Line = tuple[Vector, Vector]  # a point on it, its direction (a unit vector)
Near = Mapping[Pair, float]  # the pairs PhysX reports within its contact offset: pair -> depth


def overlapping(
    touching: Sequence[tuple[str, str, float]],
    always: Collection[Pair],
    tried: int,
    tree: KinematicTree,
) -> tuple[Pair, ...]:
    """The pairs of ``touching`` (what the search left touching) that touched in every pose it
    tried, at most :data:`NEIGHBOURS` joints apart (or after :data:`THOROUGH` poses, however
    far apart): their shapes overlap where they are joined, or are coarse."""
    return tuple(
        (a, b)
        for a, b, _ in touching
        if (a, b) in always and (tree.joints_apart(a, b) <= NEIGHBOURS or tried >= THOROUGH)
    )


def overlap_reason(pair: Pair, tree: KinematicTree) -> str:
    """Why a pair :func:`overlapping` found is exempt: its shapes overlap where the two links
    are joined (neighbours), or, farther apart, the shapes are coarse."""
    return OVERLAPPING_WHY if tree.joints_apart(*pair) <= NEIGHBOURS else COARSE_WHY


@dataclass(frozen=True)
class Bodies:
    """The robot's links as PhysX collides them: each link's welded body (the top link of the
    links fixed joints hold together) and each body's links with collision shapes, for the
    bodies that have any."""

    tree: KinematicTree
    body: Mapping[str, str]
    members: Mapping[str, Sequence[str]]

    def parent(self, link: str) -> str | None:
        joint = self.tree.up.get(link)
        return joint.parent if joint is not None else None

    def hinged(self, link: str) -> bool:
        """Whether ``link`` turns about its parent on a revolute joint."""
        joint = self.tree.up.get(link)
        return joint is not None and joint.type in HINGES

    def pairs(self, first: str, second: str) -> set[Pair]:
        """Every pair of a link of body ``first`` and one of body ``second``, each sorted."""
        return {(min(a, b), max(a, b)) for a in self.members[first] for b in self.members[second]}


def bodies(tree: KinematicTree, shaped: Collection[str]) -> Bodies:
    """The welded bodies of ``tree``, whose links ``shaped`` have collision shapes."""
    body = {link: _welded_top(tree, link) for link in tree.below}
    members: dict[str, list[str]] = {}
    for link in tree.below:
        if link in shaped:
            members.setdefault(body[link], []).append(link)
    return Bodies(tree, body, members)


def _welded_top(tree: KinematicTree, link: str) -> str:
    """The top link of the welded body ``link`` belongs to (fixed joints up from it)."""
    while link in tree.up and tree.up[link].type == "fixed":
        link = tree.up[link].parent
    return link


def shapeless_neighbours(found: Bodies) -> list[Pair]:
    """Pairs of links with collision shapes joined only through links without any (the links
    a spherical joint becomes in SAPIEN, one per axis; an MJCF body's joints after its first):
    as good as parent and child, whose collisions PhysX leaves out, yet PhysX collides these.
    DeepMimic's feet, three hinges below the shins, hit them whichever way an ankle turned.
    Links welded together (fixed joints) count as one body."""
    pairs: set[Pair] = set()
    for head in found.members:
        node, skipped = found.parent(head), False
        while node is not None and found.body[node] not in found.members:
            node, skipped = found.parent(found.body[node]), True
        if skipped and node is not None:
            pairs |= found.pairs(head, found.body[node])
    return sorted(pairs)


def nesting_yokes(found: Bodies, axes: Mapping[str, Line], near: Near) -> list[Pair]:
    """The two ends of hinges whose axes meet (a universal joint, the link between them its
    cross: iCub's shoulder, pitch, roll and yaw about one centre) whose shapes PhysX reports in
    contact at the rest pose (``near``), within its contact offset: they nest round the cross,
    millimetres apart, and PhysX collides them (the cross has shapes: the walk of
    :func:`shapeless_neighbours` stops at it). A brush between iCub's upper arm and shoulder_1,
    2.4 mm apart at rest, took a 1067 N s impulse in one physics step and threw its shoulders
    to 330 rad/s under random actions. Ends that are apart at rest (TALOS's hand and forearm
    about its wrist) are left colliding: a hand let into the forearm drags its fingers, which
    still collide, past their limits. ``axes``: each hinged link's axis, in the world."""
    pairs: set[Pair] = set()
    for head in found.members:
        parent = found.parent(head)
        if parent is None or not found.hinged(head):
            continue
        middle = found.body[parent]
        above = found.parent(middle)
        if above is None or not found.hinged(middle) or found.body[above] not in found.members:
            continue
        if head in axes and middle in axes and axes_meet(axes[head], axes[middle]):
            pairs |= found.pairs(head, found.body[above])
    return sorted(pair for pair in pairs if pair in near)


def axes_meet(first: Line, second: Line) -> bool:
    """Whether two lines, each (a point, a unit direction), cross at one point: not parallel,
    and no farther apart than :data:`MEET` where they pass closest."""
    (p, u), (q, v) = first, second
    normal = cross(u, v)
    size = math.sqrt(sum(c * c for c in normal))
    if size < 1e-6:
        return False  # parallel: turning about both moves in one plane, no cross between
    gap = sum((q[i] - p[i]) * normal[i] for i in range(3)) / size
    return abs(gap) <= MEET


@dataclass(frozen=True)
class Sweep:
    """What the sweeps of one joint over its range ask: the contacts PhysX reports at a pose
    (within its contact offsets), and how deep a pair must be to touch."""

    posed: ContactsAt
    touch: float

    def deepest(
        self,
        space: JointSpace,
        qpos: list[float],
        index: int,
        span: tuple[float, float],
        coupled: bool,
    ) -> Contacts:
        """Each pair PhysX reports, at its deepest, as joint ``index`` sweeps ``span`` (low,
        high) in :data:`MECHANISM_SAMPLES` poses, the rest as in ``qpos`` (``coupled``: its
        mimic followers following)."""
        low, high = span
        found: Contacts = {}
        for k in range(MECHANISM_SAMPLES):
            sample = list(qpos)
            sample[index] = low + (high - low) * k / (MECHANISM_SAMPLES - 1)
            for pair, depth in self.posed(space.follow(sample) if coupled else sample).items():
                found[pair] = max(found.get(pair, -math.inf), depth)
        return found

    def everywhere(
        self, space: JointSpace, qpos: list[float], index: int, span: tuple[float, float]
    ) -> set[Pair]:
        """The pairs that touch (at least :attr:`touch` deep) in every one of
        :data:`MECHANISM_SAMPLES` poses as joint ``index`` sweeps ``span``, its mimic followers
        following."""
        low, high = span
        found: set[Pair] | None = None
        for k in range(MECHANISM_SAMPLES):
            sample = list(qpos)
            sample[index] = low + (high - low) * k / (MECHANISM_SAMPLES - 1)
            posed = self.posed(space.follow(sample))
            touching = {pair for pair, depth in posed.items() if depth >= self.touch}
            found = touching if found is None else found & touching
        return found or set()


def welded_neighbours(
    found: Bodies, space: JointSpace, qpos: list[float], near: Near, sweep: Sweep
) -> list[Pair]:
    """Pairs of ``near`` (the contacts PhysX reports at ``qpos``, the rest pose, within its
    contact offsets) whose links fixed joints weld into one body, or into a parent body and its
    child, and that never touch over the whole range of the joint between them: PhysX leaves
    out the contacts of a link and its parent only, so a link collides with whatever is welded
    to its parent, and links welded together collide with each other. TALOS's gripper hangs
    below three welded links (a force-torque sensor and its tool flange) whose shapes lie within
    PhysX's contact offsets (2 cm a shape in ManiSkill's scenes) of its bars: their contacts
    took impulses of hundreds of N s in one physics step and carried a fingertip 0.12 rad past
    its limit on a test stand, 0.06 rad with them left out. An upper arm that can swing into
    the pedestal its mount is welded to keeps colliding with it."""
    pairs: set[Pair] = set()
    across: dict[int, set[Pair]] = {}  # joint index -> the pairs it moves apart
    for a, b in near:
        upper, lower = found.body[a], found.body[b]
        if upper == lower:
            pairs.add((a, b))
            continue
        for first, second in ((upper, lower), (lower, upper)):
            parent = found.parent(second)
            # the child body's joint joins its top link to one link of the parent body: that
            # pair PhysX leaves out itself
            if parent is None or found.body[parent] != first or {a, b} == {second, parent}:
                continue
            joint = found.tree.up[second]
            if joint.name in space.index:
                across.setdefault(space.index[joint.name], set()).add((a, b))
    for index, moved in sorted(across.items()):
        low, high = space.limits[index]
        if low is None or high is None:
            low, high = qpos[index] - math.pi, qpos[index] + math.pi
        # (the joint alone: a mimic follower swept with its leader would not move)
        deepest = sweep.deepest(space, qpos, index, (low, high), coupled=False)
        pairs.update(pair for pair in moved if deepest.get(pair, -math.inf) < sweep.touch)
    return sorted(pairs)


def mechanism_pairs(space: JointSpace, qpos: list[float], sweep: Sweep) -> list[Pair]:
    """Pairs of links that one mimic coupling moves (its leader's and followers' links) which
    PhysX reports within its contact offsets yet which never touch as the leader sweeps its
    range from ``qpos``, the followers following: the mechanism keeps them apart. In the
    simulation separate drives stand in for the coupling (a closed linkage, which a URDF cannot
    write, or a tendon), links swing off their coupled poses, and these pairs meet. TALOS's
    gripper is a parallelogram of four bars a side; its two sides' bars, 3 to 9 mm apart at
    rest, struck each other at 100 rad/s under random actions and carried a bar 0.14 rad past
    its limit: left out, no joint passes it."""
    pairs: set[Pair] = set()
    for leader, (low, high), links in _mechanisms(space):
        deepest = sweep.deepest(space, qpos, leader, (low, high), coupled=True)
        pairs.update(
            (a, b)
            for (a, b), depth in deepest.items()
            if a in links and b in links and depth < sweep.touch
        )
    return sorted(pairs)


def pinned_pairs(space: JointSpace, qpos: list[float], sweep: Sweep) -> list[Pair]:
    """Pairs of links that one mimic coupling moves, not parent and child, which touch in every
    pose as the leader sweeps its range from ``qpos``, the followers following: a closed
    linkage that the description cuts open (a URDF writes trees), its two ends overlapping at
    the pin it leaves out. The xArm gripper's inner knuckle is pinned to its finger, which
    hangs from the outer knuckle: 12 mm into each other at every opening, they were pushed
    apart by PhysX each step, and the gripper's drive spun away."""
    pairs: set[Pair] = set()
    for leader, (low, high), links in _mechanisms(space):
        pairs.update(
            (a, b)
            for a, b in sweep.everywhere(space, qpos, leader, (low, high))
            if a in links and b in links and not _joined(space.tree, a, b)
        )
    return sorted(pairs)


def _mechanisms(space: JointSpace) -> Iterator[tuple[int, tuple[float, float], set[str]]]:
    """Each mimic coupling with a bounded leader: the leader, its range, and the links that
    the leader and its followers move."""
    groups: dict[int, set[int]] = {}
    for follower, leader, _, _ in space.mimic:
        groups.setdefault(leader, {leader}).add(follower)
    for leader, members in sorted(groups.items()):
        low, high = space.limits[leader]
        if low is None or high is None:
            continue
        joints = {space.joints[i] for i in members}
        yield (
            leader,
            (low, high),
            {link for link in space.tree.up if space.driven_by(link) in joints},
        )


def _joined(tree: KinematicTree, a: str, b: str) -> bool:
    """Whether one link is the other's parent (PhysX leaves their contacts out itself)."""
    return any(
        link in tree.up and tree.up[link].parent == other for link, other in ((a, b), (b, a))
    )


def physx_exemptions(
    found: Bodies,
    axes: Mapping[str, Line],
    space: JointSpace,
    qpos: list[float],
    near: Near,
    sweep: Sweep,
) -> dict[Pair, str]:
    """The pairs the simulation collides and the robot does not, at the rest pose ``qpos``
    (``near``: the pairs PhysX reports there, within its contact offset), each with the kind
    of reason that found it (a key of :data:`ADJACENT_WHY`): joined through shapeless links
    first, then the nesting yokes, welded neighbours and a mechanism's parts (kept apart, then
    pinned together) not among them
    (the order of the scaffold's comment), each pair once, under the first reason found."""
    exempt = dict.fromkeys(shapeless_neighbours(found), "shapeless")
    for kind, pairs in (
        ("yoke", nesting_yokes(found, axes, near)),
        ("welded", welded_neighbours(found, space, qpos, near, sweep)),
        ("mechanism", mechanism_pairs(space, qpos, sweep)),
        ("pinned", pinned_pairs(space, qpos, sweep)),
    ):
        for pair in pairs:
            exempt.setdefault(pair, kind)
    return exempt


def filtered_cliques(description: RobotDescription) -> list[tuple[str, ...]]:
    """The links an MJCF's own collision filters keep apart, as ``never_collide`` entries: sets
    of links, each one entry, covering the description's ``filtered_pairs``; empty when they do
    not fit.

    MuJoCo collides two geoms only where one's contype shares a bit with the other's
    conaffinity, ManiSkill every pair whose contype is not 0 (RS073). A model that relies on its
    filters (the Shadow hand's collision geoms never touch each other in MuJoCo: contype 1,
    conaffinity 0) meets contacts in ManiSkill its makers never saw: a capsule overlapping the
    next link's box by 1 mm at every pose, fingers that block each other's steps. Declaring the
    filtered pairs never_collide keeps the robot as its file simulates it. Packed as robospec's
    resolver packs ``never_collide`` (:func:`robospec.resolve.collision_packing.pack`, with the
    bits ManiSkill's MJCF loader takes and the pairs they already keep apart): when they do not
    fit the free bits without disabling a pair MuJoCo collides, none are declared (RS073 still
    says which pairs collide)."""
    if not description.filtered_pairs:
        return []
    order = {name: i for i, name in enumerate(description.link_names)}
    free = set(description.adjacent_pairs())
    taken = set()
    for bit, links in description.loader_collision_bits:
        taken.add(bit)
        free |= clique_pairs(links)
    packing = pack(
        description.filtered_pairs,
        free=free,
        available=tuple(b for b in FREE_BITS if b not in taken),
    )
    if packing.uncovered or packing.side_effects:
        return []
    return [tuple(sorted(links, key=order.__getitem__)) for _, links in packing.cliques]
