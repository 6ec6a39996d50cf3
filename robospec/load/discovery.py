"""Which spec files a command works on: the files named, and the spec files under the folders
named. Light (no model, no parser): ``robospec.register`` uses it on its warm-cache path too.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import SPEC_UNREADABLE
from robospec.load.reader import SPEC_SUFFIXES


def discover(paths: Iterable[Path]) -> tuple[list[Path], list[Diagnostic]]:
    """Spec files named directly, or found under folders (sorted, so output is stable)."""
    found: list[Path] = []
    diagnostics: list[Diagnostic] = []
    for path in paths:
        try:
            found.extend(_specs_at(path, diagnostics))
        except OSError as exc:  # a name too long for the file system, a loop of links, ...
            reason = exc.strerror or type(exc).__name__
            diagnostics.append(
                error(Location(str(path)), SPEC_UNREADABLE, f"cannot read: {reason}")
            )
    unique: list[Path] = []
    for p in found:
        if p not in unique:
            unique.append(p)
    return unique, diagnostics


def _specs_at(path: Path, diagnostics: list[Diagnostic]) -> list[Path]:
    """The spec named, or the spec files under a folder; a diagnostic when there are none."""
    if path.is_dir():
        inside = sorted(
            p for p in path.rglob("*") if p.suffix.lower() in SPEC_SUFFIXES and p.is_file()
        )
        if not inside:
            # a folder named by mistake (or named like a spec) must not pass as "all valid"
            diagnostics.append(
                error(
                    Location(str(path)),
                    SPEC_UNREADABLE,
                    "no spec files (.yaml, .yml, .toml) in this folder",
                )
            )
        return inside
    if path.exists():
        return [path]
    diagnostics.append(error(Location(str(path)), SPEC_UNREADABLE, "no such file or folder"))
    return []
