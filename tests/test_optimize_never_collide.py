"""never_collide entries from a collision matrix: cliques the packer honours without disabling a
pair that touches, within the bits left, the pairs nearest in the tree first."""

from __future__ import annotations

from itertools import combinations

from robospec.optimize.never_collide import never_collide_entries
from robospec.resolve.collision_packing import clique_pairs

# a chain base - a - b - c - d - e, and a side branch base - s
PARENTS = {"a": "base", "b": "a", "c": "b", "d": "c", "e": "d", "s": "base"}
ADJACENT = {tuple(sorted((child, parent))) for child, parent in PARENTS.items()}
LINKS = ["base", *PARENTS]


def _all_pairs() -> set[tuple[str, str]]:
    return {tuple(sorted(p)) for p in combinations(LINKS, 2)} - ADJACENT  # type: ignore[misc]


def test_no_entry_disables_a_pair_that_touches() -> None:
    touches = {("a", "c"), ("d", "s")}
    never = _all_pairs() - touches
    entries = never_collide_entries(never, ADJACENT, bits=29, parents=PARENTS)
    disabled = {p for entry in entries for p in clique_pairs(entry)}
    assert never <= disabled  # every never pair covered: the bits suffice here
    assert not disabled & touches


def test_with_few_bits_the_nearest_pairs_come_first() -> None:
    never = _all_pairs()
    entries = never_collide_entries(never, ADJACENT, bits=1, parents=PARENTS)
    assert len(entries) == 1
    covered = {p for p in clique_pairs(entries[0]) if p in never}
    # a pair two joints apart (a grandparent and its grandchild, or siblings) is covered
    assert any(p in covered for p in (("a", "c"), ("b", "d"), ("base", "b"), ("a", "s")))


def test_no_bits_no_entries_and_deterministic() -> None:
    assert never_collide_entries(_all_pairs(), ADJACENT, bits=0, parents=PARENTS) == []
    first = never_collide_entries(_all_pairs(), ADJACENT, bits=3, parents=PARENTS)
    assert first == never_collide_entries(_all_pairs(), ADJACENT, bits=3, parents=PARENTS)
    assert len(first) <= 3
