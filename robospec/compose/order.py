"""In which order the parts are mounted: each on a link that exists by then."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from robospec.compose.model import PartSource, Problem
from robospec.diagnostics.codes import PART_CYCLE, UNKNOWN_MOUNT


def mount_order(
    base_links: Sequence[str], parts: Sequence[PartSource], links_of: Mapping[str, Sequence[str]]
) -> tuple[list[PartSource], list[Problem]]:
    """The parts in an order where each one's ``at`` exists when it is mounted: on the base,
    or on a part mounted before (by its name there, or as its own file names it). A part
    mounted on a link no one has is RS730; parts mounted on each other in a ring, RS733."""
    from robospec.diagnostics.suggest import did_you_mean

    known = set(base_links)
    placed: list[PartSource] = []
    left = list(parts)
    while left:
        ready = [p for p in left if p.at in known]
        if not ready:
            break
        for part in ready:
            placed.append(part)
            left.remove(part)
            known.update(links_of.get(part.name, ()))
    problems: list[Problem] = []
    owners = {link: p.name for p in left for link in links_of.get(p.name, ())}
    in_rings: set[str] = set()
    for part in left:
        if part.name in in_rings:
            continue  # said at the first part of its ring
        if part.at in owners:
            ring = _ring(part, {p.name: p for p in left}, owners)
            in_rings.update(ring)
            problems.append(
                Problem(
                    ("parts", part.name, "at"),
                    PART_CYCLE,
                    f"parts are mounted on each other in a ring: {' -> '.join(ring)}",
                    "mount one of them on a link of this robot",
                )
            )
        else:
            candidates = [*base_links, *(n for p in placed for n in links_of.get(p.name, ()))]
            problems.append(
                Problem(
                    ("parts", part.name, "at"),
                    UNKNOWN_MOUNT,
                    f"part '{part.name}' is mounted on '{part.at}', a link that neither this "
                    "robot nor another part has",
                    did_you_mean(part.at, candidates),
                )
            )
    return placed, problems


def _ring(
    part: PartSource, by_name: Mapping[str, PartSource], owners: Mapping[str, str]
) -> list[str]:
    seen = [part.name]
    current = part
    while current.at in owners:
        owner = owners[current.at]
        if owner in seen:
            return [*seen[seen.index(owner) :], owner]
        seen.append(owner)
        current = by_name[owner]
    return seen
