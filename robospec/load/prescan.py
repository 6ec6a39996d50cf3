"""A cheap look at a spec's text before the real parser sees it: nesting depth and value count.

ruamel.yaml's scanner is quadratic in flow nesting (10,000 ``[`` take it ~50 s) and its
composer recurses once per level; tomllib recurses too. Both are also slow per value (a
600 KB list of 300,000 numbers takes ruamel ~15 s). So before parsing we bound both with
a linear scan that only knows brackets, quotes, comments, indentation and separators. It
over-counts rather than under-counts (a bracket inside a plain scalar counts as nesting),
so its limits sit well above what the parsed data may have (``reader.MAX_DEPTH``) and far
above any real spec, whose data the reader then checks exactly.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

# Well above the reader's exact limits, below where the parsers recurse or crawl.
MAX_SCAN_DEPTH = 256
MAX_SCAN_VALUES = 50_000

# What the scan stops at: brackets, separators, quotes, comments and line breaks.
_TOKEN = re.compile(r"""[\[\]{},#"'\n]""")
# A quoted string on one line (YAML and TOML escapes differ; either way it ends at its quote).
_DOUBLE_QUOTED = re.compile(r'"(?:[^"\\\n]|\\.)*"')
_SINGLE_QUOTED = re.compile(r"'(?:[^'\n]|'')*'")
_BLOCK_ITEM = re.compile(r"[ \t]*(?:-[ \t]+)*")


@dataclass(frozen=True)
class ScanLimit:
    """Where the scan found the text too deep or too long: a message and a 1-based position."""

    message: str
    line: int
    column: int


def prescan(text: str, indentation_nests: bool) -> ScanLimit | None:
    """None when the text is within the limits; else where it first went past them.

    ``indentation_nests``: YAML, where a deeper indentation (or ``- `` item) opens a level.
    """
    depth = 0  # open flow brackets
    values = 0
    indents: list[int] = []  # YAML block levels open at the current line
    line = 1
    line_start = 0
    position = 0
    if indentation_nests:
        found = _block_level(text, 0, indents)
        if found is not None:
            return ScanLimit(found, 1, 1)
    while True:
        match = _TOKEN.search(text, position)
        if match is None:
            return None
        char = match.group()
        position = match.end()
        if char == "\n":
            line += 1
            line_start = position
            values += 1
            if indentation_nests and depth == 0:
                found = _block_level(text, position, indents)
                if found is not None:
                    return ScanLimit(found, line, 1)
        elif char == "#":
            if match.start() == line_start or text[match.start() - 1] in " \t":
                end = text.find("\n", position)
                position = len(text) if end < 0 else end
        elif char in "\"'":
            quoted = (_DOUBLE_QUOTED if char == '"' else _SINGLE_QUOTED).match(text, match.start())
            if quoted is not None:
                position = quoted.end()
        elif char in "[{":
            depth += 1
            if depth + len(indents) > MAX_SCAN_DEPTH:
                return ScanLimit(
                    f"spec is nested deeper than {MAX_SCAN_DEPTH} levels",
                    line,
                    match.start() - line_start + 1,
                )
        elif char in "]}":
            depth = max(depth - 1, 0)
        else:  # ","
            values += 1
        if values > MAX_SCAN_VALUES:
            return ScanLimit(
                f"spec has more than {MAX_SCAN_VALUES} values", line, match.start() - line_start + 1
            )


def _block_level(text: str, start: int, indents: list[int]) -> str | None:
    """Track YAML block levels by indentation at the line from ``start``; each ``- `` item
    marker opens a level of its own (``- - - x`` is three sequences deep)."""
    lead = _BLOCK_ITEM.match(text, start)
    assert lead is not None  # the pattern matches the empty string
    rest = text[lead.end() : lead.end() + 1]
    if rest in ("", "\n", "#"):
        return None  # blank or comment lines open nothing
    columns = [dash.start() for dash in re.finditer("-", text[start : lead.end()])]
    columns.append(lead.end() - start)
    while indents and indents[-1] >= columns[0]:
        indents.pop()
    indents.extend(columns)
    if len(indents) > MAX_SCAN_DEPTH:
        return f"spec is nested deeper than {MAX_SCAN_DEPTH} levels"
    return None
