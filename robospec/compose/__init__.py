"""Composed descriptions: a robot and the parts mounted on it (a gripper, a hand), written as
one description.

Design. A spec's ``parts:`` mount other robots — each a spec of its own or a bare description —
at links of its robot. This stage is pure: it takes the texts of the descriptions (each
already expanded and mended by the derive stage, :mod:`robospec.derive`) and writes the
combined text, URDF with URDF (:mod:`robospec.compose.urdf`), MJCF with MJCF
(:mod:`robospec.compose.mjcf`). Names of a part that the robot (or a part mounted before it)
already has get the part's prefix; the others are kept, so a part's names read as they do in
its own file. Every element of the combined text remembers the file and line it came from
(:class:`Origins`), so whatever a later stage reports about it points at the user's file — the
arm's, the hand's, or, for the joint that mounts a part, the spec's ``parts:`` entry.

The result goes the way every derived description goes: the resolve stage parses it
(:func:`robospec.resolve.description_files.load_spec_description`) and hands its text on in
the robot's ``FileRef``, so ``register``, ``build`` (self-contained, with copies of the meshes),
``check``, ``tune``, ``optimize`` and the language server load the combined description.
What comes along from a part's spec (controllers, keyframes, tcp, ...) is merged after
resolution, by :mod:`robospec.resolve.parts`.

Only lxml and the standard library are imported here: composing runs on the validate path.
"""

from __future__ import annotations

import bisect
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

from robospec.load.source_map import KeyPath

Kind = Literal["urdf", "mjcf"]

# the codes this stage reports (robospec/diagnostics/codes.py)
UNKNOWN_MOUNT = "RS730"
NOT_A_FIXED_TREE = "RS731"
CLASH = "RS732"
CYCLE = "RS733"
MIXED_FORMATS = "RS735"
PREFIXED = "RS736"
NOTHING_TO_FOLD = "RS741"


@dataclass(frozen=True)
class Problem:
    """Something about a part that the spec must change, at ``path`` in the spec."""

    path: KeyPath
    code: str
    message: str
    hint: str | None = None
    severity: Literal["error", "warning", "note"] = "error"


@dataclass(frozen=True)
class PartSource:
    """One part as the compose stage takes it: its description's text and where to mount it."""

    name: str
    kind: Kind
    text: bytes
    path: str  # the description file, absolute: relative files are found from its folder
    shown: str  # how diagnostics name it
    at: str  # the link it is mounted on
    position: tuple[float, float, float]
    quaternion: tuple[float, float, float, float]  # wxyz
    rpy: tuple[float, float, float] | None  # the rotation as the spec wrote it, when in rpy
    joint: str  # the name of the fixed joint that mounts it
    prefix: str
    # mesh and texture URIs as the part's description writes them -> the file robospec found
    files: Mapping[str, str] = field(default_factory=dict)
    # where the spec's parts entry is: the origin of the elements composing adds (file, line)
    entry: tuple[str, int] = ("", 1)
    key: Literal["spec", "description"] = "spec"  # which of the two the entry gives
    joint_given: bool = False  # the spec names the mounting joint (else it is `<part>_mount`)
    fold_frames: bool = False  # leave out the empty frames at the seam (see Part.fold_frames)


@dataclass(frozen=True)
class BaseSource:
    """The robot the parts are mounted on: its description's text (mended, expanded)."""

    kind: Kind
    text: bytes
    path: str
    shown: str


@dataclass(frozen=True)
class Mounted:
    """A part as mounted: its names in the combined description."""

    name: str
    at: str
    joint: str
    root: str  # its root link, as named now
    links: tuple[str, ...]
    joints: tuple[str, ...]
    # (what, old name, new name) for every name the prefix changed: link, joint, material, ...
    renamed: tuple[tuple[str, str, str], ...] = ()
    # empty frames fold_frames left out: the robot's mount link, the part's root (and joints)
    folded: tuple[str, ...] = ()

    def new_name(self, what: str, name: str) -> str:
        for kind, old, new in self.renamed:
            if kind == what and old == name:
                return new
        return name


@dataclass(frozen=True)
class Origins:
    """Where each line of the combined text came from: ``(line, file, line there)`` for the
    first line of each element, in line order."""

    entries: tuple[tuple[int, str, int], ...]

    def locate(self, line: int) -> tuple[str, int] | None:
        """The file and line that ``line`` of the combined text shows, or None before the
        first element."""
        lines = [entry[0] for entry in self.entries]
        index = bisect.bisect_right(lines, line) - 1
        if index < 0:
            return None
        start, file, there = self.entries[index]
        return file, there + (line - start)


@dataclass(frozen=True)
class Composed:
    """The combined description, or the problems that stopped it (then ``text`` is None)."""

    kind: Kind
    text: str | None
    origins: Origins
    parts: tuple[Mounted, ...] = ()
    problems: tuple[Problem, ...] = ()


def compose(base: BaseSource, parts: Sequence[PartSource]) -> Composed:
    """Mount ``parts`` on ``base`` (in an order where each part's link exists when it is
    mounted), as one description of ``base``'s kind."""
    mixed = [p for p in parts if p.kind != base.kind]
    if mixed:
        return Composed(
            base.kind, None, Origins(()), problems=tuple(_mixed(base, p) for p in mixed)
        )
    if base.kind == "urdf":
        from robospec.compose.urdf import compose_urdf

        return compose_urdf(base, parts)
    from robospec.compose.mjcf import compose_mjcf

    return compose_mjcf(base, parts)


def _mixed(base: BaseSource, part: PartSource) -> Problem:
    """A part of the other kind. URDF has no form for an MJCF body's several joints, its
    geoms' defaults or its sites, and ManiSkill's MJCF loader reads no URDF element; robospec
    writes no converter between the two that would keep every mass, limit and shape."""
    if base.kind == "urdf":
        why = (
            f"part '{part.name}' is MJCF and this robot is URDF: robospec writes a combined URDF "
            "from URDF parts only (an MJCF body may carry several joints, and its defaults, "
            "geoms and masses have no URDF form robospec writes)"
        )
        hint = "mount a URDF of the part (or describe this robot in MJCF)"
    else:
        why = (
            f"part '{part.name}' is URDF and this robot is MJCF: robospec writes a combined MJCF "
            "from MJCF parts only (ManiSkill's MJCF loader reads no URDF element, and robospec "
            "writes no URDF-to-MJCF conversion that keeps every inertia and shape)"
        )
        hint = "mount an MJCF of the part (or describe this robot in URDF)"
    return Problem(("parts", part.name, part.key), MIXED_FORMATS, why, hint)


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
    for part in left:
        if part.at in owners:
            ring = _ring(part, {p.name: p for p in left}, owners)
            problems.append(
                Problem(
                    ("parts", part.name, "at"),
                    CYCLE,
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
