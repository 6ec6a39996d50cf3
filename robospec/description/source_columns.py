"""Where an XML element of a description file starts: lxml gives its line, and a caret at
column 1 would sit in the indentation before it (``    <inertial>``)."""

from __future__ import annotations

import functools
import os

from lxml import etree

from robospec.diagnostics import Location


def element_at(path: str, element: etree._Element) -> Location:
    """The location of ``element``'s start tag in the file at ``path``."""
    line = element.sourceline
    line = line if isinstance(line, int) and line > 0 else 1
    return Location(path, line, tag_column(path, line, element.tag))


def tag_column(path: str, line: int, tag: object) -> int:
    """The 1-based column of ``<tag`` on ``line`` of the file at ``path``, so that a caret
    points at the element, not at the indentation before it: lxml gives lines only. Where
    the file or the tag cannot be found there (a xacro expansion is not on disk), the line's
    first non-blank character, else 1."""
    text = _source_line(path, line)
    if text is None:
        return 1
    name = tag if isinstance(tag, str) else ""
    found = text.find(f"<{name.rpartition('}')[2]}") if name else -1
    if found < 0:
        found = len(text) - len(text.lstrip())
    return found + 1


def _source_line(path: str, line: int) -> str | None:
    lines = _file_lines(path)
    return lines[line - 1] if lines is not None and 1 <= line <= len(lines) else None


@functools.lru_cache(maxsize=32)
def _lines_of(path: str, mtime_ns: int) -> tuple[str, ...] | None:
    try:
        return tuple(_read(path).decode("utf-8", errors="replace").splitlines())
    except OSError:
        return None


def _file_lines(path: str) -> tuple[str, ...] | None:
    try:
        return _lines_of(path, os.stat(path).st_mtime_ns)
    except (OSError, ValueError):
        return None


def _read(path: str) -> bytes:
    with open(path, "rb") as handle:
        return handle.read()
