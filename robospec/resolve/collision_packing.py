"""Pack ``never_collide`` pairs into the fewest collision-group bits. Pure: no SAPIEN here.

How PhysX decides, as SAPIEN configures it (``TypeAffinityIgnoreFilterShader``): two shapes do
not collide when ``(a.group2 & b.group2) != 0`` and the low 16 bits of their group 3 are equal.
So every bit of group 2 makes the links that carry it a *clique*: no two of them collide. What
ManiSkill's own route does with an SRDF — one bit per ``disable_collisions`` pair — spends a bit
where a clique of eight links needs one for all 28 of its pairs; group 2 has only 32 bits.

Two instances of one robot in a scene share those bits. SAPIEN leaves group 3 at 0 on every
shape of a robot (ManiSkill's loaders do not touch it), and measured on physx_cpu two pandas
whose links overlap stop colliding with *each other* once both carry the same group-2 bit.
So a bit set on links of robot A also disables collisions between those links and the links
of robot B that carry it: ``never_collide`` on a multi-robot scene (``robot_uids=(a, a)``)
also keeps the listed links of the two robots from colliding with one another.

The problem, then: the requested pairs form a graph; cover its edges with the fewest cliques
(an *edge clique cover*). Links that already never collide — parent and child in the tree,
which PhysX ignores in an articulation; pairs sharing a bit the loader set from an SRDF or an
MJCF body tree; pairs of the spec's own ``collision_rules`` — need no cover, but may join a
clique for free. :func:`pack` grows cliques greedily and then, when the instance is small enough
for its step budget, searches the maximal cliques for a smaller exact cover. When the cover
needs more bits than are free it merges cliques, each time the two whose union stops the
fewest further pairs from colliding, and reports those pairs as side effects.

Bits: 0..28 only. 29 is ``disable_self_collisions``'s; ManiSkill sets 30 on the ground of its
scenes (wheels ignore it) and 31 on fetch's base, on xarm6_robotiq's links and, in RoboCasa, on
the robot's base. The caller removes the loader's, the spec's and the scenes' bits from what it
offers.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass
from itertools import combinations

NEVER_USED = frozenset({29, 30, 31})
FREE_BITS: tuple[int, ...] = tuple(range(29))
DEFAULT_BUDGET = 50_000  # search steps for the exact cover; beyond it the greedy cover stands

Pair = tuple[str, str]


def pair(a: str, b: str) -> Pair:
    """A pair of links as :func:`pack` keys them: sorted."""
    return (a, b) if a <= b else (b, a)


def clique_pairs(links: Iterable[str]) -> set[Pair]:
    """Every pair of distinct links in ``links``."""
    return {pair(a, b) for a, b in combinations(sorted(set(links)), 2)}


@dataclass(frozen=True)
class Packing:
    """Group-2 bits to set, each on a clique of links (sorted by bit, links sorted)."""

    cliques: tuple[tuple[int, tuple[str, ...]], ...]
    # pairs neither requested nor already non-colliding that share a bit: bits were short
    side_effects: tuple[Pair, ...] = ()
    # requested pairs no bit covers: no bit was free at all
    uncovered: tuple[Pair, ...] = ()

    @property
    def bits(self) -> tuple[int, ...]:
        return tuple(bit for bit, _ in self.cliques)

    def disabled_pairs(self) -> set[Pair]:
        """Every pair of links sharing one of the packed bits."""
        return {p for _, links in self.cliques for p in clique_pairs(links)}


def pack(
    requested: Iterable[Pair],
    *,
    free: Collection[Pair] = (),
    available: Iterable[int] = FREE_BITS,
    budget: int = DEFAULT_BUDGET,
) -> Packing:
    """Cover every ``requested`` pair with a bit from ``available`` (29-31 are never taken).

    ``free`` pairs already never collide: they need no bit and may share one at no cost.
    Deterministic: the same input gives the same cliques and bits.
    """
    free_pairs = {pair(a, b) for a, b in free if a != b}
    need = {pair(a, b) for a, b in requested if a != b} - free_pairs
    bits = sorted({b for b in available if 0 <= b < 32} - NEVER_USED)
    if not need:
        return Packing(())
    if not bits:
        return Packing((), uncovered=tuple(sorted(need)))
    ok = need | free_pairs
    nodes = sorted({x for p in need for x in p})
    adjacency: dict[str, set[str]] = {v: set() for v in nodes}
    for a, b in ok:
        if a in adjacency and b in adjacency:
            adjacency[a].add(b)
            adjacency[b].add(a)
    cover = _greedy_cover(need, adjacency)
    if len(cover) > 1:
        cover = _exact_cover(need, adjacency, cover, budget)
    cover = _trim(cover, need)
    while len(cover) > len(bits):
        cover = _trim(_merge_cheapest(cover, ok), need)
    ordered = sorted(tuple(sorted(c)) for c in cover)
    cliques = tuple(zip(bits, ordered, strict=False))
    side = sorted({p for _, links in cliques for p in clique_pairs(links)} - ok)
    return Packing(cliques, side_effects=tuple(side))


# -- covering ----------------------------------------------------------------------------------


def _greedy_cover(need: set[Pair], adjacency: dict[str, set[str]]) -> list[frozenset[str]]:
    """Take the first uncovered pair, grow a maximal clique around it preferring links that
    cover the most uncovered pairs; repeat."""
    uncovered = set(need)
    cover: list[frozenset[str]] = []
    while uncovered:
        a, b = min(uncovered)
        clique = {a, b}
        candidates = sorted(adjacency[a] & adjacency[b])
        while candidates:
            best = max(candidates, key=lambda v: sum(pair(v, u) in uncovered for u in clique))
            clique.add(best)
            candidates = [v for v in candidates if v != best and v in adjacency[best]]
        cover.append(frozenset(clique))
        uncovered -= clique_pairs(clique)
    return cover


def _maximal_cliques(adjacency: dict[str, set[str]], budget: list[int]) -> list[frozenset[str]]:
    """Bron–Kerbosch with pivoting, in sorted order; stops when the budget runs out."""
    found: list[frozenset[str]] = []

    def expand(r: set[str], p: set[str], x: set[str]) -> None:
        budget[0] -= 1
        if budget[0] < 0:
            return
        if not p and not x:
            if len(r) > 1:
                found.append(frozenset(r))
            return
        pivot = max(sorted(p | x), key=lambda u: len(adjacency[u] & p))
        for v in sorted(p - adjacency[pivot]):
            expand(r | {v}, p & adjacency[v], x & adjacency[v])
            p = p - {v}
            x = x | {v}

    expand(set(), set(adjacency), set())
    return found


def _exact_cover(
    need: set[Pair],
    adjacency: dict[str, set[str]],
    greedy: list[frozenset[str]],
    budget: int,
) -> list[frozenset[str]]:
    """A cover with the fewest cliques: some minimum edge clique cover consists of maximal
    cliques, so branch over the maximal cliques containing the hardest uncovered pair. Gives
    the greedy cover back when the budget runs out before a smaller one is proven."""
    steps = [budget]
    cliques = _maximal_cliques(adjacency, steps)
    if steps[0] < 0:
        return greedy
    covers = [clique_pairs(c) & need for c in cliques]
    by_pair: dict[Pair, list[int]] = {p: [] for p in need}
    for index, pairs in enumerate(covers):
        for p in pairs:
            by_pair[p].append(index)
    largest = max(len(c) for c in covers)
    best: list[list[int]] = []
    limit = [len(greedy)]

    def search(uncovered: set[Pair], chosen: list[int]) -> None:
        steps[0] -= 1
        if steps[0] < 0:
            return
        if not uncovered:
            if len(chosen) < limit[0]:
                limit[0] = len(chosen)
                best[:] = [list(chosen)]
            return
        if len(chosen) + -(-len(uncovered) // largest) >= limit[0]:
            return
        hardest = min(uncovered, key=lambda p: (len(by_pair[p]), p))
        options = sorted(by_pair[hardest], key=lambda i: (-len(covers[i] & uncovered), i))
        for index in options:
            chosen.append(index)
            search(uncovered - covers[index], chosen)
            chosen.pop()

    search(set(need), [])
    if not best:
        return greedy
    return [cliques[i] for i in best[0]]


def _trim(cover: Sequence[frozenset[str]], need: set[Pair]) -> list[frozenset[str]]:
    """Drop cliques whose needed pairs others cover, then links a clique does not need."""
    cliques = [set(c) for c in cover]
    owned = [clique_pairs(c) & need for c in cliques]
    count: Counter[Pair] = Counter(p for pairs in owned for p in pairs)
    order = sorted(range(len(cliques)), key=lambda i: (len(owned[i]), i))
    kept = set(range(len(cliques)))
    for i in order:
        if all(count[p] > 1 for p in owned[i]):
            kept.discard(i)
            count.subtract(owned[i])
    for i in sorted(kept):
        members = cliques[i]
        changed = True
        while changed:
            changed = False
            for v in sorted(members):
                own = {pair(v, u) for u in members if u != v} & need
                if all(count[p] > 1 for p in own):
                    members.discard(v)
                    count.subtract(own)
                    changed = True
                    break
    return [frozenset(cliques[i]) for i in sorted(kept) if len(cliques[i]) > 1]


def _merge_cheapest(cover: list[frozenset[str]], ok: set[Pair]) -> list[frozenset[str]]:
    """Merge the two cliques whose union disables the fewest pairs nothing disables yet."""
    disabled: dict[str, set[str]] = {}
    for a, b in set().union(*(clique_pairs(c) for c in cover)) | ok:
        disabled.setdefault(a, set()).add(b)
        disabled.setdefault(b, set()).add(a)
    best: tuple[int, int, int] | None = None
    for i, j in combinations(range(len(cover)), 2):
        first, second = cover[i] - cover[j], cover[j] - cover[i]
        cost = sum(len(second - disabled.get(a, set())) for a in first)
        if best is None or cost < best[0]:
            best = (cost, i, j)
    assert best is not None
    _, i, j = best
    merged = cover[i] | cover[j]
    return [c for k, c in enumerate(cover) if k not in (i, j)] + [merged]
