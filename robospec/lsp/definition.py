"""Go to definition: a joint or link name to its element in the URDF/MJCF; ``extends``, a
controller in a control mode, a group, a material or a named link to where the spec defines it.

With ``parts:``, into the part: a link or joint of a part to its element in the part's own
description, a controller (or named link, ...) that came along from a part's spec to where that
spec defines it, and a part's ``spec:`` to the part's spec file."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from robospec.diagnostics import Location
from robospec.lsp.documents import Analysis
from robospec.lsp.positions import Cursor
from robospec.lsp.robot import DEFINED_IN
from robospec.lsp.schema_paths import allowed_at


@dataclass(frozen=True)
class Target:
    file: Path
    line: int  # 1-based
    column: int  # 1-based


def definition(analysis: Analysis, cursor: Cursor) -> Target | None:
    name = cursor.word
    data = analysis.data if analysis.data is not None else cursor.data
    if cursor.role == "key":
        kinds = allowed_at(cursor.path[:-1], cursor.data).key_kinds
    else:
        kinds = allowed_at(cursor.path, cursor.data).value_kinds
    if cursor.path[-1:] == ("extends",) and cursor.path[:1] == ("controllers",):
        kinds = {"controller"}
    if cursor.path[:1] == ("parts",) and cursor.path[-1:] == ("spec",):
        return _part_spec(analysis, name)
    # a name the spec defines itself (a group before a joint: a group may not share a joint's name)
    for kind in sorted(kinds):
        section = DEFINED_IN.get(kind)
        if section and isinstance(data, dict) and isinstance(data.get(section), dict):
            if name in data[section] and (section, name) != cursor.path:
                return _in_spec(analysis, (section, name))
        # ... or one that came along from a part's spec: where the part's spec defines it
        where = analysis.compiled.part_location((section, name)) if section else None
        if where is not None:
            return _at(where)
    description = analysis.description
    if description is None:
        return None
    element = description.joint(name) or description.link(name)
    if element is None or analysis.description_file is None:
        return None
    if analysis.compiled.composed is not None:  # a part's element: in the part's file
        found = analysis.element_at(element.line)
        return Target(found[0], found[1], 1) if found is not None else None
    if analysis.expanded:
        return _in_xacro(analysis.description_file, name)
    return Target(analysis.description_file, element.line, 1)


def _at(location: Location) -> Target | None:
    path = Path(location.file)
    return Target(path, location.line, location.column) if path.is_absolute() else None


def _part_spec(analysis: Analysis, text: str) -> Target | None:
    """A part's ``spec:`` value: the part's spec file, from its first line."""
    path = Path(os.path.normpath(analysis.path.parent / text))
    return Target(path, 1, 1) if path.is_file() else None


def _in_spec(analysis: Analysis, path: tuple[str, str]) -> Target | None:
    loaded = analysis.compiled.loaded
    if loaded is None:
        return None
    where = loaded.source.key(path)
    return Target(analysis.path, where.line, where.column)


def _in_xacro(file: Path, name: str) -> Target | None:
    """The expansion's lines are not the file's: look for the element's name in the xacro
    (a name built from arguments, ``${prefix}joint1``, is not found)."""
    try:
        text = file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    found = re.search(rf"name\s*=\s*[\"']{re.escape(name)}[\"']", text)
    if found is None:
        return Target(file, 1, 1)
    # at the element's start tag (`<joint name=...`), where the name's attribute is
    tag = text.rfind("<", 0, found.start())
    line_start = text.rfind("\n", 0, found.start()) + 1
    column = tag - line_start + 1 if tag >= line_start else 1
    return Target(file, text.count("\n", 0, found.start()) + 1, column)
