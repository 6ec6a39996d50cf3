"""A syntax error explained: the mistake a person made, where, and the fix (the record
:mod:`.syntax_hints` and :mod:`.brackets` return, which the reader turns into a diagnostic),
and the small text measures both use."""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Explained:
    code: str
    line: int  # 1-based
    column: int  # 1-based
    message: str
    hint: str


def offset_of(text: str, line: int, column: int) -> int:
    """The character offset of 1-based ``line``:``column`` in ``text`` (past its end for a
    position after the last line, as a parser's "end of input" mark)."""
    start = 0
    for _ in range(line - 1):
        found = text.find("\n", start)
        if found < 0:
            return len(text)
        start = found + 1
    return start + column - 1


_COMMENT = re.compile(r"(?:^|\s)#.*$")


def content(line: str) -> str:
    """``line`` without its comment and the spaces around it."""
    return _COMMENT.sub("", line).strip()


def last_word(text: str) -> str:
    """The last word written in ``text`` (its last line with content, comment left out), in
    quotes: what a fix is placed after."""
    for line in reversed(text.split("\n")):
        words = content(line).split()
        if words:
            return f"'{words[-1].lstrip('[{') or words[-1]}'"
    return "the value"
