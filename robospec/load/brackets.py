"""Brackets, braces and quotes a person leaves open, closes with the wrong one or closes twice
(RS015), said at the one that is never closed, with where to close it.

The parsers say it in their own terms, at the place where they gave up: ruamel.yaml "while
parsing a flow sequence expected ',' or ']', but got '<scalar>'" at the line after the real
mistake (the next key, which it reads as one more item), tomllib "Unclosed array" there too,
with no word of where the array began. ruamel.yaml's context mark is where the collection (or
the quoted text) began; for TOML the text is scanned here, strings and comments skipped, to
find the brackets still open where tomllib stopped and whether they are closed further on.

A TOML array whose values lack a ',' between them, which tomllib also calls "Unclosed array",
and an inline table written over several lines (TOML keeps one on a line) are told as what
they are (RS002, with the fix).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from robospec.diagnostics import line_column as position_of
from robospec.diagnostics.codes import SPEC_SYNTAX, UNBALANCED_BRACKET
from robospec.load.explained import Explained, content, last_word, offset_of

_CLOSER = {"[": "]", "{": "}"}
_OPENER = {"]": "[", "}": "{"}
_YAML_KIND = {"[": "list", "{": "mapping"}
_TOML_KIND = {"[": "array", "{": "inline table"}
Position = tuple[int, int]  # 1-based line, column


# -- YAML ------------------------------------------------------------------------------------


def explain_yaml(
    context: str, problem: str, text: str, opened: Position | None, at: Position
) -> Explained | None:
    """The bracket or quote behind ruamel.yaml's error: ``context`` and ``problem`` are its
    words, ``opened`` its context mark and ``at`` its problem mark."""
    lines = text.split("\n")
    if opened is not None and context.startswith("while parsing a flow "):
        return _yaml_flow(text, problem, opened, at)
    if opened is not None and context == "while scanning a quoted scalar":
        quote = repr(_char(lines, opened))
        return Explained(
            UNBALANCED_BRACKET,
            *opened,
            f"the text opened with {quote} is never closed: YAML reads the rest of the file "
            "as part of it",
            f"close it with {quote} after {last_word(lines[opened[0] - 1])} on line {opened[0]}",
        )
    stray = re.search(r"found '([\]}])'$", problem)
    if stray:
        closer = stray.group(1)
        return Explained(
            UNBALANCED_BRACKET,
            *at,
            f"this '{closer}' closes no {_YAML_KIND[_OPENER[closer]]}: every "
            f"'{_OPENER[closer]}' before it is closed",
            f"delete this '{closer}'",
        )
    if problem.endswith("but found '<scalar>'"):
        return _quoted_runs_on(text, at)
    return None


def _yaml_flow(text: str, problem: str, opened: Position, at: Position) -> Explained | None:
    bracket = _char(text.split("\n"), opened)
    if bracket not in _CLOSER:
        return None
    kind, closer = _YAML_KIND[bracket], _CLOSER[bracket]
    found = re.search(r"but got '(.)'$", problem)
    wrong = found.group(1) if found and found.group(1) in _OPENER else None
    if wrong is not None and wrong != closer:
        return _wrong_closer(kind, closer, wrong, at, _enclosing_yaml(text, opened, wrong), opened)
    return Explained(
        UNBALANCED_BRACKET,
        *opened,
        f"the {kind} opened with '{bracket}' is never closed: YAML reads what follows, "
        f"{_up_to(text, offset_of(text, *at))}, as more of the {kind}",
        _close_after(closer, text, opened, offset_of(text, *at)),
    )


def _events(text: str) -> list[Any]:
    """ruamel.yaml's parse events of ``text`` up to its error."""
    from ruamel.yaml import YAML

    events: list[Any] = []
    try:
        events.extend(YAML(typ="rt").parse(text))
    except Exception:  # the error that brought us here: the events before it are the ones wanted
        pass
    return events


def _start(event: Any) -> Position:
    return event.start_mark.line + 1, event.start_mark.column + 1


def _enclosing_yaml(text: str, opened: Position, closer: str) -> Position | None:
    """Where the flow collection around the one ``opened`` begins, if ``closer`` closes it."""
    from ruamel.yaml.events import CollectionEndEvent, CollectionStartEvent

    open_flows: list[Position | None] = []  # None: a block collection
    for event in _events(text):
        if isinstance(event, CollectionStartEvent):
            open_flows.append(_start(event) if event.flow_style else None)
        elif isinstance(event, CollectionEndEvent) and open_flows:
            open_flows.pop()
    if opened not in open_flows:
        return None
    index = open_flows.index(opened)
    outer = open_flows[index - 1] if index > 0 else None
    if outer is not None and _char(text.split("\n"), outer) == _OPENER[closer]:
        return outer
    return None


def _quoted_runs_on(text: str, at: Position) -> Explained | None:
    """A quoted text left open on its line and closed by the next quote on a later line, just
    before the parser's error: YAML read the lines between as part of the text."""
    from ruamel.yaml.events import ScalarEvent

    scalars = [e for e in _events(text) if isinstance(e, ScalarEvent)]
    if not scalars or scalars[-1].style not in ('"', "'"):
        return None
    last = scalars[-1]
    opened, closed = _start(last), (last.end_mark.line + 1, last.end_mark.column)
    if closed[0] == opened[0] or closed[0] != at[0]:
        return None
    quote = repr(last.style)
    lines = text.split("\n")
    return Explained(
        UNBALANCED_BRACKET,
        *opened,
        f"the text opened with {quote} is not closed on its line: YAML reads on to the "
        f"{quote} on line {closed[0]}, column {closed[1]}, and takes the lines between as part "
        "of it",
        f"close it with {quote} after {last_word(lines[opened[0] - 1])} on line {opened[0]}",
    )


# -- TOML ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Open:
    char: str  # "[" or "{" of a value, "header" for a [table] header, or a string's quote
    offset: int


@dataclass
class _Scan:
    """TOML's brackets and strings, read from the start of ``text``: what is open at a point."""

    text: str
    offset: int = 0
    brackets: tuple[_Open, ...] = ()
    string: _Open | None = None  # a one-line string is left open at its line's end
    # set where the scan met a closer that is not the open bracket's: (closer, its offset)
    mismatch: tuple[str, int] | None = None

    def run(self, until: int) -> None:
        """Read on up to offset ``until``; stop early at a mismatched closer, or at the end of
        a line that a one-line string leaves open."""
        text = self.text
        while self.offset < until and self.mismatch is None:
            i = self.offset
            char = text[i]
            if self.string is not None:
                quote = self.string.char
                if len(quote) == 1 and char == "\n":
                    return
                if char == "\\" and quote.startswith('"'):
                    self.offset = i + 2
                elif text.startswith(quote, i):
                    self.string = None
                    self.offset = i + len(quote)
                else:
                    self.offset = i + 1
                continue
            if char == "#":
                end = text.find("\n", i)
                self.offset = len(text) if end < 0 else end
                continue
            if char in "\"'":
                quote = char * 3 if text.startswith(char * 3, i) else char
                self.string = _Open(quote, i)
                self.offset = i + len(quote)
                continue
            if char == "[":
                header = not self.brackets and not text[text.rfind("\n", 0, i) + 1 : i].strip()
                self.brackets += (_Open("header" if header else "[", i),)
                if header and text.startswith("[[", i):
                    self.offset += 1  # an [[array of tables]] header
            elif char == "{":
                self.brackets += (_Open("{", i),)
            elif char in "]}":
                top = self.brackets[-1] if self.brackets else None
                if top is not None and top.char in (_OPENER[char], "header"):
                    if top.char == "header" and text.startswith("]]", i):
                        self.offset += 1
                    self.brackets = self.brackets[:-1]
                else:
                    self.mismatch = (char, i)
                    return
            elif char == "\n" and self.brackets and self.brackets[-1].char == "header":
                self.brackets = self.brackets[:-1]  # tomllib has refused it already
            self.offset += 1

    def closes(self, bracket: _Open) -> bool:
        """Read on to the end: whether ``bracket``, open now, is closed by its own closer (a
        one-line string left open is taken to end with its line)."""
        depth = self.brackets.index(bracket)
        while self.offset < len(self.text) and self.mismatch is None:
            if self.string is not None and len(self.string.char) == 1:
                if self.text[self.offset] == "\n":
                    self.string = None
            self.run(self.offset + 1)
            if len(self.brackets) <= depth:
                return True
        return False


def explain_toml(message: str, text: str, line: int, column: int) -> Explained | None:
    """The bracket or string behind tomllib's ``message`` at ``line``:``column``."""
    lines = text.split("\n")
    at = min(offset_of(text, line, column), len(text))
    scan = _Scan(text)
    scan.run(at)
    # a one-line string left open: the scan stopped at its line's end (and tomllib there, or
    # at the end of the file), not at a character tomllib refuses inside it
    open_line = scan.offset >= len(text) or text[scan.offset] == "\n"
    if scan.string is not None and len(scan.string.char) == 1 and open_line:
        return _toml_unclosed_string(scan.string, text, lines)
    if scan.mismatch is not None or not scan.brackets:
        return _toml_stray_closer(message, text, at, line, column)
    if scan.brackets[-1].char == "header":
        return _toml_unclosed_header(scan.brackets[-1], text, lines)
    return _toml_unclosed_bracket(scan, text, lines, at, (line, column))


def _toml_unclosed_string(string: _Open, text: str, lines: list[str]) -> Explained:
    where = position_of(text, string.offset)
    quote = repr(string.char)
    return Explained(
        UNBALANCED_BRACKET,
        *where,
        f"the string opened with {quote} is not closed on its line: a TOML string ends "
        f'on the line it starts (one in """ may span lines)',
        f"close it with {quote} after {last_word(lines[where[0] - 1])} on line {where[0]}",
    )


def _toml_stray_closer(
    message: str, text: str, at: int, line: int, column: int
) -> Explained | None:
    """A closer where every bracket before it is closed (or none of tomllib's brackets)."""
    closer = text[at] if at < len(text) else ""
    if closer in _OPENER and "Expected newline" in message:
        kind = _TOML_KIND[_OPENER[closer]]
        return Explained(
            UNBALANCED_BRACKET,
            line,
            column,
            f"this '{closer}' closes no {kind}: every '{_OPENER[closer]}' before it is closed",
            f"delete this '{closer}'",
        )
    return None


def _toml_unclosed_header(header_open: _Open, text: str, lines: list[str]) -> Explained | None:
    opened = position_of(text, header_open.offset)
    header = content(lines[opened[0] - 1])
    if header.count("]") >= header.count("["):
        return None  # closed: tomllib stopped at it for another reason
    return Explained(
        UNBALANCED_BRACKET,
        *opened,
        "the table header opened with '[' is not closed on its line",
        f"write {header}]" if header.count("[") == 1 else f"write {header}]]",
    )


def _toml_unclosed_bracket(
    scan: _Scan, text: str, lines: list[str], at: int, stopped: Position
) -> Explained:
    """The innermost array or inline table open where tomllib stopped: closed by the wrong
    closer, closed further on (a missing ',', or an inline table over several lines: RS002),
    or never closed."""
    innermost = scan.brackets[-1]
    opened = position_of(text, innermost.offset)
    kind, closer = _TOML_KIND[innermost.char], _CLOSER[innermost.char]
    here = text[at] if at < len(text) else ""
    if here in _OPENER and here != closer:
        outer = scan.brackets[-2] if len(scan.brackets) > 1 else None
        enclosing = (
            position_of(text, outer.offset)
            if outer is not None and outer.char == _OPENER[here]
            else None
        )
        return _wrong_closer(kind, closer, here, stopped, enclosing, opened)
    if scan.closes(innermost):
        if innermost.char == "{":
            return Explained(
                SPEC_SYNTAX,
                *opened,
                f"the inline table opened with '{{' runs on past line {opened[0]}: TOML writes "
                "an inline table on one line",
                "write it on one line, or as a [table] of its own with one key per line",
            )
        return Explained(
            SPEC_SYNTAX,
            *stopped,
            f"a ',' is missing before this value of the array opened on line {opened[0]}",
            f"write ',' after {last_word(text[:at])}",
        )
    if innermost.char == "{":
        hint = f"close it with '}}' after {last_word(lines[opened[0] - 1])} on line {opened[0]}"
        return Explained(
            UNBALANCED_BRACKET,
            *opened,
            "the inline table opened with '{' is never closed: TOML writes an inline table "
            "on one line",
            hint,
        )
    return Explained(
        UNBALANCED_BRACKET,
        *opened,
        f"the {kind} opened with '[' is never closed: TOML reads what follows, "
        f"{_up_to(text, at)}, as more of its values",
        _close_after(closer, text, opened, at),
    )


# -- shared ----------------------------------------------------------------------------------


def _char(lines: list[str], position: tuple[int, int]) -> str:
    line, column = position
    text = lines[line - 1] if 1 <= line <= len(lines) else ""
    return text[column - 1] if 1 <= column <= len(text) else ""


def _up_to(text: str, stop: int) -> str:
    """How far the parser read on: to the line where it stopped, or to the end."""
    if not text[stop:].strip():
        return "to the end of the file"
    return f"on to line {text.count(chr(10), 0, stop) + 1}"


def _close_after(closer: str, text: str, opened: Position, stop: int) -> str:
    """Where to put ``closer``: after the last word written before offset ``stop``, where the
    parser stopped. What starts the line there (a key, by its indentation) was meant to follow
    the collection, so that line counts only when the parser stopped at the end of the file;
    at the earliest, the line the collection opens on."""
    lines = text[:stop].split("\n")
    if text[stop:].strip():
        lines[-1] = ""
    for number in range(len(lines), opened[0], -1):
        if content(lines[number - 1]):
            return f"close it with '{closer}' after {last_word(lines[number - 1])} on line {number}"
    first = text.split("\n")[opened[0] - 1]
    return f"close it with '{closer}' after {last_word(first)} on line {opened[0]}"


def _wrong_closer(
    kind: str,
    closer: str,
    wrong: str,
    at: tuple[int, int],
    enclosing: tuple[int, int] | None,
    opened: tuple[int, int],
) -> Explained:
    if enclosing is not None:
        hint = (
            f"close the {kind} with '{closer}' before that '{wrong}' (which closes the "
            f"'{_OPENER[wrong]}' on line {enclosing[0]}, column {enclosing[1]})"
        )
    else:
        hint = f"write '{closer}' for that '{wrong}'"
    return Explained(
        UNBALANCED_BRACKET,
        *opened,
        f"the {kind} opened with '{_OPENER[closer]}' is closed with '{wrong}' on line {at[0]}, "
        f"column {at[1]}",
        hint,
    )
