"""From an editor's cursor to the spec's key path, for YAML and TOML alike.

The word under the cursor is replaced by a marker and the text parsed by the spec loader
(:mod:`robospec.load.reader`); where the marker lands in the data is the key path, and whether
it landed in a key or a value says which. A half-typed line (``  stiff``, ``tcp = pan``) is
not valid YAML or TOML; it is tried again as a key (``stiff: 0``) and as a quoted value, so the
cursor is placed in the documents people have while they type, not only in finished ones.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Literal

from robospec.load.reader import parse_spec_bytes
from robospec.load.source_map import KeyPath

MARKER = "rsCursorMarkQz"  # letters only: a plain YAML scalar and a bare TOML key
# the characters of a name as specs write them (joint names, globs, dotted keys are split)
_STOP = set(" \t,:[]{}\"'#=")
_CLOSERS = {"[": "]", "{": "}"}


@dataclass(frozen=True)
class Cursor:
    path: KeyPath  # where the word is: a key's path, or a value's
    role: Literal["key", "value"]
    word: str  # the whole word under the cursor
    line: int  # 0-based, as LSP counts
    start: int  # the word's columns on the line (0-based, end exclusive)
    end: int
    data: Any  # the document's data with the marker in it


def word_span(line_text: str, character: int) -> tuple[int, int]:
    start = min(character, len(line_text))
    end = start
    while start > 0 and line_text[start - 1] not in _STOP:
        start -= 1
    while end < len(line_text) and line_text[end] not in _STOP:
        end += 1
    return start, end


def locate(text: str, fmt: str, line: int, character: int) -> Cursor | None:
    """The cursor at 0-based ``line``:``character`` in ``text`` (``fmt``: yaml or toml)."""
    lines = text.split("\n")
    if not 0 <= line < len(lines):
        return None
    line_text = lines[line]
    start, end = word_span(line_text, character)
    word = line_text[start:end]
    before, after = line_text[:start], line_text[end:]
    for candidate in _candidates(before, after, fmt):
        lines[line] = candidate
        loaded, _ = parse_spec_bytes("\n".join(lines).encode(), "cursor", fmt)
        if loaded is None:
            continue
        found = _find(loaded.data, ())
        if found is not None:
            path, role = found
            return Cursor(path, role, word, line, start, end, loaded.data)
    return None


def _candidates(before: str, after: str, fmt: str) -> list[str]:
    lone = not before.strip() and not after.strip()
    tried = [before + MARKER + after]
    if fmt == "yaml":
        if lone:
            tried.append(f"{before}{MARKER}: 0")
        # an unclosed flow collection on this line ("joints: [a, b"): close it after the cursor
        missing = _unclosed(before)
        if missing:
            tried.append(before + MARKER + missing)
    else:
        tried.append(f'{before}"{MARKER}"{after}')
        if lone:
            tried.append(f"{before}{MARKER} = 0")
        missing = _unclosed(before)
        if missing:
            tried.append(f'{before}"{MARKER}"{missing}')
    return tried


def _unclosed(text: str) -> str:
    stack: list[str] = []
    for char in text:
        if char in _CLOSERS:
            stack.append(_CLOSERS[char])
        elif stack and char == stack[-1]:
            stack.pop()
    return "".join(reversed(stack))


def _find(node: Any, path: KeyPath) -> tuple[KeyPath, Literal["key", "value"]] | None:
    if isinstance(node, dict):
        for key, value in node.items():
            if MARKER in str(key):
                return (*path, key), "key"
            found = _find(value, (*path, key))
            if found is not None:
                return found
    elif isinstance(node, list):
        for index, value in enumerate(node):
            found = _find(value, (*path, index))
            if found is not None:
                return found
    elif isinstance(node, str) and MARKER in node:
        return path, "value"
    return None


def value_at(data: Any, path: KeyPath, missing: Any = None) -> Any:
    """The value at ``path`` in ``data``; ``missing`` when there is none."""
    for key in path:
        if isinstance(data, dict) and key in data:
            data = data[key]
        elif isinstance(data, list) and isinstance(key, int) and 0 <= key < len(data):
            data = data[key]
        else:
            return missing
    return data


CODE = re.compile(r"RS\d{3}")
