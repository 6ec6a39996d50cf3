"""The fast profile's contact offset: how many of a robot's own link pairs make contacts in
PhysX at its sampled configurations, with ManiSkill's 2 cm offset on every shape and with a
smaller one, and which offset stops the pairs that never touch from making any.

PhysX makes contacts for two shapes once they come nearer than the sum of their contact
offsets (ManiSkill's scene config gives every shape 0.02 m), touching or not, and each such
pair costs a narrow-phase test and solver rows every substep. The collision matrix
(:mod:`robospec.optimize.collision_matrix`) knows which pairs never touch; those the spec
cannot disable with a group-2 bit (there are too few bits) keep making contacts whenever they
are near. Here the robot is put in sampled configurations (the matrix's own, fewer) with every
pair's group bits cleared, and every contact PhysX reports between two of its links is
counted, except for the pairs the final robot never collides (adjacent links, the spec's and
the SRDF's group-2 bits): those PhysX skips before making contacts.

SAPIEN and numpy are imported inside the functions: importing this module stays cheap.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass
from itertools import combinations
from typing import TYPE_CHECKING, Any

from robospec.optimize.collision_matrix import posed_contacts
from robospec.resolve.collision_packing import Pair, pair

if TYPE_CHECKING:
    import numpy as np

    from robospec.optimize.collision_matrix import ContactScene

# the profile's offset: at most 1 mm (measured, optimized robots under random actions: from
# 2 cm to 2 mm the G1 and the Allegro hand step about 1.5x as fast, 5 mm gives no more, and
# Baxter, whose arms really touch its torso, gains another tenth from 2 mm to 1 mm; contacts
# with the scene are hardly affected, its shapes keeping ManiSkill's 2 cm), at least 0.5 mm
# (PhysX must still see a contact coming: nearer than twice this, a pair is in contact anyway)
LARGEST_OFFSET = 0.001
SMALLEST_OFFSET = 0.0005


@dataclass(frozen=True)
class ContactCount:
    """Pairs of the robot's own links making contacts, at one contact offset on every shape."""

    offset: float
    configurations: int
    pairs_per_configuration: float  # mean over the configurations
    never_touching_pairs: int  # pairs that never touch yet made contacts somewhere
    # the nearest a pair that never touches came to touching, in m (None: none came within
    # the sum of the offsets)
    nearest_gap: float | None


def disabled_pairs(
    links: Iterable[str],
    adjacent: Collection[Pair],
    bits: Iterable[tuple[int, Iterable[str]]],
) -> frozenset[Pair]:
    """The pairs the final robot never collides: parent and child (PhysX skips them in an
    articulation), and pairs of links sharing a group-2 bit (``bits``: each bit with the links
    that carry it, from every rule and loader that sets one)."""
    carried: dict[int, set[str]] = {}
    for bit, named in bits:
        carried.setdefault(bit, set()).update(named)
    known = set(links)
    disabled = {pair(a, b) for a, b in adjacent}
    for named in carried.values():
        disabled |= {pair(a, b) for a, b in combinations(sorted(named & known), 2)}
    return frozenset(disabled)


def count_contacts_at(
    loaded: ContactScene,
    rows: np.ndarray,
    offset: float,
    skip: Collection[Pair],
    never: Collection[Pair],
) -> ContactCount:
    """Put every collision shape of ``loaded`` (a :class:`ContactScene`) at ``offset`` and
    count, over the configurations ``rows``, the pairs of its links that make contacts (any
    contact point, touching or not), except the pairs in ``skip``; ``never``: the pairs the
    collision matrix found never touching."""
    links = list(loaded.robot.links)  # kept alive: contacts name these very objects
    names = {id(link): link.name for link in links}
    for link in links:
        for shape in link.collision_shapes:
            shape.set_contact_offset(offset)
    total = 0
    near_never: set[Pair] = set()
    nearest: float | None = None
    never_set = set(never)
    for contacts in posed_contacts(loaded, rows):
        made = _pairs_with_contacts(contacts, names)
        made = {key: gap for key, gap in made.items() if key not in skip}
        total += len(made)
        for key, gap in made.items():
            if key in never_set:
                near_never.add(key)
                nearest = gap if nearest is None else min(nearest, gap)
    return ContactCount(
        offset=offset,
        configurations=len(rows),
        pairs_per_configuration=total / max(len(rows), 1),
        never_touching_pairs=len(near_never),
        nearest_gap=nearest,
    )


def _pairs_with_contacts(contacts: Iterable[Any], names: Mapping[int, str]) -> dict[Pair, float]:
    """``{pair: smallest separation}`` for each pair of the robot's links with any contact."""
    made: dict[Pair, float] = {}
    for contact in contacts:
        a, b = (names.get(id(body)) for body in contact.bodies)
        if a is None or b is None or a == b or not contact.points:
            continue
        gap = min(float(point.separation) for point in contact.points)
        key = pair(a, b)
        made[key] = min(made.get(key, gap), gap)
    return made


def profile_offset(nearest_gap: float | None) -> float:
    """The fast profile's contact offset: half the nearest any pair that never touches came
    to touching (two such shapes then make no contact there), within
    [``SMALLEST_OFFSET``, ``LARGEST_OFFSET``]."""
    if nearest_gap is None:
        return LARGEST_OFFSET
    return min(LARGEST_OFFSET, max(SMALLEST_OFFSET, nearest_gap / 2))
