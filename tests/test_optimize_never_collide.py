"""never_collide entries from a collision matrix: cliques the packer honours without disabling a
pair that touches, within the bits left, the pairs nearest in the tree first; and the sampled
configurations the matrix is counted over, where a mimic joint follows its leader."""

from __future__ import annotations

from itertools import combinations

import numpy as np
from conftest import FUZZ_SCALE
from hypothesis import given, settings
from hypothesis import strategies as st

from robospec.optimize.collision_matrix import Mimic, configurations
from robospec.optimize.never_collide import never_collide_entries
from robospec.resolve.collision_packing import clique_pairs

# a chain base - a - b - c - d - e, and a side branch base - s
PARENTS = {"a": "base", "b": "a", "c": "b", "d": "c", "e": "d", "s": "base"}
ADJACENT = {tuple(sorted((child, parent))) for child, parent in PARENTS.items()}
LINKS = ["base", *PARENTS]
# every pair two joints apart in that tree: grandparent and grandchild, or siblings
TWO_APART = {("a", "c"), ("b", "d"), ("c", "e"), ("b", "base"), ("a", "s")}


def _all_pairs() -> set[tuple[str, str]]:
    return {tuple(sorted(p)) for p in combinations(LINKS, 2)} - ADJACENT  # type: ignore[misc]


def _disabled(entries: list[list[str]]) -> set[tuple[str, str]]:
    return {p for entry in entries for p in clique_pairs(entry)}


def test_no_entry_disables_a_pair_that_touches() -> None:
    touches = {("a", "c"), ("d", "s")}
    never = _all_pairs() - touches
    entries = never_collide_entries(never, ADJACENT, bits=29, parents=PARENTS)
    disabled = _disabled(entries)
    assert never <= disabled  # every never pair covered: the bits suffice here
    assert not disabled & touches


def test_with_few_bits_the_nearest_pairs_come_first() -> None:
    # b and s (three joints apart) touch, so no one clique holds every pair two joints apart:
    # with two bits each of those pairs is covered, and the pair that touches is not
    never = _all_pairs() - {("b", "s")}
    entries = never_collide_entries(never, ADJACENT, bits=2, parents=PARENTS)
    assert len(entries) == 2
    covered = _disabled(entries)
    for pair in sorted(TWO_APART):  # each one, not any one of them
        assert pair in covered, (pair, entries)
    assert ("b", "s") not in covered


def test_a_band_that_does_not_fit_gets_the_bits_left_and_no_more() -> None:
    # one bit for the same robot: the band two joints apart needs two, so the bit goes to
    # the clique covering most of it, and nothing disables the pair that touches
    never = _all_pairs() - {("b", "s")}
    (entry,) = never_collide_entries(never, ADJACENT, bits=1, parents=PARENTS)
    covered = clique_pairs(entry)
    assert ("b", "s") not in covered
    assert len(covered & TWO_APART) == 4  # all but (a, s): s cannot join b's clique


def test_one_bit_covers_every_near_pair_when_no_pair_touches() -> None:
    # nothing touches: one clique of every link is one bit for every pair, the farther
    # pairs taken in for free
    never = _all_pairs()
    entries = never_collide_entries(never, ADJACENT, bits=1, parents=PARENTS)
    assert len(entries) == 1
    covered = _disabled(entries)
    for pair in sorted(TWO_APART):
        assert pair in covered, (pair, entries)
    assert never <= covered


def test_no_bits_no_entries_and_deterministic() -> None:
    assert never_collide_entries(_all_pairs(), ADJACENT, bits=0, parents=PARENTS) == []
    first = never_collide_entries(_all_pairs(), ADJACENT, bits=3, parents=PARENTS)
    assert first == never_collide_entries(_all_pairs(), ADJACENT, bits=3, parents=PARENTS)
    assert len(first) <= 3


@st.composite
def trees(draw: st.DrawFn) -> tuple[dict[str, str], set[tuple[str, str]], int]:
    """A random tree of 3-14 links (each link's parent drawn among the links before it), the
    pairs that never touch (most of the pairs a joint does not join: partial bands are the
    common case), and the free bits."""
    count = draw(st.integers(3, 14))
    names = [f"l{i:02d}" for i in range(count)]
    parents = {names[i]: names[draw(st.integers(0, i - 1))] for i in range(1, count)}
    adjacent = {tuple(sorted(p)) for p in parents.items()}
    rest = sorted({tuple(sorted(p)) for p in combinations(names, 2)} - adjacent)
    touching = set(draw(st.lists(st.sampled_from(rest), max_size=max(len(rest) // 4, 1))))
    bits = draw(st.integers(0, 8))
    return parents, set(rest) - touching, bits  # type: ignore[return-value]


@settings(max_examples=max(round(200 * FUZZ_SCALE), 25), deadline=None)
@given(trees())
def test_entries_fit_the_free_bits_and_disable_only_pairs_that_never_touch(
    tree: tuple[dict[str, str], set[tuple[str, str]], int],
) -> None:
    parents, never, bits = tree
    adjacent = {tuple(sorted(p)) for p in parents.items()}
    entries = never_collide_entries(never, adjacent, bits=bits, parents=parents)
    assert len(entries) <= bits, f"{len(entries)} entries for {bits} free bit(s)"
    for entry in entries:
        assert len(entry) >= 2
        stray = clique_pairs(entry) - never - adjacent
        assert not stray, f"{entry} disables pairs that touch: {sorted(stray)}"
    assert entries == never_collide_entries(never, adjacent, bits=bits, parents=parents)


def test_a_mimic_of_a_mimic_listed_before_its_leader_follows_it() -> None:
    # c mimics b, which mimics a; c is listed first, so one pass in list order would set c
    # from b's drawn value, before b follows a
    names = ["a", "b", "c"]
    lower, upper = np.full(3, -1.0), np.full(3, 1.0)
    mimics = [Mimic("c", "b", 2.0, 0.1), Mimic("b", "a", -0.5, 0.2)]
    keyframe = {"a": 0.4}
    rows = configurations(names, lower, upper, mimics, [keyframe], 50, seed=3)
    a, b, c = rows[:, 0], rows[:, 1], rows[:, 2]
    np.testing.assert_allclose(b, -0.5 * a + 0.2)
    np.testing.assert_allclose(c, 2.0 * b + 0.1)
    assert rows[0, 0] == 0.4 and np.isclose(rows[0, 2], 2.0 * (-0.5 * 0.4 + 0.2) + 0.1)
