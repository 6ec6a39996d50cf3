"""From the sampled collision matrix to ``never_collide`` entries that the spec's bit packer can
honour without side effects.

Every pair that never touched (or always did: MoveIt disables those too, as a pair in contact at
every pose is two shapes of one rigid body in effect) may be disabled. The packer
(:func:`robospec.resolve.collision_packing.pack`) covers them with cliques, one group-2 bit each;
a clique whose links are all pairwise disabled-or-adjacent disables nothing that can touch.
Only 29 bits exist, fewer once the spec's own rules and the scene's are set, and a humanoid has
hundreds of such pairs: too many to cover. What costs PhysX time is a pair whose bounding boxes
overlap — links a joint or two apart in the tree — while a left ankle and a right shoulder are
never looked at past the broad phase. So pairs are taken nearest first: all pairs at most two
joints apart, then three, ... as far as the bits cover them without a side effect, and the
remaining bits go to the cliques of the next band that cover the most pairs.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.resolve.collision_packing import FREE_BITS, Pair, clique_pairs, pack

if TYPE_CHECKING:
    from robospec.optimize.collision_matrix import CollisionMatrix
    from robospec.pipeline import CompiledSpec


def never_collide_entries(
    disabled: Iterable[Pair],
    adjacent: Collection[Pair],
    bits: int,
    parents: Mapping[str, str] | None = None,
) -> list[list[str]]:
    """At most ``bits`` cliques covering pairs of ``disabled`` (adjacent pairs may join them for
    free), nearest pairs first (``parents``: link -> parent link, the tree); each clique
    disables only ``disabled`` or ``adjacent`` pairs. Deterministic."""
    adjacent_pairs = {_sorted(p) for p in adjacent}
    want = {_sorted(p) for p in disabled} - adjacent_pairs
    if not want or bits <= 0:
        return []
    ok = want | adjacent_pairs
    available = sorted(FREE_BITS)[:bits]
    distance = _tree_distance(parents or {})
    bands = sorted({distance(p) for p in want})
    chosen: list[tuple[str, ...]] = []
    for band in bands:
        near = {p for p in want if distance(p) <= band}
        # the farther pairs that never touch need no bit in this band, but a clique may take
        # them in for free: a bit then covers more than the band
        free = ok - near
        packing = pack(near, free=free, available=available)
        if packing.side_effects or packing.uncovered:
            # this band does not fit: what is left of the bits goes to its best cliques
            whole = pack(near, free=free, available=FREE_BITS)
            covered = {p for links in chosen for p in clique_pairs(links)}
            extra = [
                links
                for _, links in whole.cliques
                if clique_pairs(links) <= ok and not clique_pairs(links) & want <= covered
            ]
            extra.sort(key=lambda links: (-len((clique_pairs(links) & want) - covered), links))
            chosen += extra[: bits - len(chosen)]
            break
        chosen = [links for _, links in packing.cliques]
    return [list(links) for links in chosen]


def free_bits(taken: Iterable[int]) -> int:
    """How many group-2 bits a spec has left for new entries once ``taken`` are used."""
    return len(set(FREE_BITS) - set(taken))


def _sorted(p: Iterable[str]) -> Pair:
    a, b = sorted(p)
    return (a, b)


def _tree_distance(parents: Mapping[str, str]) -> Callable[[Pair], int]:
    """Joints between two links of the tree (links it does not know: far apart)."""

    def chain(link: str) -> list[str]:
        out = [link]
        while out[-1] in parents and len(out) <= len(parents):
            out.append(parents[out[-1]])
        return out

    def distance(p: Pair) -> int:
        a, b = chain(p[0]), chain(p[1])
        common = set(a) & set(b)
        if not common:
            return len(parents) + 1
        return next(i for i, x in enumerate(a) if x in common) + next(
            i for i, x in enumerate(b) if x in common
        )

    return distance


def sampled_entries(
    urdf_file: Path, urdf: Any, compiled: CompiledSpec, samples: int, seed: int
) -> tuple[list[list[str]], CollisionMatrix]:
    """never_collide entries for the pairs of the URDF (``urdf_file``, read as ``urdf``) that
    touched in no sampled configuration and no keyframe (or in every one), within the group-2
    bits the spec leaves free; and the collision matrix they come from."""
    assert compiled.robot is not None and compiled.context is not None  # compiled
    from robospec.optimize.collision_matrix import sample_collision_matrix
    from robospec.optimize.links import child

    robot = compiled.robot
    keyframes = [
        dict(zip(robot.active_joints, keyframe.qpos, strict=False))
        for keyframe in robot.keyframes
        if keyframe.qpos is not None
    ]
    matrix = sample_collision_matrix(
        str(urdf_file),
        samples=samples,
        seed=seed,
        keyframes=keyframes,
        fix_root_link=robot.fix_root_link,
    )
    taken = {rule.bit for rule in robot.collision_rules if rule.group == 2}
    taken |= set(compiled.context.spec.scene_collision_bits)
    assert compiled.description is not None
    taken |= {bit for bit, _ in compiled.description.loader_collision_bits}
    parents = {
        name: parent.get("link")
        for joint in urdf.iter("joint")
        if (name := child(joint)) is not None and (parent := joint.find("parent")) is not None
    }
    entries = never_collide_entries(
        matrix.never | matrix.always, matrix.adjacent, free_bits(taken), parents
    )
    return entries, matrix
