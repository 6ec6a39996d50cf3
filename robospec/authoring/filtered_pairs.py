"""The links an MJCF's own collision filters keep apart, as ``never_collide`` entries for
``robospec new``: MuJoCo collides two geoms only where one's contype shares a bit with the
other's conaffinity, ManiSkill every pair whose contype is not 0 (RS073). A model that relies
on its filters (the Shadow hand's collision geoms never touch each other in MuJoCo: contype 1,
conaffinity 0) meets contacts in ManiSkill its makers never saw: a capsule overlapping the next
link's box by 1 mm at every pose, fingers that block each other's steps. Declaring the filtered
pairs never_collide keeps the robot as its file simulates it.

Packed as robospec's resolver packs ``never_collide``
(:func:`robospec.resolve.collision_packing.pack`, with the bits ManiSkill's MJCF loader takes
and the pairs they already keep apart): when they do not fit the free bits without disabling a
pair MuJoCo collides, none are declared (RS073 still says which pairs collide).
"""

from __future__ import annotations

from robospec.description import RobotDescription
from robospec.resolve.collision_packing import FREE_BITS, clique_pairs, pack


def filtered_cliques(description: RobotDescription) -> list[tuple[str, ...]]:
    """Sets of links, each one ``never_collide`` entry, covering the description's
    ``filtered_pairs``; empty when they do not fit."""
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
