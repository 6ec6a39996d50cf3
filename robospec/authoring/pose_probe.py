"""The child process of ``robospec new`` that loads the scaffolded robot in ManiSkill: it finds
a rest pose in which no two links touch and, for a floating robot, how high its root must stand
for its lowest collision point to touch the ground.

Run as ``python -m robospec.authoring.pose_probe`` with a JSON request on stdin (see
:class:`Request`); prints one JSON answer on stdout. A child, because loading a description
nobody checked can crash SAPIEN outright (a segfault takes the process with it): ``new`` then
writes the scaffold without the check and says why.

The contact test is ``robospec check``'s (:mod:`robospec.physics.self_contact`): set the pose,
hold the drives there, one physics step, and every pair of the robot's links deeper in contact
than ``min_depth``. The search is deterministic: from the starting pose, the smallest move of
one joint (of those between two touching links, by 10, 20, 35 or 50 % of its range, either way)
that leaves fewer pairs touching (:func:`better`); when no move helps, a chain of such moves of
the joints between one touching pair, each leaving links less deep in each other, kept if it ends
with fewer pairs touching (:meth:`Probe._descend`); then random moves of all those joints at once,
from a fixed seed. A pose changes only to undo a contact, so a contact nothing
undoes leaves the starting pose as it was; the answer names the pairs that touched in every pose
tried.
"""

from __future__ import annotations

import gc
import json
import math
import random
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from robospec.authoring.rest_pose import NEIGHBOURS
from robospec.geometry import IDENTITY, ZERO, Vector, cross
from robospec.model.thresholds import MIN_CONTACT_DEPTH

STEPS = (0.1, 0.2, 0.35, 0.5)
FULL_TURN = 2 * math.pi
FLOATING_LIFT = 10.0  # m: a floating robot is held well above the ground while contacts count
SEED = 0
# pose_probe's chain of moves that deepen no contact (Probe._descend): moves at most, and by how
# much each must leave the pair shallower (m: more than the depth's noise between two loads)
DESCENT_MOVES = 8
DESCENT_GAIN = 0.002
# poses of a joint (a mimic coupling's leader), evenly over its range, in which the links it
# moves must not touch to be kept apart (Probe.mechanism_pairs, Probe.welded_neighbours)
MECHANISM_SAMPLES = 9


@dataclass
class Request:
    spec: str  # a spec of the robot to register (the draft scaffold)
    uid: str
    mode: str  # a control mode of that spec whose controllers take joint positions
    joints: list[str]  # the active joints, in qpos order
    start: list[float]
    limits: list[tuple[float | None, float | None]]
    # (follower, leader, multiplier, offset) by index into ``joints``
    mimic: list[tuple[int, int, float, float]] = field(default_factory=list)
    # link -> (parent link, the joint between them), for every link but the root
    parents: dict[str, tuple[str, str]] = field(default_factory=dict)
    floating: bool = False
    min_depth: float = MIN_CONTACT_DEPTH
    # the search keeps links this far apart (m): two links just touching block each other, and
    # a step of one towards the other (robospec check's step response) goes nowhere
    clearance: float = 0.002
    budget: int = 600  # poses tried at most
    # (w, x, y, z): how a floating robot stands (its root turned so, for a y-up description)
    upright: list[float] = field(default_factory=lambda: list(IDENTITY))
    # then scaffold the robot at the rest pose found and measure its gains there
    # (robospec.authoring.refine): (the description file, the spec's path, the schema reference)
    refinement: tuple[str, str, str] | None = None


Contacts = dict[tuple[str, str], float]
# m: how far a contact's depth wanders between two loads of the same pose (float32 positions,
# the settling step): a pair this close to ``min_depth`` counts as touching
DEPTH_NOISE = 1e-5


def better(new: Contacts, old: Contacts) -> bool:
    """Fewer touching pairs. Depth alone does not count: two shapes that overlap where their
    links are joined touch in every pose, more or less deeply, and chasing that depth led the
    search to poses no one would choose (legs splayed to shave a millimetre)."""
    return len(new) < len(old)


class Probe:
    def __init__(self, request: Request) -> None:
        import mani_skill.envs  # noqa: F401  (registers Empty-v1)

        from robospec.output.register import register
        from robospec.physics.sim import Sim

        # ManiSkill collects garbage each time it builds a scene (Sim builds one per pose
        # tried): with torch's and ManiSkill's objects in view that costs 0.15 s a pose, out of
        # view (frozen, as robospec check's worker does) 30 ms
        gc.collect()
        gc.freeze()
        self.request = request
        register(request.spec)
        self.sim = Sim(request.uid, request.mode)
        self.index = {name: i for i, name in enumerate(request.joints)}
        self.followers = {follower for follower, _, _, _ in request.mimic}
        self.tried = 0
        self.always: set[tuple[str, str]] | None = None  # the pairs every pose tried touched
        self._adjacent: list[tuple[str, str]] | None = None  # (adjacent(), once: links stay)

    def contacts(self, qpos: list[float]) -> Contacts:
        self.tried += 1
        touching = {
            pair: depth
            for pair, depth in sorted(self.posed(qpos).items())
            if depth >= -self.request.clearance
        }
        self.always = set(touching) if self.always is None else self.always & set(touching)
        return touching

    def follow(self, qpos: list[float]) -> list[float]:
        """Mimic followers set from their leaders, every joint inside its limits."""
        out = [self.clamp(i, v) for i, v in enumerate(qpos)]
        for follower, leader, multiplier, offset in self.request.mimic:
            out[follower] = self.clamp(follower, out[leader] * multiplier + offset)
        return out

    def clamp(self, index: int, value: float) -> float:
        low, high = self.request.limits[index]
        if low is not None:
            value = max(value, low)
        if high is not None:
            value = min(value, high)
        return value

    def span(self, index: int) -> float:
        low, high = self.request.limits[index]
        if low is None or high is None:
            return FULL_TURN
        return min(high - low, FULL_TURN)

    def movable(self, contacts: Contacts) -> list[int]:
        """The joints (by index) between the links of each touching pair, leaders only."""
        found: set[int] = set()
        for a, b in contacts:
            path_a, path_b = self._path(a), self._path(b)
            for joint in set(path_a) ^ set(path_b):
                if joint in self.index and self.index[joint] not in self.followers:
                    found.add(self.index[joint])
        return sorted(found)

    def _path(self, link: str) -> list[str]:
        joints = []
        while link in self.request.parents and len(joints) <= len(self.request.parents):
            link, joint = self.request.parents[link]
            joints.append(joint)
        return joints

    def search(self) -> tuple[list[float], Contacts]:
        best = self.follow(list(self.request.start))
        best_contacts = self.contacts(best)
        rng = random.Random(SEED)
        while best_contacts and self.tried < self.request.budget:
            candidates = self.movable(best_contacts)
            if not candidates:
                break
            moved = self._greedy(best, best_contacts, candidates)
            if moved is None:
                moved = self._descend(best, best_contacts)
            if moved is None:
                moved = self._random(best, best_contacts, candidates, rng)
            if moved is None:
                break
            best, best_contacts = moved
        return best, best_contacts

    def _greedy(
        self, qpos: list[float], contacts: Contacts, joints: list[int]
    ) -> tuple[list[float], Contacts] | None:
        """The smallest move of one joint that undoes a contact (smaller steps first)."""
        for step in STEPS:
            for move in self._moves(qpos, step, joints):
                if move is None:  # the budget is spent
                    return None
                if better(move[1], contacts):
                    return move
        return None

    def _moves(
        self, qpos: list[float], step: float, joints: list[int]
    ) -> Iterator[tuple[list[float], Contacts] | None]:
        """Each of ``joints`` moved ``step`` of its span each way from ``qpos`` (mimics
        following), with the contacts there; ``None`` last when the budget runs out first."""
        for index in joints:
            for sign in (1.0, -1.0):
                if self.tried >= self.request.budget:
                    yield None
                    return
                trial = list(qpos)
                trial[index] = qpos[index] + sign * step * self.span(index)
                trial = self.follow(trial)
                if trial != qpos:
                    yield trial, self.contacts(trial)

    def _descend(
        self, qpos: list[float], contacts: Contacts
    ) -> tuple[list[float], Contacts] | None:
        """Undo a contact no single move undoes, by a chain of moves of the joints between its
        two links, each leaving the links that are not neighbours less deep in each other in
        all (:meth:`_intrusion`): iCub's right forearm, 65 mm inside its torso, comes out by
        turning the shoulder twice, and the first turn leaves as many pairs touching as before
        (the forearm 5 mm in the torso, 4 mm in the thigh). The pairs whose links are furthest
        apart go first (a hand in the hip, rather than shapes that overlap where they are
        joined), then the deepest. The chain is kept only if it ends with fewer pairs touching:
        a pose changes only to undo a contact."""
        pairs = sorted(
            (pair for pair in contacts if self._apart(*pair) > NEIGHBOURS),
            key=lambda pair: (-self._apart(*pair), -contacts[pair]),
        )
        for pair in pairs:
            joints = self._nearest_first(*pair)
            here, depth = list(qpos), self._intrusion(contacts, contacts)
            for _ in range(DESCENT_MOVES):
                found = self._shallower(here, depth, joints, contacts)
                if found is None:
                    break
                here, touching = found
                if better(touching, contacts):
                    return here, touching
                depth = self._intrusion(touching, contacts)
            if self.tried >= self.request.budget:
                return None
        return None

    def _shallower(
        self, qpos: list[float], depth: float, joints: list[int], base: Contacts
    ) -> tuple[list[float], Contacts] | None:
        """The move of one of ``joints`` that leaves the intrusion least, of the smallest steps
        that leave it less than ``depth`` by :data:`DESCENT_GAIN` at least: the first move that
        helps at all would be the wrist's, which slides the forearm from the torso into the
        thigh, where the shoulder's lifts it out of both."""
        for step in STEPS:
            best: tuple[float, list[float], Contacts] | None = None
            for move in self._moves(qpos, step, joints):
                if move is None:  # the budget is spent
                    return None
                trial, touching = move
                left = self._intrusion(touching, base)
                if left < depth - DESCENT_GAIN and (best is None or left < best[0]):
                    best = left, trial, touching
            if best is not None:
                return best[1], best[2]
        return None

    def _intrusion(self, contacts: Contacts, base: Contacts) -> float:
        """How deep links are in each other, in all (m, each pair counted from the search's
        clearance), but for neighbours that touched in ``base`` (where the chain of moves
        started): their shapes overlap where they are joined, and :func:`better` leaves all
        depth out for them. A neighbour touching anew counts: a forearm lifted out of the
        torso by pressing its upper arm into the shoulder is no better off."""
        return sum(
            depth + self.request.clearance
            for pair, depth in contacts.items()
            if pair not in base or self._apart(*pair) > NEIGHBOURS
        )

    def _nearest_first(self, a: str, b: str) -> list[int]:
        """The joints (leaders, by index) between links ``a`` and ``b``, those nearest either
        link first: the forearm's elbow and shoulder turn before the torso that carries the
        whole arm (and the head, and the other arm) leans."""
        path_a, path_b = self._path(a), self._path(b)
        between = set(path_a) ^ set(path_b)
        # how far up from its link each joint lies (each joint between them lies on one path)
        height = {joint: i for path in (path_a, path_b) for i, joint in enumerate(path)}
        order = sorted(between, key=height.__getitem__)
        return [
            self.index[j] for j in order if j in self.index and self.index[j] not in self.followers
        ]

    def _apart(self, a: str, b: str) -> int:
        """How many active joints lie between links ``a`` and ``b``."""
        return len({j for j in set(self._path(a)) ^ set(self._path(b)) if j in self.index})

    def _random(
        self, qpos: list[float], contacts: Contacts, joints: list[int], rng: random.Random
    ) -> tuple[list[float], Contacts] | None:
        for _ in range(4 * len(joints)):
            if self.tried >= self.request.budget:
                return None
            trial = list(qpos)
            for index in joints:
                trial[index] += rng.uniform(-0.5, 0.5) * self.span(index)
            trial = self.follow(trial)
            touching = self.contacts(trial)
            if better(touching, contacts):
                return trial, touching
        return None

    def adjacent(self) -> list[tuple[str, str]]:
        """Pairs of links with collision shapes joined only through links without any (the
        links a spherical joint becomes in SAPIEN, one per axis; an MJCF body's joints after
        its first): as good as parent and child, whose collisions PhysX leaves out, yet PhysX
        collides these. DeepMimic's feet, three hinges below the shins, hit them whichever
        way an ankle turned. Links welded together (fixed joints) count as one body."""
        if self._adjacent is not None:
            return self._adjacent
        links, body, members = self._bodies()
        found = set()
        for head in members:
            node, skipped = _parent(links[head]), False
            while node is not None and body[node.name] not in members:
                node, skipped = _parent(links[body[node.name]]), True
            if not skipped or node is None:
                continue
            for a in members[head]:
                for b in members[body[node.name]]:
                    found.add((min(a, b), max(a, b)))
        self._adjacent = sorted(found)
        return self._adjacent

    def _bodies(self) -> tuple[dict[str, Any], dict[str, str], dict[str, list[str]]]:
        """The robot's links by name; each link's welded body (the top link of the links
        fixed joints hold together); each body's links with collision shapes, for the bodies
        that have any."""
        links = {link.name: link for link in self.sim.robot.links}
        body = {name: _welded_top(links[name]) for name in links}
        members: dict[str, list[str]] = {}
        for name in links:
            if links[name]._objs[0].collision_shapes:
                members.setdefault(body[name], []).append(name)
        return links, body, members

    def nesting_yokes(self, near: Contacts) -> list[tuple[str, str]]:
        """The two ends of hinges whose axes meet (a universal joint, the link between them its
        cross: iCub's shoulder, pitch, roll and yaw about one centre) whose shapes PhysX
        reports in contact at ``qpos``, within its contact offset: they nest round the cross,
        millimetres apart, and PhysX collides them (the cross has shapes: :meth:`adjacent`'s
        walk stops at it). A brush between iCub's upper arm and shoulder_1, 2.4 mm apart at
        rest, took a 1067 N s impulse in one physics step and threw its shoulders to
        330 rad/s under random actions. Ends that are apart at rest (TALOS's hand and
        forearm about its wrist) are left colliding: a hand let into the forearm drags its
        fingers, which still collide, past their limits."""
        links, body, members = self._bodies()
        found: set[tuple[str, str]] = set()
        for head in members:
            cross = _parent(links[head])
            if cross is None or not _hinge(links[head]):
                continue
            cross = links[body[cross.name]]
            above = _parent(cross)
            if above is None or not _hinge(cross) or body[above.name] not in members:
                continue
            if not axes_meet(_axis_line(links[head]), _axis_line(cross)):
                continue
            for a in members[head]:
                for b in members[body[above.name]]:
                    found.add((min(a, b), max(a, b)))
        return sorted(pair for pair in found if pair in near)

    def welded_neighbours(self, qpos: list[float], near: Contacts) -> list[tuple[str, str]]:
        """Pairs of ``near`` (the contacts PhysX reports at ``qpos``, the rest pose, within its
        contact offsets) whose links fixed joints weld into one body, or into a parent body and
        its child, and that never touch over the whole range of the joint between them:
        PhysX leaves out the contacts of a link and its parent only, so a link collides with
        whatever is welded to its parent, and links welded together collide with each other.
        TALOS's gripper hangs below three welded links (a force-torque sensor and its tool
        flange) whose shapes lie within PhysX's contact offsets (2 cm a shape in ManiSkill's
        scenes) of its bars: their contacts took impulses of hundreds of N s in one physics
        step and carried a fingertip 0.12 rad past its limit on a test stand, 0.06 rad with
        them left out. An upper arm that can swing into the pedestal its mount is welded to
        keeps colliding with it."""
        links, body, _ = self._bodies()
        found: set[tuple[str, str]] = set()
        across: dict[int, set[tuple[str, str]]] = {}  # joint index -> the pairs it moves apart
        for a, b in near:
            upper, lower = body[a], body[b]
            if upper == lower:
                found.add((a, b))
                continue
            for first, second in ((upper, lower), (lower, upper)):
                parent = _parent(links[second])
                joint = links[second].joint
                # the child body's joint joins its top link to one link of the parent body:
                # that pair PhysX leaves out itself
                if parent is None or body[parent.name] != first or {a, b} == {second, parent.name}:
                    continue
                if joint is not None and joint.name in self.index:
                    across.setdefault(self.index[joint.name], set()).add((a, b))
        for index, pairs in sorted(across.items()):
            low, high = self.request.limits[index]
            if low is None or high is None:
                low, high = qpos[index] - math.pi, qpos[index] + math.pi
            # (the joint alone: a mimic follower swept with its leader would not move)
            deepest = self._deepest(qpos, index, low, high, coupled=False)
            found.update(pair for pair in pairs if deepest.get(pair, -math.inf) < self._touch)
        return sorted(found)

    def mechanism_pairs(self, qpos: list[float]) -> list[tuple[str, str]]:
        """Pairs of links that one mimic coupling moves (its leader's and followers' links)
        which PhysX reports within its contact offsets yet which never touch as the leader
        sweeps its range from ``qpos``, the followers following: the mechanism keeps them
        apart. In the simulation separate drives stand in for the coupling (a closed linkage,
        which a URDF cannot write, or a tendon), links swing off their coupled poses, and
        these pairs meet. TALOS's gripper is a parallelogram of four bars a side; its two
        sides' bars, 3 to 9 mm apart at rest, struck each other at 100 rad/s under random
        actions and carried a bar 0.14 rad past its limit: left out, no joint passes it."""
        groups: dict[int, set[int]] = {}
        for follower, leader, _, _ in self.request.mimic:
            groups.setdefault(leader, {leader}).add(follower)
        found: set[tuple[str, str]] = set()
        for leader, members in sorted(groups.items()):
            low, high = self.request.limits[leader]
            if low is None or high is None:
                continue
            joints = {self.request.joints[i] for i in members}
            links = {link for link in self.request.parents if self._driven_by(link) in joints}
            deepest = self._deepest(qpos, leader, low, high, coupled=True)
            found.update(
                (a, b)
                for (a, b), depth in deepest.items()
                if a in links and b in links and depth < self._touch
            )
        return sorted(found)

    @property
    def _touch(self) -> float:
        """How deep a pair must be to touch, as robospec check counts it (less float noise)."""
        return self.request.min_depth - DEPTH_NOISE

    def _deepest(
        self, qpos: list[float], index: int, low: float, high: float, coupled: bool
    ) -> Contacts:
        """Each pair PhysX reports, at its deepest, as joint ``index`` sweeps from ``low`` to
        ``high`` in :data:`MECHANISM_SAMPLES` poses, the rest as in ``qpos`` (``coupled``: its
        mimic followers following)."""
        deepest: Contacts = {}
        for k in range(MECHANISM_SAMPLES):
            sample = list(qpos)
            sample[index] = low + (high - low) * k / (MECHANISM_SAMPLES - 1)
            for pair, depth in self.posed(self.follow(sample) if coupled else sample).items():
                deepest[pair] = max(deepest.get(pair, -math.inf), depth)
        return deepest

    def _driven_by(self, link: str) -> str | None:
        """The active joint nearest above ``link`` (None for the root's welded body)."""
        while link in self.request.parents:
            link, joint = self.request.parents[link]
            if joint in self.index:
                return joint
        return None

    def posed(self, qpos: list[float]) -> dict[tuple[str, str], float]:
        """Every pair PhysX reports in contact (within its contact offset) with the robot at
        ``qpos``, its drives holding it there for one physics step: pair -> depth."""
        from robospec.resolve.resolved import ResolvedKeyframe

        lift = FLOATING_LIFT if self.request.floating else 0.0
        self.sim.start(ResolvedKeyframe("rest", (0.0, 0.0, lift), IDENTITY, tuple(qpos), None))
        self.sim.hold_drive_targets()
        self.sim.sim_step()
        return dict(self.sim.self_contacts())

    def mount_height(self, qpos: list[float]) -> float | None:
        """For a fixed robot whose moving links reach below the ground at ``qpos`` (its root at
        the origin, where ManiSkill's scenes put it), the height to mount it at so they clear
        the ground; None when nothing reaches below."""
        from robospec.physics.ground import DEPTH, LIFT_MARGIN
        from robospec.resolve.resolved import ResolvedKeyframe

        self.sim.start(ResolvedKeyframe("rest", ZERO, IDENTITY, tuple(qpos), None))
        mounted = self.sim.mounted_links()
        lowest = [z for name, z in self.sim.lowest_points().items() if name not in mounted]
        if not lowest or min(lowest) >= -DEPTH:
            return None
        return -min(lowest) + LIFT_MARGIN

    def standing_height(self, qpos: list[float]) -> float | None:
        """How far above the ground the root must be for the lowest collision point of the
        robot, at ``qpos`` and upright (its root turned as ``upright`` says), to touch it."""
        import torch
        from mani_skill.utils.structs.pose import Pose

        robot = self.sim.robot
        turn = torch.tensor([self.request.upright], dtype=torch.float32)
        robot.set_pose(Pose.create_from_pq(torch.zeros(1, 3), turn))
        robot.set_qpos(torch.tensor([qpos], dtype=torch.float32))
        lowest = math.inf
        for link in robot.links:
            body = link._objs[0]
            if body.collision_shapes:
                lowest = min(lowest, float(body.compute_global_aabb_tight()[0][2]))
        return None if math.isinf(lowest) else -lowest


def _parent(link: Any) -> Any:
    return link.joint.parent_link if link.joint is not None else None


def _hinge(link: Any) -> bool:
    """Whether ``link`` turns about its parent on a revolute joint."""
    joint = link.joint
    return joint is not None and str(joint._objs[0].type).startswith("revolute")


def _axis_line(link: Any) -> tuple[Vector, Vector]:
    """The line ``link``'s joint turns about, in the world: (a point on it, its direction);
    a PhysX joint turns about its frame's x axis."""
    matrix = link.joint._objs[0].get_global_pose().to_transformation_matrix()
    point = (float(matrix[0, 3]), float(matrix[1, 3]), float(matrix[2, 3]))
    return point, (float(matrix[0, 0]), float(matrix[1, 0]), float(matrix[2, 0]))


# m: how close two hinge axes pass for them to meet at one point (a spherical joint's axes,
# written with the same origin, meet to rounding)
MEET = 1e-4


def axes_meet(first: tuple[Vector, Vector], second: tuple[Vector, Vector]) -> bool:
    """Whether two lines, each (a point, a unit direction), cross at one point: not parallel,
    and no farther apart than :data:`MEET` where they pass closest."""
    (p, u), (q, v) = first, second
    normal = cross(u, v)
    size = math.sqrt(sum(c * c for c in normal))
    if size < 1e-6:
        return False  # parallel: turning about both moves in one plane, no cross between
    gap = sum((q[i] - p[i]) * normal[i] for i in range(3)) / size
    return abs(gap) <= MEET


def _welded_top(link: Any) -> str:
    """The top link of the welded body ``link`` belongs to (fixed joints up from it)."""
    while _fixed(link) and _parent(link) is not None:
        link = _parent(link)
    return str(link.name)


def _fixed(link: Any) -> bool:
    """Whether ``link`` is welded to its parent (a fixed joint)."""
    joint = link.joint
    return joint is not None and joint.parent_link is not None and joint._objs[0].type == "fixed"


def run(request: Request) -> dict[str, Any]:
    probe = Probe(request)
    try:
        qpos, contacts = probe.search()
        height = probe.standing_height(qpos) if request.floating else probe.mount_height(qpos)
        # the nesting yokes, welded neighbours and a mechanism's parts after the pairs joined
        # through shapeless links (the order of the scaffold's comment)
        shapeless = probe.adjacent()
        near = probe.posed(qpos)  # the rest pose, within PhysX's contact offset
        why = {pair: "shapeless" for pair in shapeless}
        for kind, pairs in (
            ("yoke", probe.nesting_yokes(near)),
            ("welded", probe.welded_neighbours(qpos, near)),
            ("mechanism", probe.mechanism_pairs(qpos)),
        ):
            for pair in pairs:
                why.setdefault(pair, kind)
        adjacent = list(why)
    finally:
        probe.sim.close()
    answer: dict[str, Any] = {
        "qpos": qpos,
        # in contact as robospec check counts it (the search kept a clearance besides), with a
        # margin: a depth at the threshold itself (TIAGo's 1 mm spheres centred on its hand's
        # safety box: 0.99999 mm here, 1.00003 mm in check) is on either side by float noise
        "touching": [
            [a, b, depth]
            for (a, b), depth in contacts.items()
            if depth >= request.min_depth - DEPTH_NOISE
        ],
        "tried": probe.tried,
        # (one pose tried: no joint lies between the pairs touching there, so they always do)
        "always": sorted(probe.always or ()),
        "root_height": height,
        "upright": list(request.upright),
        "adjacent": adjacent,
        # why each adjacent pair is (rest_pose.ADJACENT_WHY's keys), for the scaffold's header
        "adjacent_why": [why[pair] for pair in adjacent],
    }
    if request.refinement is not None:
        try:
            found = refine_scaffold(request, answer)
        except Exception as exc:  # the scaffold's gains could not be measured: the parent says
            answer["refine_error"] = f"{type(exc).__name__}: {exc}"
        else:
            answer.update(
                gains=found.gains,
                over_rating=found.over_rating,
                refined=found.changed,
                simulations=found.simulations,
            )
    return answer


def refine_scaffold(request: Request, answer: dict[str, Any]) -> Any:
    """Scaffold the robot at the rest pose found (as the parent will: the same functions on
    the same answer), register it, and measure and refine its gains
    (:mod:`robospec.authoring.refine`)."""
    import tempfile
    from pathlib import Path

    from robospec.authoring.analysis import analyse
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.joint_gains import joint_gains
    from robospec.authoring.refine import refine
    from robospec.authoring.rest_pose import REFINE_UID, rest_from_answer
    from robospec.authoring.scaffold import scaffold
    from robospec.authoring.scaffold_controllers import unbalanced
    from robospec.description.ratings import joint_ratings
    from robospec.importer.yamlout import to_yaml
    from robospec.output.register import register
    from robospec.physics.sim import Sim
    from robospec.pipeline import compile_spec

    assert request.refinement is not None
    description, out, schema = request.refinement
    source, _ = read_description_file(Path(description))
    if source is None:
        raise ValueError(f"cannot read {description} again")
    analysis = analyse(source)
    rest = rest_from_answer(answer, analysis.description)
    gains = joint_gains(analysis, rest.qpos, unbalanced(analysis))
    draft = scaffold(analysis, Path(out), rest, REFINE_UID, absolute_paths=True, gains=gains)
    with tempfile.TemporaryDirectory(prefix="robospec-new-refine-") as folder:
        spec = Path(folder) / "refine.yaml"
        spec.write_text(to_yaml(draft, schema), encoding="utf-8")
        item = compile_spec(spec)
        if not item.ok or item.context is None or item.robot is None:
            raise ValueError("the scaffold does not compile")
        register(spec)
        ratings = {k: r.value for k, r in joint_ratings(item.context.description).items()}
        # the rest keyframe as the draft resolves it, so as robospec check will hold it: its
        # root where the description places the robot (an MJCF wrapper body's turn included:
        # the Shadow hand's mount turns its wrist across gravity, which sagged 0.073 rad there
        # and 0.002 rad upright at the origin)
        keyframe = next(k for k in item.robot.keyframes if k.name == "rest")
        sim = Sim(REFINE_UID, request.mode)
        try:
            return refine(sim, item.context.spec.checks, ratings, keyframe)
        finally:
            sim.close()


def main() -> int:
    raw = json.loads(sys.stdin.read())
    raw["limits"] = [tuple(pair) for pair in raw["limits"]]
    raw["mimic"] = [tuple(item) for item in raw.get("mimic", [])]
    raw["parents"] = {k: tuple(v) for k, v in raw.get("parents", {}).items()}
    if raw.get("refinement") is not None:
        raw["refinement"] = tuple(raw["refinement"])
    try:
        answer = run(Request(**raw))
    except Exception as exc:  # the robot could not be loaded: the parent says so and goes on
        answer = {"error": f"{type(exc).__name__}: {exc}"}
    sys.stdout.write("\n" + json.dumps(answer) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
