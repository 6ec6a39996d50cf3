"""Syntax errors in words a person reads: what the parser tripped on, said as the mistake a
person makes (a key indented to no level, a tab, a TOML text without quotes), with the fix.

The parsers (ruamel.yaml, tomllib) stop at the first error and name it in their own terms
("mapping values are not allowed here", "expected <block end>, but found '<block mapping
start>'", "Invalid value"). Each function here looks at the text around the parser's mark and
returns a :class:`Explained` when it recognises the mistake, else None (the parser's words are
kept, under RS002). Brackets, braces and quotes left open or closed wrongly are
:mod:`.brackets`' (RS015); a key given twice names the line of the first (RS003).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from robospec.diagnostics.codes import (
    COLON_IN_PLAIN_VALUE,
    DUPLICATE_KEY,
    SPEC_SYNTAX,
    STRAY_INDENTATION,
    TAB_INDENTATION,
    UNQUOTED_TOML_TEXT,
)
from robospec.load import brackets
from robospec.load.explained import Explained

_KEY = re.compile(
    r"^(?P<indent> *)(?:- +)?(?P<key>[^\s:#'\"{\[][^:#]*?|'[^']*'|\"[^\"]*\")\s*:(?:\s|$)"
)
_TOML_WORDS = {"true", "false", "inf", "nan"}
_BARE = re.compile(r"[A-Za-z_][\w.\-]*")
# a TOML string, basic or literal: bare words inside one are not values
_QUOTED = re.compile(r"(\"(?:[^\"\\]|\\.)*\"|'[^']*')")
# a line that starts with a key (in a sequence item, too): `  - name: ...`


@dataclass(frozen=True)
class _Line:
    number: int  # 1-based
    indent: int
    key: str | None
    opens_block: bool  # `key:` with nothing after it: the lines below may nest under it


def _significant(lines: list[str], before: int) -> list[_Line]:
    """The lines above line ``before`` (1-based) that hold YAML, nearest first."""
    found = []
    for number in range(before - 1, 0, -1):
        text = lines[number - 1]
        stripped = text.strip()
        if not stripped or stripped.startswith("#") or stripped in ("---", "..."):
            continue
        match = _KEY.match(text)
        key = match["key"].strip("'\"") if match else None
        after = text[match.end() :].split(" #", 1)[0].strip() if match else stripped
        found.append(
            _Line(number, len(text) - len(text.lstrip(" ")), key, bool(match) and not after)
        )
    return found


def _levels(above: list[_Line]) -> list[tuple[int, _Line, _Line | None]]:
    """The indentation levels a new key below ``above[0]`` may take: (indent, a key at that
    level, the key that level belongs to, or None at the top), innermost first."""
    levels: list[tuple[int, _Line, _Line | None]] = []
    current: _Line | None = None
    for line in above:
        if current is None or line.indent < current.indent:
            if current is not None:
                levels.append((current.indent, current, line))
            current = line
            if line.indent == 0:
                break
    if current is not None and current.indent == 0:
        levels.append((0, current, None))
    return levels


def _where(level: tuple[int, _Line, _Line | None]) -> str:
    indent, sibling, parent = level
    owner = "a top-level key" if parent is None else f"a key of '{parent.key}'"
    return f"column {indent + 1} ({owner}, as '{sibling.key}' on line {sibling.number})"


def explain_yaml(
    problem: str,
    text: str,
    line: int,
    column: int,
    context: str = "",
    opened: tuple[int, int] | None = None,
) -> Explained | None:
    """The mistake behind ruamel.yaml's ``problem`` at ``line``:``column`` (1-based), said
    ``context`` about what began at ``opened`` (its context mark: a bracket, a quote)."""
    # ruamel.yaml counts a lone carriage return as a line break, as YAML does: so do the lines
    # read here, or its marks point past them
    text = re.sub(r"\r\n?", "\n", text)
    unbalanced = brackets.explain_yaml(context, problem, text, opened, (line, column))
    if unbalanced is not None:
        return unbalanced
    lines = text.split("\n")
    if not 1 <= line <= len(lines):
        return None
    here = lines[line - 1]
    alias = re.match(r"found undefined alias '(.*)'$", problem)
    if alias and here[column - 1 : column] == "*":
        return _glob_read_as_alias(alias.group(1), here, line, column)
    if "'\\t'" in problem:
        return _tab(lines, line)
    match = _KEY.match(here)
    indent = len(here) - len(here.lstrip(" "))
    above = _significant(lines, line)
    if "mapping values are not allowed" in problem:
        if match and column - 1 > match.end("key") and above:
            # `key: a: b` read as one value: a plain value cannot hold ": "
            value = here[match.end() :].strip()
            return Explained(
                COLON_IN_PLAIN_VALUE,
                line,
                column,
                f"the value of '{match['key']}' holds ': ', which YAML reads as a second "
                "key on the same line",
                f"write a nested mapping as {match['key']}: {{{value}}}, or quote the value",
            )
        return _more_indented(match, indent, above, line)
    if "expected <block end>" in problem and match and above:
        deeper = _more_indented(match, indent, above, line)
        if deeper is not None:
            return deeper
        levels = _levels(above)
        if indent in {level[0] for level in levels}:
            return None
        return Explained(
            STRAY_INDENTATION,
            line,
            indent + 1,
            f"'{match['key']}' is indented to column {indent + 1}, which lines up with no key "
            "above it",
            "indent it to " + " or ".join(_where(level) for level in levels),
        )
    return None


def _glob_read_as_alias(name: str, here: str, line: int, column: int) -> Explained:
    """``arm: *joint[1-7]``: a glob that starts with ``*``, which YAML reads as an alias."""
    word = re.match(r"\*[^\s,]*", here[column - 1 :])
    pattern = word.group() if word else f"*{name}"
    while pattern[-1:] in ("]", "}") and pattern.count(pattern[-1]) > pattern.count(
        "[" if pattern[-1] == "]" else "{"
    ):
        pattern = pattern[:-1]  # the end of the flow collection it stands in
    return Explained(
        SPEC_SYNTAX,
        line,
        column,
        f"'{pattern}' starts with '*', which YAML reads as an alias: a reference to an "
        f"anchor '&{name}', which the spec does not define",
        f"a name pattern that starts with '*' needs quotes: \"{pattern}\"",
    )


def _more_indented(
    match: re.Match[str] | None, indent: int, above: list[_Line], line: int
) -> Explained | None:
    """A key indented below a key that already has a value."""
    if not (match and above and indent > above[0].indent and not above[0].opens_block):
        return None
    previous = above[0]
    return Explained(
        STRAY_INDENTATION,
        line,
        indent + 1,
        f"'{match['key']}' is indented more than '{previous.key}' on line {previous.number}, "
        "which already has a value: YAML reads it as part of that value",
        "indent it to " + " or ".join(_where(level) for level in _levels(above)),
    )


_TOML_KEY = re.compile(r"^\s*(?P<key>[^=#\[]+?)\s*=")
_TOML_HEADER = re.compile(r"^\s*\[")


def duplicate_key(text: str, key: str | None, line: int, column: int, language: str) -> Explained:
    """A key given twice in one mapping (YAML) or table (TOML): at the second, naming the line
    of the first, which the parser does not say. ``key``: YAML's (the parser names it); TOML's
    is read from the line tomllib names, whose column lies at the end of the value."""
    lines = text.split("\n")
    here = lines[line - 1] if 1 <= line <= len(lines) else ""
    if language == "toml" and _TOML_HEADER.match(here):
        header = here.split("#", 1)[0].strip()
        first = next(
            (n for n in range(1, line) if lines[n - 1].split("#", 1)[0].strip() == header), None
        )
        return Explained(
            DUPLICATE_KEY,
            line,
            len(here) - len(here.lstrip()) + 1,
            f"the table {header} is declared twice"
            + (f" (first on line {first})" if first is not None else ""),
            "keep one header: put the table's keys under the first",
        )
    if language == "toml":
        found = _TOML_KEY.match(here)
        key = found["key"] if found else None
        column = found.start("key") + 1 if found else column
    first = _first_occurrence(lines, line, key, language) if key else None
    before = f" (first on line {first})" if first is not None else ""
    shown = f"'{key}'" if key else "a key"
    return Explained(
        DUPLICATE_KEY,
        line,
        column,
        f"{shown} is given twice in the same {'mapping' if language == 'yaml' else 'table'}"
        f"{before}",
        "keep one of them: a key names one value (merge the two if both hold part of it)",
    )


def _first_occurrence(lines: list[str], line: int, key: str, language: str) -> int | None:
    """The line above ``line`` where ``key`` is given at the same level: the same indentation
    in YAML, the same [table] in TOML."""
    if not 1 <= line <= len(lines):
        return None
    indent = len(lines[line - 1]) - len(lines[line - 1].lstrip(" "))
    for number in range(line - 1, 0, -1):
        text = lines[number - 1]
        if language == "toml":
            if _TOML_HEADER.match(text):
                return None
            found = _TOML_KEY.match(text)
            if found and found["key"] == key:
                return number
            continue
        match = _KEY.match(text)
        if match is None:
            continue
        level = len(match["indent"])
        if level < indent:
            return None
        if level == indent and match["key"].strip("'\"") == key:
            return number
    return None


def _tab(lines: list[str], line: int) -> Explained:
    text = lines[line - 1]
    column = text.index("\t") + 1 if "\t" in text else 1
    tabbed = [n for n, t in enumerate(lines, 1) if "\t" in t[: len(t) - len(t.lstrip(" \t"))]]
    others = [n for n in tabbed if n != line]
    also = (
        f" (and line{'s' if len(others) > 1 else ''} {', '.join(map(str, others))})"
        if others
        else ""
    )
    return Explained(
        TAB_INDENTATION,
        line,
        column,
        f"a tab indents this line{also}: YAML indents with spaces only",
        "replace each tab with spaces (editors can insert spaces for the Tab key)",
    )


def explain_toml(message: str, text: str, line: int, column: int) -> Explained | None:
    """The mistake behind tomllib's ``message`` at ``line``:``column`` (1-based)."""
    for explain in (_unquoted_text, _colon_for_equals, brackets.explain_toml):
        explained = explain(message, text, line, column)
        if explained is not None:
            return explained
    return None


def _colon_for_equals(message: str, text: str, line: int, column: int) -> Explained | None:
    """``uid: "my_arm"`` in TOML, as YAML writes it."""
    lines = text.split("\n")
    if not message.startswith("Expected '=' after a key") or not 1 <= line <= len(lines):
        return None
    here = lines[line - 1]
    if here[column - 1 : column] != ":":
        return None
    key, value = here[: column - 1].strip(), here[column:].strip()
    return Explained(
        SPEC_SYNTAX,
        line,
        column,
        f"'{key}' is followed by ':', as in YAML: TOML writes a key and its value with '='",
        f"write {key} = {value}",
    )


def _unquoted_text(message: str, text: str, line: int, column: int) -> Explained | None:
    lines = text.split("\n")
    if "Invalid value" not in message or not 1 <= line <= len(lines):
        return None
    here = lines[line - 1]
    word = _BARE.match(here, column - 1)
    if word is None or word.group() in _TOML_WORDS:
        return None
    bare = word.group()
    key, equals, value = here.partition("=")
    if not equals or len(key) >= column:
        return None
    # every bare word of the value quoted, outside the strings it already has
    parts = _QUOTED.split(value)
    fixed = "".join(
        part if index % 2 else _BARE.sub(_quote, part) for index, part in enumerate(parts)
    )
    return Explained(
        UNQUOTED_TOML_TEXT,
        line,
        column,
        f"the value of '{key.strip()}' is text without quotes: TOML needs quotes around '{bare}'",
        f"write {key.strip()} = {fixed.strip()}",
    )


def _quote(word: re.Match[str]) -> str:
    return word.group() if word.group() in _TOML_WORDS else f'"{word.group()}"'
