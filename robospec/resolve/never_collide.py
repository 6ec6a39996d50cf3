"""Stage 3, continued: bind ``never_collide`` to links and pack it into collision-group bits.

Every entry's names and globs go through the resolver's own link selection (RS202 unknown
link, RS206 a glob matching nothing). The pairs are then packed by
:func:`robospec.resolve.collision_packing.pack` into group-2 bits that nothing else uses — not
the loader's (SRDF, MJCF bodies), not the spec's ``collision_rules``, not
``scene_collision_bits`` — and come out as ordinary collision rules after the spec's own. What
the packing could not do (an entry of one link, no bit left) is the checks' to report.
"""

from __future__ import annotations

from robospec.resolve.collision_packing import FREE_BITS, Pair, clique_pairs, pack
from robospec.resolve.context import ResolveContext
from robospec.resolve.resolved import ResolvedCollisionRule, ResolvedNeverCollide
from robospec.resolve.selection import select_links


def resolve_never_collide(
    context: ResolveContext,
    user_rules: tuple[ResolvedCollisionRule, ...],
    extra: tuple[tuple[str, ...], ...] = (),
) -> tuple[tuple[ResolvedCollisionRule, ...], ResolvedNeverCollide | None]:
    """The packed rules (to append after ``user_rules``) and what the checks need to know.
    ``extra``: entries already bound to links (what the parts bring), after the spec's own."""
    spec = context.spec
    description = context.description
    if not spec.never_collide and not extra:
        return (), None
    order = {name: i for i, name in enumerate(description.link_names)}
    entries = tuple(
        tuple(
            sorted(
                set(select_links(context, entry, ("never_collide", index))), key=order.__getitem__
            )
        )
        for index, entry in enumerate(spec.never_collide)
    ) + tuple(tuple(sorted(set(links) & set(order), key=order.__getitem__)) for links in extra)
    if spec.loader.disable_self_collisions:
        return (), ResolvedNeverCollide(entries, skipped=True)

    requested: dict[Pair, int] = {}  # pair -> the first entry that lists it
    for index, links in enumerate(entries):
        for p in sorted(clique_pairs(links)):
            requested.setdefault(p, index)

    # group-2 bits the loader and the spec already set, and the pairs they already keep apart
    taken = set(spec.scene_collision_bits)
    cleared: dict[int, set[str]] = {}
    free: set[Pair] = set(description.adjacent_pairs())
    for rule in user_rules:
        if rule.group != 2:
            continue
        taken.add(rule.bit)
        if rule.value == 1:
            free |= clique_pairs(rule.links)
        else:
            cleared.setdefault(rule.bit, set()).update(rule.links)
    for bit, links in description.loader_collision_bits:
        taken.add(bit)
        free |= clique_pairs(set(links) - cleared.get(bit, set()))
    available = tuple(b for b in FREE_BITS if b not in taken)

    packing = pack(requested, free=free, available=available)
    rules = tuple(
        ResolvedCollisionRule(tuple(sorted(links, key=order.__getitem__)), 2, bit, 1)
        for bit, links in packing.cliques
    )
    side_effects: dict[int, set[Pair]] = {}
    side = set(packing.side_effects)
    for _, links in packing.cliques:
        pairs = clique_pairs(links)
        carried = pairs & side
        if carried:
            # reported at the first entry whose pairs this bit carries
            source = min(requested[p] for p in pairs if p in requested and p not in free)
            side_effects.setdefault(source, set()).update(carried)
    record = ResolvedNeverCollide(
        entries=entries,
        bits=packing.bits,
        available=available,
        side_effects=tuple(
            (index, tuple(sorted(pairs))) for index, pairs in sorted(side_effects.items())
        ),
        uncovered=packing.uncovered,
    )
    return rules, record
