"""Source positions for TOML: key paths mapped to 1-based line:column of their key and value.

``tomllib`` gives data without positions, so the same text is parsed a second time with
tree-sitter-toml and its syntax tree is walked to name every key path the way the data names it:
``("links", "panda_*finger", "material")``, ``("controllers", "arm", "joints", 0)``.

Conventions (shared with the YAML source map):

- lines and columns are 1-based and count characters, not bytes;
- an array item's "key" position is the item's own position;
- a table that has no value text of its own (a ``[table]`` header, ``[[array]]`` element, or the
  ``a`` and ``b`` that ``a.b.c = 1`` creates) has, as value position, the position of the key
  segment that continues it (``b`` for ``a``), or of its own header key when nothing continues it.
- an explicit definition (``[a]``, ``a = {...}``) wins over an implicit one (``[a.b]``,
  ``a.b = 1``); otherwise the first occurrence wins.

tree-sitter is imported lazily: the YAML path must not pay for it.
"""

from __future__ import annotations

import functools
import re
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from tree_sitter import Node, Tree

Path = tuple[str | int, ...]
Position = tuple[int, int]

_KEY_TYPES = frozenset({"bare_key", "quoted_key", "dotted_key"})
# Named nodes that carry no data where values are expected.
_NOT_VALUES = frozenset({"comment", "ERROR"})


def toml_positions(text: str) -> dict[Path, tuple[Position, Position]]:
    """Map every key path in ``text`` to ``((key_line, key_col), (value_line, value_col))``.

    Best effort on invalid TOML (parts inside syntax errors are left out); never raises.
    """
    tree = _parse(text)
    walker = _Walker(_Columns(text))
    walker.document(tree.root_node)
    return walker.positions


_TOMLLIB_AT = re.compile(r"\s*\(at line (\d+), column (\d+)\)\s*$")
_TOMLLIB_END = re.compile(r"\s*\(at end of document\)\s*$")


def tomllib_error_location(exc: BaseException, text: str) -> tuple[int, int, str]:
    """``(line, column, message)`` for a ``tomllib.TOMLDecodeError`` raised on ``text``.

    tomllib puts the position in the message ("... (at line 3, column 7)", or "(at end of
    document)"); Python 3.14 also sets ``lineno``/``colno``. Columns count characters.
    """
    message = str(exc)
    lineno, colno = getattr(exc, "lineno", None), getattr(exc, "colno", None)
    plain = getattr(exc, "msg", None)
    if isinstance(lineno, int) and isinstance(colno, int) and isinstance(plain, str):
        return lineno, colno, plain
    match = _TOMLLIB_AT.search(message)
    if match:
        return int(match.group(1)), int(match.group(2)), message[: match.start()]
    match = _TOMLLIB_END.search(message)
    if match:
        lines = text.split("\n")
        return len(lines), len(lines[-1]) + 1, message[: match.start()]
    return 1, 1, message


# -- parsing -------------------------------------------------------------------------------


@functools.lru_cache(maxsize=1)
def _language() -> Any:
    import tree_sitter
    import tree_sitter_toml

    return tree_sitter.Language(tree_sitter_toml.language())


def _parse(text: str) -> Tree:
    import tree_sitter

    # A parser per call: tree-sitter parsers are not safe to share between threads.
    parser = tree_sitter.Parser(_language())
    return parser.parse(text.encode("utf-8", "surrogatepass"))


def _text(node: Node) -> str:
    return (node.text or b"").decode("utf-8", "replace")


class _Columns:
    """Turns tree-sitter points (0-based row, byte column) into 1-based line and character."""

    def __init__(self, text: str) -> None:
        self._lines = text.encode("utf-8", "surrogatepass").split(b"\n")

    def point(self, point: Any) -> Position:
        row, byte_col = point[0], point[1]
        if row >= len(self._lines):
            return row + 1, byte_col + 1
        line = self._lines[row]
        if line.isascii():
            return row + 1, byte_col + 1
        return row + 1, len(line[:byte_col].decode("utf-8", "surrogatepass")) + 1


# -- keys ----------------------------------------------------------------------------------

_BASIC_ESCAPE = re.compile(r"\\(?:u([0-9A-Fa-f]{4})|U([0-9A-Fa-f]{8})|x([0-9A-Fa-f]{2})|(.))")
_SIMPLE_ESCAPES = {"b": "\b", "t": "\t", "n": "\n", "f": "\f", "r": "\r", "e": "\x1b"}


def _unescape(match: re.Match[str]) -> str:
    hex_code = match.group(1) or match.group(2) or match.group(3)
    if hex_code:
        try:
            return chr(int(hex_code, 16))
        except ValueError:  # beyond U+10FFFF: invalid TOML, which tomllib reports
            return match.group(0)
    char = match.group(4)
    return _SIMPLE_ESCAPES.get(char, char)  # \" and \\ stand for themselves


def _key_name(node: Node) -> str:
    """The key as tomllib names it: quotes removed, escapes of basic strings applied."""
    raw = _text(node)
    if node.type != "quoted_key" or len(raw) < 2:
        return raw
    inner = raw[1:-1]
    if raw[0] == "'":  # literal string: no escapes
        return inner
    return _BASIC_ESCAPE.sub(_unescape, inner)


def _segments(key: Node) -> list[Node]:
    """The bare/quoted key nodes of a (possibly dotted) key, left to right."""
    out: list[Node] = []
    stack = [key]
    while stack:
        node = stack.pop()
        if node.type == "dotted_key":
            stack.extend(reversed([c for c in node.named_children if c.type in _KEY_TYPES]))
        elif node.type in ("bare_key", "quoted_key"):
            out.append(node)
    return out


def _is_placeholder(node: Node) -> bool:
    """tree-sitter's stand-in for text a syntax error left out: a MISSING node, or a node of
    zero width (``a = {b = }`` gets an empty integer for b's value)."""
    return node.is_missing or node.start_byte == node.end_byte


# -- the walk ------------------------------------------------------------------------------


class _Walker:
    def __init__(self, columns: _Columns) -> None:
        self.columns = columns
        self.positions: dict[Path, tuple[Position, Position]] = {}
        self._explicit: set[Path] = set()
        # How many [[x]] elements each array-of-tables path has so far: a later header [x.y]
        # or [[x.y]] continues the last of them.
        self._aot_counts: dict[Path, int] = {}

    def _put(self, path: Path, key: Node, value: Node, *, explicit: bool) -> None:
        if path in self._explicit:
            return  # a second explicit definition is a TOML error; keep the first
        entry = (self.columns.point(key.start_point), self.columns.point(value.start_point))
        if explicit:
            self.positions[path] = entry
            self._explicit.add(path)
        else:
            self.positions.setdefault(path, entry)

    def document(self, root: Node) -> None:
        for child in root.named_children:
            if child.type == "pair":
                self._pair(child, ())
            elif child.type in ("table", "table_array_element"):
                prefix = self._header(child)
                if prefix is None:
                    continue
                for pair in child.named_children:
                    if pair.type == "pair":
                        self._pair(pair, prefix)

    def _header(self, table: Node) -> Path | None:
        """Register a [table] or [[array]] header; return the path its pairs live under."""
        key = next((c for c in table.named_children if c.type in _KEY_TYPES), None)
        if key is None:
            return None
        segments = _segments(key)
        if not segments:
            return None
        path: Path = ()
        for i, seg in enumerate(segments):
            if _is_placeholder(seg):
                return None  # a header cut short by a syntax error (``[a.]``)
            path = (*path, _key_name(seg))
            last = i == len(segments) - 1
            follow = segments[i + 1] if not last else seg
            if not last:
                self._put(path, seg, follow, explicit=False)
                if path in self._aot_counts:  # [[x]] ... [x.y]: y belongs to the last x
                    path = (*path, self._aot_counts[path] - 1)
            elif table.type == "table":
                self._put(path, seg, seg, explicit=True)
            else:
                # [[x]]: x is the array (first header), (x, i) the i-th element (its header)
                index = self._aot_counts.get(path, 0)
                self._aot_counts[path] = index + 1
                self._put(path, seg, seg, explicit=False)
                path = (*path, index)
                self._put(path, seg, seg, explicit=True)
        return path

    def _pair(self, pair: Node, prefix: Path) -> None:
        # Values are walked with an explicit stack: deeply nested arrays must not hit Python's
        # recursion limit.
        pending: list[tuple[Node, Path]] = [(pair, prefix)]
        while pending:
            node, base = pending.pop()
            if node.type == "pair":
                self._one_pair(node, base, pending)
            elif node.type == "inline_table":
                for child in reversed(node.named_children):
                    if child.type == "pair":
                        pending.append((child, base))
            elif node.type == "array":
                items = [c for c in node.named_children if c.type not in _NOT_VALUES]
                for index, item in enumerate(items):
                    self._put((*base, index), item, item, explicit=True)
                for index, item in reversed(list(enumerate(items))):
                    if item.type in ("array", "inline_table"):
                        pending.append((item, (*base, index)))

    def _one_pair(self, pair: Node, prefix: Path, pending: list[tuple[Node, Path]]) -> None:
        children = [c for c in pair.named_children if c.type != "comment"]
        if len(children) < 2 or children[0].type not in _KEY_TYPES:
            return  # a pair damaged by a syntax error
        key, value = children[0], children[-1]
        if _is_placeholder(value) or value.type == "ERROR":
            return
        segments = _segments(key)
        path = prefix
        for i, seg in enumerate(segments):
            if _is_placeholder(seg):
                return  # a key cut short by a syntax error (``a.b. = 1``) holds no value
            path = (*path, _key_name(seg))
            if i < len(segments) - 1:
                self._put(path, seg, segments[i + 1], explicit=False)
            else:
                self._put(path, seg, value, explicit=True)
        if value.type in ("array", "inline_table"):
            pending.append((value, path))
