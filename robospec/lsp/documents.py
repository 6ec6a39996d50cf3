"""What the server knows about each open spec: its text as the editor holds it (unsaved), the
compilation of that text, and the files the compilation read.

Everything here is plain Python over the pipeline (no LSP types), so it is tested and
benchmarked without a client. Descriptions are parsed through one
:class:`~robospec.description.memo.DescriptionMemo` for the life of the server: an edit of the
spec reuses the parsed URDF, an edit of the URDF (on disk) parses it again.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robospec.description.facts import RobotDescription
from robospec.description.memo import DescriptionMemo, remembering
from robospec.diagnostics import Diagnostic, Location
from robospec.load.reader import SPEC_SUFFIXES
from robospec.pipeline import CompiledSpec, compile_spec
from robospec.resolve.description_loading import EXPANDED
from robospec.resolve.paths import in_maniskill


def _signature(path: Path) -> tuple[int, int] | None:
    try:
        status = path.stat()
    except (OSError, ValueError):
        return None
    return status.st_mtime_ns, status.st_size


@dataclass
class Analysis:
    """One compilation of one spec text."""

    path: Path  # the spec file (absolute)
    text: str
    version: int | None
    compiled: CompiledSpec
    # the description file it read (absolute), None when it read none
    description_file: Path | None
    # signatures of the files read besides the spec (description, SRDF): a change makes it stale
    read: dict[Path, tuple[int, int] | None] = field(default_factory=dict)

    @property
    def fmt(self) -> str:
        return SPEC_SUFFIXES.get(self.path.suffix.lower(), "yaml")

    @property
    def description(self) -> RobotDescription | None:
        return self.compiled.description

    @property
    def data(self) -> Any:
        loaded = self.compiled.loaded
        return loaded.data if loaded is not None else None

    @property
    def expanded(self) -> bool:
        """The description is a xacro's expansion: its lines are not the file's."""
        data = self.data
        return (
            isinstance(data, dict)
            and isinstance(data.get("description"), dict)
            and ("xacro" in data["description"])
        )

    def stale(self) -> bool:
        return any(_signature(path) != known for path, known in self.read.items())

    def by_file(self) -> dict[Path, list[Diagnostic]]:
        """The diagnostics by the file they are in: the spec's, and the description's (a
        problem in the URDF is shown in the URDF). What cannot be placed in a file (a xacro's
        expansion) is shown on the spec's ``description`` key, naming where it is."""
        out: dict[Path, list[Diagnostic]] = {self.path: []}
        for diagnostic in self.compiled.diagnostics:
            file = self.file_of(diagnostic.location.file)
            if file is None:
                diagnostic = self._on_spec(diagnostic)
                file = self.path
            out.setdefault(file, []).append(diagnostic)
        return out

    def file_of(self, shown: str) -> Path | None:
        """The file a diagnostic's ``file`` names, as the pipeline showed it."""
        if shown == str(self.path):
            return self.path
        if shown.endswith(EXPANDED):
            return None
        found = in_maniskill(shown)
        if found is not None:
            return found[2]
        candidate = Path(os.path.normpath(shown))
        return candidate if candidate.is_absolute() and candidate.is_file() else None

    def element_at(self, line: int) -> tuple[Path, int] | None:
        """The file and line of the description's element on ``line`` — in the file it came
        from, for a description composed with parts."""
        composed = self.compiled.composed
        if composed is None:
            return (self.description_file, line) if self.description_file is not None else None
        found = composed.origins.locate(line)
        if found is None:
            return None
        path = composed.origins.path_of(found[0])
        return (Path(path), found[1]) if path is not None else None

    def _on_spec(self, diagnostic: Diagnostic) -> Diagnostic:
        loaded = self.compiled.loaded
        where = (
            loaded.source.key(("description",)) if loaded is not None else Location(str(self.path))
        )
        loc = diagnostic.location
        shown = Path(loc.file.removesuffix(EXPANDED)).name
        suffix = EXPANDED if loc.file.endswith(EXPANDED) else ""
        return Diagnostic(
            where,
            diagnostic.code,
            diagnostic.severity,
            f"{shown}{suffix}:{loc.line}:{loc.column}: {diagnostic.message}",
            diagnostic.hint,
        )


def _part_files(compiled: CompiledSpec) -> list[Path]:
    """The files the parts of a spec were read from: their descriptions (the combined
    description's origins) and their specs."""
    files: list[Path] = []
    if compiled.composed is not None:
        files += [Path(path) for _, path in compiled.composed.origins.files]
    if compiled.robot is not None:
        files += [Path(path) for path in compiled.robot.description.sources]
    return list(dict.fromkeys(files))


class Workspace:
    """The open specs, compiled on demand, and the description files they read."""

    def __init__(self) -> None:
        self.memo = DescriptionMemo()
        self.texts: dict[Path, tuple[str, int | None]] = {}
        self.analyses: dict[Path, Analysis] = {}

    def open(self, path: Path, text: str, version: int | None = None) -> None:
        self.texts[path] = (text, version)

    def close(self, path: Path) -> None:
        self.texts.pop(path, None)
        self.analyses.pop(path, None)

    def is_spec(self, path: Path) -> bool:
        return path.suffix.lower() in SPEC_SUFFIXES

    def analyse(self, path: Path) -> Analysis:
        """Compile the spec's current text (the editor's, else the file's)."""
        text, version = self.texts.get(path, (None, None))
        if text is None:
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                text = ""
        with remembering(self.memo):
            compiled = compile_spec(path, str(path), text=text.encode("utf-8"))
        description_file = None
        if compiled.description is None and compiled.loaded is not None:
            # a spec with errors in its model (half written) is not resolved: its description
            # (with its parts mounted) is still what completion and hover need
            data = compiled.loaded.data
            if isinstance(data, dict) and isinstance(data.get("parts"), dict):
                self._with_parts_alone(path, data, compiled)
            else:
                compiled.description = self._description_alone(path, data)
        if compiled.description is not None:
            description_file = Path(compiled.description.path)
        read: dict[Path, tuple[int, int] | None] = {}
        if description_file is not None:
            read[description_file] = _signature(description_file)
            srdf = description_file.with_suffix(".srdf")
            read[srdf] = _signature(srdf)
        for part_file in _part_files(compiled):  # a part's spec or description edited on disk
            read[part_file] = _signature(part_file)
        analysis = Analysis(path, text, version, compiled, description_file, read)
        self.analyses[path] = analysis
        return analysis

    def _with_parts_alone(self, spec: Path, data: dict[str, Any], compiled: CompiledSpec) -> None:
        """The combined description of a half-written spec's description and parts, and what
        came along from the parts' specs: compiled from those two keys alone (YAML reads the
        JSON written here), whatever else the spec has wrong."""
        import json

        alone = {
            "robospec": 1,
            "uid": "robospec_lsp_parts",
            "description": data.get("description"),
            "parts": data["parts"],
            "control_modes": {"mode": "controller"},  # required; unknown, and never resolved
        }
        try:
            text = json.dumps(alone).encode("utf-8")
        except (TypeError, ValueError):
            return
        with remembering(self.memo):
            found = compile_spec(spec, str(spec), text=text)
        compiled.description = found.description
        compiled.composed = found.composed
        compiled.part_origins = found.part_origins

    def describe_from(self, analysis: Analysis, data: Any) -> None:
        """Give ``analysis`` (of a text that does not parse) the description that ``data``
        (the same text, repaired where the cursor is) names, if it has none."""
        if analysis.compiled.description is not None:
            return
        description = self._description_alone(analysis.path, data)
        if description is None:
            return
        analysis.compiled.description = description
        analysis.description_file = Path(description.path)
        analysis.read[analysis.description_file] = _signature(analysis.description_file)

    def _description_alone(self, spec: Path, data: Any) -> RobotDescription | None:
        """The URDF or MJCF a spec names (not a xacro: that needs expanding), loaded alone as
        the spec would load it (robospec.resolve.description_loading); its problems are the
        compilation's to tell."""
        from robospec.resolve.description_loading import DescriptionEntry, Loaded, Reader, load

        given = data.get("description") if isinstance(data, dict) else None
        if not isinstance(given, dict):
            return None
        for kind in ("urdf", "mjcf"):
            text = given.get(kind)
            if not isinstance(text, str):
                continue
            reader = Reader(spec.parent, spec.parent, lambda _: Location(str(spec)))
            with remembering(self.memo):
                loaded = load(reader, DescriptionEntry(text, kind))
            return loaded.description if isinstance(loaded, Loaded) else None
        return None

    def current(self, path: Path) -> Analysis:
        """The analysis of the spec's current text, compiled again only when the text or a
        file it read changed since."""
        known = self.analyses.get(path)
        text, _ = self.texts.get(path, (None, None))
        if known is None or known.stale() or (text is not None and known.text != text):
            return self.analyse(path)
        return known

    def dependents(self, changed: Path) -> Iterator[Path]:
        """The open specs that read ``changed`` (a description or its SRDF)."""
        for path, analysis in list(self.analyses.items()):
            if changed in analysis.read or changed == path:
                yield path
