"""What the compose stage takes and gives: the robot's and the parts' descriptions, the
parts as mounted, where each line of the combined text came from, and the problems found.
Plain data (see :mod:`robospec.compose`)."""

from __future__ import annotations

import bisect
import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Literal

from robospec.diagnostics import Diagnostic, Location
from robospec.geometry import Quaternion, Vector
from robospec.load.source_map import KeyPath

Kind = Literal["urdf", "mjcf"]

# the codes this stage reports (robospec/diagnostics/codes.py)


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
    position: Vector
    quaternion: Quaternion  # wxyz
    rpy: Vector | None  # the rotation as the spec wrote it, when in rpy
    joint: str  # the name of the fixed joint that mounts it
    prefix: str
    # mesh and texture URIs as the part's description writes them -> the file robospec found
    files: Mapping[str, str] = field(default_factory=dict)
    # where the spec's parts entry is: the origin of the elements composing adds (file, line)
    entry: tuple[str, int] = ("", 1)
    entry_path: str | None = None  # the spec file, absolute
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
    # each file an element came from: (as diagnostics show it, its absolute path)
    files: tuple[tuple[str, str], ...] = ()

    def path_of(self, shown: str) -> str | None:
        return next((path for name, path in self.files if name == shown), None)

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


def relocate(diagnostics: list[Diagnostic], absolute: str, composed: Composed) -> list[Diagnostic]:
    """Diagnostics of the combined text (read as ``absolute``), each at the element's line in
    the file it came from."""
    out = []
    for d in diagnostics:
        if d.location.file == absolute:
            found = composed.origins.locate(d.location.line)
            if found is not None:
                d = dataclasses.replace(d, location=Location(found[0], found[1], d.location.column))
        out.append(d)
    return out
