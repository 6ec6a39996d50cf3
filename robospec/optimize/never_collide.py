"""From the sampled collision matrix to ``never_collide`` entries that the spec's bit packer can
honour without side effects.

Every pair that never touched (or always did: MoveIt disables those too, as a pair in contact at
every pose is two shapes of one rigid body in effect) may be disabled. The packer
(:func:`robospec.resolve.collision_packing.pack`) covers them with cliques, one group-2 bit each;
a clique whose links are all pairwise disabled-or-adjacent disables nothing that can touch. Only
29 bits exist, fewer once the spec's own rules and the scene's are set, so the cliques that
cover the most pairs are written, largest first, and a clique that would disable a pair that
sometimes touches is never written: the robot must behave as before.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable

from robospec.resolve.collision_packing import FREE_BITS, Pair, clique_pairs, pack


def never_collide_entries(
    disabled: Iterable[Pair], adjacent: Collection[Pair], bits: int
) -> list[list[str]]:
    """At most ``bits`` cliques covering pairs of ``disabled`` (adjacent pairs may join them
    for free), most pairs covered first; each clique disables only ``disabled`` or
    ``adjacent`` pairs. Deterministic."""
    want = {tuple(sorted(p)) for p in disabled} - {tuple(sorted(p)) for p in adjacent}
    if not want or bits <= 0:
        return []
    ok = want | {tuple(sorted(p)) for p in adjacent}
    packing = pack(want, free=adjacent, available=FREE_BITS)
    cliques = [links for _, links in packing.cliques if clique_pairs(links) <= ok]
    cliques.sort(key=lambda links: (-len(clique_pairs(links) & want), links))
    return [list(links) for links in cliques[:bits]]


def free_bits(taken: Iterable[int]) -> int:
    """How many group-2 bits a spec has left for new entries once ``taken`` are used."""
    return len(set(FREE_BITS) - set(taken))
