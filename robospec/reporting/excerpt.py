"""Source lines for excerpts: read the file a diagnostic names (spec, URDF, MJCF) and find how
far the key or value at a column reaches, so the caret can underline all of it.

Diagnostics carry a start position only; the span is recovered from the text, which is exact
for the tokens diagnostics point at (a plain or quoted scalar, a key, a flow collection on one
line) and falls back to a single caret elsewhere."""

from __future__ import annotations

import functools
import re
import stat
from pathlib import Path

# An excerpt is a courtesy: never read something huge (or a FIFO, which would block) to make one.
MAX_SOURCE_BYTES = 8 * 1024 * 1024
# YAML, TOML and XML all end lines at CRLF, CR or LF (str.splitlines also splits at \f, \x1c, ...)
_LINE_BREAK = re.compile(r"\r\n|\r|\n")
# where a plain (unquoted) YAML/TOML token ends; ':' only ends it before a space or the line end
_PLAIN_END = set(",[]{}=")
_CLOSING = {"{": "}", "[": "]"}


def _lines(file: str) -> tuple[str, ...] | None:
    path = Path(file)
    try:
        info = path.stat()
    except (OSError, ValueError):
        return None
    if not stat.S_ISREG(info.st_mode) or info.st_size > MAX_SOURCE_BYTES:
        return None
    # keyed by where the file is now and its state, not by the name a diagnostic gives: in a
    # long-lived process (register in a notebook) the file changes, or the working folder does
    return _read_lines(str(path.resolve()), info.st_mtime_ns, info.st_size)


@functools.lru_cache(maxsize=32)
def _read_lines(path: str, mtime_ns: int, size: int) -> tuple[str, ...] | None:
    try:
        data = Path(path).read_bytes()
    except OSError:
        return None
    return tuple(_LINE_BREAK.split(data.decode("utf-8", errors="replace")))


def source_line(file: str, line: int) -> str | None:
    """Line ``line`` (1-based) of ``file``, or None when the file cannot be read or is shorter."""
    lines = _lines(file)
    if lines is None or not 1 <= line <= len(lines):
        return None
    return lines[line - 1]


def span_width(text: str, column: int) -> int:
    """How many characters the token starting at 1-based ``column`` of ``text`` covers (>= 1)."""
    start = column - 1
    if not 0 <= start < len(text) or text[start].isspace():
        return 1
    first = text[start]
    if first in "\"'":
        end = _quoted_end(text, start)
    elif first in _CLOSING:
        end = _bracket_end(text, start)
    elif first == "<":  # an XML element written on one line
        close = text.find(">", start)
        end = close + 1 if close >= 0 else start + 1
    else:
        end = _plain_end(text, start)
    return max(1, end - start)


def _quoted_end(text: str, start: int) -> int:
    quote = text[start]
    if text.startswith(quote * 3, start):  # a TOML multi-line string: up to the line end
        close = text.find(quote * 3, start + 3)
        return close + 3 if close >= 0 else len(text.rstrip())
    i = start + 1
    while i < len(text):
        ch = text[i]
        if quote == '"' and ch == "\\":
            i += 2
            continue
        if ch == quote:
            if quote == "'" and text.startswith("''", i):  # YAML's escaped single quote
                i += 2
                continue
            return i + 1
        i += 1
    return len(text.rstrip())


def _bracket_end(text: str, start: int) -> int:
    depth = 0
    i = start
    while i < len(text):
        ch = text[i]
        if ch in "\"'":
            i = _quoted_end(text, i)
            continue
        if ch in _CLOSING:
            depth += 1
        elif ch in _CLOSING.values():
            depth -= 1
            if depth == 0:
                return i + 1
        i += 1
    return start + 1  # not closed on this line: point at the opening bracket only


def _plain_end(text: str, start: int) -> int:
    i = start
    while i < len(text):
        ch = text[i]
        if ch.isspace() or ch in _PLAIN_END:
            break
        if ch == ":" and (i + 1 == len(text) or text[i + 1].isspace()):
            break
        i += 1
    return i
