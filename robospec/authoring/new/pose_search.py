"""The rest-pose search of ``robospec new``: from a starting pose, a pose in which no two links
touch, over any function that says which pairs of links touch how deeply at a pose (in the
probe's child process, ManiSkill's contacts: :mod:`.probe`; in tests, a made-up geometry).

The search is deterministic: from the starting pose, the smallest move of one joint (of those
between two touching links, by 10, 20, 35 or 50 % of its range, either way) that leaves fewer
pairs touching (:func:`better`); when no move helps, a chain of such moves of the joints between
one touching pair, each leaving links less deep in each other, kept if it ends with fewer pairs
touching (:meth:`PoseSearch._descend`); then random moves of all those joints at once, from a
fixed seed. A pose changes only to undo a contact, so a contact nothing undoes leaves the
starting pose as it was; :attr:`PoseSearch.always` names the pairs that touched in every pose
tried.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Iterator, Mapping, Sequence

from robospec.authoring.new.joint_space import NEIGHBOURS, JointSpace

Pair = tuple[str, str]
Contacts = dict[Pair, float]  # pair of links -> how deep in each other (m; < 0: apart by that)
# the pairs of links in contact (or nearly: within the simulator's contact offset) at a pose
ContactsAt = Callable[[list[float]], Mapping[Pair, float]]
Move = tuple[list[float], Contacts]  # a pose tried, and the pairs touching there

STEPS = (0.1, 0.2, 0.35, 0.5)
SEED = 0
# the chain of moves that deepen no contact (PoseSearch._descend): moves at most, and by how
# much each must leave the pair shallower (m: more than the depth's noise between two loads)
DESCENT_MOVES = 8
DESCENT_GAIN = 0.002
# the search keeps links this far apart (m): two links just touching block each other, and a
# step of one towards the other (robospec check's step response) goes nowhere
CLEARANCE = 0.002
BUDGET = 600  # poses tried at most


def better(new: Contacts, old: Contacts) -> bool:
    """Fewer touching pairs. Depth alone does not count: two shapes that overlap where their
    links are joined touch in every pose, more or less deeply, and chasing that depth led the
    search to poses no one would choose (legs splayed to shave a millimetre)."""
    return len(new) < len(old)


class PoseSearch:
    """One search over ``contacts_at``: :meth:`search` finds the pose; :attr:`tried` counts the
    poses tried and :attr:`always` holds the pairs every one of them touched."""

    def __init__(
        self,
        space: JointSpace,
        contacts_at: ContactsAt,
        clearance: float = CLEARANCE,
        budget: int = BUDGET,
    ) -> None:
        self.space = space
        self.contacts_at = contacts_at
        self.clearance = clearance
        self.budget = budget
        self.tried = 0
        self.always: set[Pair] | None = None  # the pairs every pose tried touched

    def contacts(self, qpos: list[float]) -> Contacts:
        """The pairs closer than the clearance at ``qpos`` (one pose more tried)."""
        self.tried += 1
        touching = {
            pair: depth
            for pair, depth in sorted(self.contacts_at(qpos).items())
            if depth >= -self.clearance
        }
        self.always = set(touching) if self.always is None else self.always & set(touching)
        return touching

    def search(self, start: Sequence[float]) -> Move:
        best = self.space.follow(list(start))
        best_contacts = self.contacts(best)
        rng = random.Random(SEED)
        while best_contacts and self.tried < self.budget:
            candidates = self.space.movable(best_contacts)
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

    def _greedy(self, qpos: list[float], contacts: Contacts, joints: list[int]) -> Move | None:
        """The smallest move of one joint that undoes a contact (smaller steps first)."""
        for step in STEPS:
            for move in self._moves(qpos, step, joints):
                if move is None:  # the budget is spent
                    return None
                if better(move[1], contacts):
                    return move
        return None

    def _moves(self, qpos: list[float], step: float, joints: list[int]) -> Iterator[Move | None]:
        """Each of ``joints`` moved ``step`` of its span each way from ``qpos`` (mimics
        following), with the contacts there; ``None`` last when the budget runs out first."""
        for index in joints:
            for sign in (1.0, -1.0):
                if self.tried >= self.budget:
                    yield None
                    return
                trial = list(qpos)
                trial[index] = qpos[index] + sign * step * self.space.span(index)
                trial = self.space.follow(trial)
                if trial != qpos:
                    yield trial, self.contacts(trial)

    def _descend(self, qpos: list[float], contacts: Contacts) -> Move | None:
        """Undo a contact no single move undoes, by a chain of moves of the joints between its
        two links, each leaving the links that are not neighbours less deep in each other in
        all (:meth:`_intrusion`): iCub's right forearm, 65 mm inside its torso, comes out by
        turning the shoulder twice, and the first turn leaves as many pairs touching as before
        (the forearm 5 mm in the torso, 4 mm in the thigh). The pairs whose links are furthest
        apart go first (a hand in the hip, rather than shapes that overlap where they are
        joined), then the deepest. The chain is kept only if it ends with fewer pairs touching:
        a pose changes only to undo a contact."""
        apart = self.space.apart
        pairs = sorted(
            (pair for pair in contacts if apart(*pair) > NEIGHBOURS),
            key=lambda pair: (-apart(*pair), -contacts[pair]),
        )
        for pair in pairs:
            joints = self.space.nearest_first(*pair)
            here, depth = list(qpos), self._intrusion(contacts, contacts)
            for _ in range(DESCENT_MOVES):
                found = self._shallower(here, depth, joints, contacts)
                if found is None:
                    break
                here, touching = found
                if better(touching, contacts):
                    return here, touching
                depth = self._intrusion(touching, contacts)
            if self.tried >= self.budget:
                return None
        return None

    def _shallower(
        self, qpos: list[float], depth: float, joints: list[int], base: Contacts
    ) -> Move | None:
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
            depth + self.clearance
            for pair, depth in contacts.items()
            if pair not in base or self.space.apart(*pair) > NEIGHBOURS
        )

    def _random(
        self, qpos: list[float], contacts: Contacts, joints: list[int], rng: random.Random
    ) -> Move | None:
        for _ in range(4 * len(joints)):
            if self.tried >= self.budget:
                return None
            trial = list(qpos)
            for index in joints:
                trial[index] += rng.uniform(-0.5, 0.5) * self.space.span(index)
            trial = self.space.follow(trial)
            touching = self.contacts(trial)
            if better(touching, contacts):
                return trial, touching
        return None
