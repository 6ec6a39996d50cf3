"""Read a spec file (YAML or TOML) into plain data and a source map. Never raises on bad input."""

from __future__ import annotations

import os
import re
import stat
import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.diagnostics import Diagnostic, Location, error, line_column
from robospec.diagnostics.codes import (
    SPEC_FILE_TYPE,
    SPEC_NOT_A_MAPPING,
    SPEC_SYNTAX,
    SPEC_TOO_LARGE,
    SPEC_UNREADABLE,
)
from robospec.load.prescan import prescan
from robospec.load.source_map import KeyPath, LoadedSpec, SourceMap, WrittenNumber

if TYPE_CHECKING:
    # imported where a syntax error is explained: a spec that parses needs none of it
    from robospec.load.explained import Explained

SPEC_SUFFIXES = {".yaml": "yaml", ".yml": "yaml", ".toml": "toml"}
MAX_BYTES = 2 * 1024 * 1024
MAX_NODES = 200_000  # an alias bomb expands far past this while the file stays tiny
MAX_DEPTH = 64


class _TooBig(Exception):
    def __init__(self, message: str, path: KeyPath, code: str = SPEC_TOO_LARGE) -> None:
        super().__init__(message)
        self.path = path
        self.code = code


def read_spec(path: Path, display: str | None = None) -> tuple[LoadedSpec | None, list[Diagnostic]]:
    display = display or str(path)
    fmt = SPEC_SUFFIXES.get(path.suffix.lower())
    if fmt is None:
        return None, [
            error(
                Location(display),
                SPEC_FILE_TYPE,
                f"unsupported spec file type '{path.suffix}'",
                "use .yaml, .yml or .toml",
            )
        ]
    raw, problem = read_spec_file_bytes(path, display)
    if raw is None:
        return None, [problem] if problem else []
    return parse_spec_bytes(raw, display, fmt)


def read_spec_file_bytes(path: Path, display: str) -> tuple[bytes | None, Diagnostic | None]:
    """The file's bytes, refusing what is not a plain file (a FIFO would block the read
    forever) and what is too large by its size, before reading it."""
    try:
        status = path.stat()
        if not stat.S_ISREG(status.st_mode):
            what = "a folder" if stat.S_ISDIR(status.st_mode) else "not a regular file"
            return None, error(
                Location(display), SPEC_UNREADABLE, f"cannot read spec: it is {what}"
            )
        if status.st_size > MAX_BYTES:
            return None, _too_large(display)
        # O_NONBLOCK: should the path become a FIFO after the check, opening it cannot hang
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(descriptor, "rb") as handle:
            raw = handle.read(MAX_BYTES + 1)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        return None, error(Location(display), SPEC_UNREADABLE, f"cannot read spec: {reason}")
    return raw, None


def _too_large(display: str) -> Diagnostic:
    return error(
        Location(display),
        SPEC_TOO_LARGE,
        f"spec is larger than {MAX_BYTES // 1024} KiB",
        "a spec is a few KiB; is this the right file?",
    )


def parse_spec_bytes(
    raw: bytes, display: str, fmt: str
) -> tuple[LoadedSpec | None, list[Diagnostic]]:
    if len(raw) > MAX_BYTES:
        return None, [_too_large(display)]
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        column = exc.start - (raw.rfind(b"\n", 0, exc.start) + 1) + 1
        return None, [
            error(Location(display, line, column), SPEC_UNREADABLE, "spec is not valid UTF-8 text")
        ]
    if text.startswith("\ufeff"):
        text = text[1:]
    if not text.strip():
        # YAML rejects a tab that starts a line even when nothing follows: still just empty
        return None, [error(Location(display), SPEC_NOT_A_MAPPING, "spec is empty")]
    source = SourceMap(display)
    limit = prescan(text, indentation_nests=fmt == "yaml")
    if limit is not None:
        return None, [
            error(Location(display, limit.line, limit.column), SPEC_TOO_LARGE, limit.message)
        ]
    if fmt == "yaml":
        data, diagnostics = _load_yaml(text, source)
    else:
        data, diagnostics = _load_toml(text, source)
    if diagnostics:
        return None, diagnostics
    if data is None or (isinstance(data, dict) and not data):
        return None, [error(Location(display), SPEC_NOT_A_MAPPING, "spec is empty")]
    if not isinstance(data, dict):
        return None, [
            error(
                source.value(()), SPEC_NOT_A_MAPPING, "a spec must be a mapping of keys to values"
            )
        ]
    return LoadedSpec(display, data, source, raw, fmt), []


# --------------------------------------------------------------------------------------------
# YAML


def _load_yaml(text: str, source: SourceMap) -> tuple[Any, list[Diagnostic]]:
    from ruamel.yaml import YAML
    from ruamel.yaml.constructor import DuplicateKeyError
    from ruamel.yaml.error import MarkedYAMLError, YAMLError
    from ruamel.yaml.reader import ReaderError

    yaml = YAML(typ="rt")
    try:
        with warnings.catch_warnings():
            # ruamel warns (on stderr, naming its own source file) about an anchor defined
            # twice, which YAML allows: the later one wins, as aliases after it show
            warnings.simplefilter("ignore")
            document = yaml.load(text)
    except DuplicateKeyError as exc:
        return None, [_explained(_duplicate_yaml(exc, text), source)]
    except MarkedYAMLError as exc:
        explained = _explained_yaml(exc, text)
        if explained is not None:
            return None, [_explained(explained, source)]
        message = " ".join(p for p in (exc.context, exc.problem) if p) or "YAML syntax error"
        return None, [_marked(exc, text, source, SPEC_SYNTAX, message)]
    except ReaderError as exc:
        return None, [_unreadable_character(exc, text, source)]
    except ValueError as exc:
        return None, [_value_error(exc, text, source, "YAML")]
    except NotImplementedError as exc:  # ruamel's round-trip reader and some comment layouts
        return None, [_comment_overlap(exc, text, source)]
    except TypeError:  # a mapping key that is itself a mapping holding a list: unhashable
        line, column = _first_collection_key(text)
        return None, [
            error(
                Location(source.file, line, column),
                SPEC_SYNTAX,
                "YAML: keys must be plain scalars, not lists or mappings",
            )
        ]
    except (YAMLError, RecursionError) as exc:
        return None, [error(Location(source.file), SPEC_SYNTAX, f"YAML error: {exc}")]
    too_big = _alias_expansion(document, source)
    if too_big is not None:
        return None, [too_big]
    try:
        data = _walk_yaml(document, (), source, [0], text.split("\n"))
    except _TooBig as exc:
        return None, [error(source.key(exc.path), exc.code, str(exc))]
    _keep_within_text(source, text)
    return data, []


def _keep_within_text(source: SourceMap, text: str) -> None:
    """ruamel places an empty value at the end of the file (``key:`` on the last line) on the
    line after it; move such positions onto the last line so every diagnostic names a line."""
    last = len(text.splitlines()) or 1
    for table in (source.keys, source.values):
        for path, (line, column) in table.items():
            if line > last:
                table[path] = _within_text(text, line, column)


def _alias_expansion(document: Any, source: SourceMap) -> Diagnostic | None:
    """Count what the document expands to, each shared (aliased) node counted once per use
    but measured once, before walking it: an alias bomb is refused in time linear in its text.
    Located at the top-level key whose value crosses the limit."""
    from ruamel.yaml.comments import CommentedMap, CommentedSeq

    sizes: dict[int, int] = {}

    def size(node: Any) -> int:
        known = sizes.get(id(node))
        if known is not None:
            return known
        total = 1
        if isinstance(node, CommentedMap):
            total += sum(size(child) for child in node.values())
        elif isinstance(node, CommentedSeq):
            total += sum(size(child) for child in node)
        sizes[id(node)] = total
        return total

    if size(document) <= MAX_NODES:
        return None
    line, column, running = 1, 1, 1
    if isinstance(document, CommentedMap):
        for key, value in document.items():
            running += size(value)
            if running > MAX_NODES:
                position = (document.lc.data or {}).get(key)
                if position is not None:
                    line, column = position[0] + 1, position[1] + 1
                break
    return error(
        Location(source.file, line, column),
        SPEC_TOO_LARGE,
        f"spec expands to more than {MAX_NODES} values (alias bomb?)",
        "an alias (*name) repeats its anchor's whole value each time it is used",
    )


def _first_collection_key(text: str) -> tuple[int, int]:
    """Where the first mapping key that is a list or a mapping starts (1:1 if none is found),
    from the parser's events: ruamel's constructor fails on it without saying where."""
    from ruamel.yaml import YAML
    from ruamel.yaml.events import (
        AliasEvent,
        CollectionEndEvent,
        CollectionStartEvent,
        MappingStartEvent,
        ScalarEvent,
    )

    frames: list[list[Any]] = []  # per open collection: [is_mapping, items seen]
    try:
        for event in YAML(typ="rt").parse(text):
            if isinstance(event, (ScalarEvent, AliasEvent, CollectionStartEvent)):
                at_key = bool(frames) and frames[-1][0] and frames[-1][1] % 2 == 0
                if isinstance(event, CollectionStartEvent) and at_key:
                    mark = event.start_mark
                    return _within_text(text, mark.line + 1, mark.column + 1)
                if frames:
                    frames[-1][1] += 1
                if isinstance(event, CollectionStartEvent):
                    frames.append([isinstance(event, MappingStartEvent), 0])
            elif isinstance(event, CollectionEndEvent) and frames:
                frames.pop()
    except Exception:  # the events are only a locator: a file they cannot read stays at 1:1
        pass
    return 1, 1


_COMMENT_TOKEN = re.compile(r"CommentToken\(.*?line: (\d+), col: (\d+)\)")


def _comment_overlap(exc: NotImplementedError, text: str, source: SourceMap) -> Diagnostic:
    """ruamel.yaml's round-trip parser gives up on some comments placed between a key and a
    value it has not finished ("overlap in comment"); it names the comment token's 0-based
    position only in its message."""
    found = _COMMENT_TOKEN.search(str(exc))
    line, column = (int(found.group(1)) + 1, int(found.group(2)) + 1) if found else (1, 1)
    line, column = _within_text(text, line, column)
    return error(
        Location(source.file, line, column),
        SPEC_SYNTAX,
        "YAML: this comment cannot be read where it is (ruamel.yaml gives up on it)",
        "move the comment onto a line of its own",
    )


def _value_error(exc: ValueError, text: str, source: SourceMap, language: str) -> Diagnostic:
    """A value the parser could not convert; in practice an integer with more digits than
    Python converts (``sys.get_int_max_str_digits``), located at the first such digit run."""
    limit = sys.get_int_max_str_digits() if hasattr(sys, "get_int_max_str_digits") else 4300
    long_number = re.compile("[0-9][0-9_]{" + str(max(limit, 1)) + ",}")
    found = long_number.search(text)
    if found is None:
        return error(Location(source.file), SPEC_SYNTAX, f"{language}: {exc}")
    line, column = line_column(text, found.start())
    return error(
        Location(source.file, line, column),
        SPEC_SYNTAX,
        f"{language}: a number with more than {limit} digits",
        "no value in a spec needs that many digits",
    )


def _unreadable_character(exc: Any, text: str, source: SourceMap) -> Diagnostic:
    """A character YAML forbids (a control character): located by its offset in the text,
    which is all ruamel's reader gives."""
    position = exc.position if isinstance(exc.position, int) else 0
    line, column = line_column(text, position)
    character = exc.character  # an int (the code point), or a str in some ruamel versions
    code_point = ord(character) if isinstance(character, str) else int(character)
    shown = f"U+{code_point:04X}"
    return error(
        Location(source.file, line, column),
        SPEC_SYNTAX,
        f"YAML does not allow the character {shown} here",
        "control characters (other than tab and line breaks) must be escaped in a quoted string",
    )


def _duplicate_yaml(exc: Any, text: str) -> Explained:
    from robospec.load.syntax_hints import duplicate_key

    match = re.search(r'found duplicate key "([^"]*)"', str(exc))
    mark = exc.problem_mark
    line, column = _within_text(text, mark.line + 1, mark.column + 1)
    return duplicate_key(text, match.group(1) if match else None, line, column, "yaml")


def _explained_yaml(exc: Any, text: str) -> Explained | None:
    from robospec.load.syntax_hints import explain_yaml

    mark = exc.problem_mark or exc.context_mark
    if mark is None:
        return None
    opened = exc.context_mark if exc.problem_mark is not None else None
    return explain_yaml(
        exc.problem or "",
        text,
        mark.line + 1,
        mark.column + 1,
        exc.context or "",
        (opened.line + 1, opened.column + 1) if opened is not None else None,
    )


def _explained(explained: Explained, source: SourceMap) -> Diagnostic:
    location = Location(source.file, explained.line, explained.column)
    return error(location, explained.code, explained.message, explained.hint)


def _marked(exc: Any, text: str, source: SourceMap, code: str, message: str) -> Diagnostic:
    mark = exc.problem_mark or exc.context_mark
    if mark is None:
        return error(Location(source.file), code, message)
    line, column = _within_text(text, mark.line + 1, mark.column + 1)
    return error(Location(source.file, line, column), code, message)


def _within_text(text: str, line: int, column: int) -> tuple[int, int]:
    """A position the file has: the parser's mark for "end of input" lies on the line after
    a final newline, which an editor does not show; point past the last character instead."""
    lines = text.splitlines() or [""]
    if line <= len(lines):
        return line, column
    return len(lines), len(lines[-1]) + 1


def _spend(path: KeyPath, count: list[int]) -> None:
    """Count one value against the size and depth budget (an alias bomb exhausts it early)."""
    count[0] += 1
    if count[0] > MAX_NODES:
        raise _TooBig(f"spec expands to more than {MAX_NODES} values (alias bomb?)", path)
    if len(path) > MAX_DEPTH:
        raise _TooBig(f"spec is nested deeper than {MAX_DEPTH} levels", path)


def _walk_yaml(
    node: Any, path: KeyPath, source: SourceMap, count: list[int], lines: list[str]
) -> Any:
    """Turn ruamel's round-trip nodes into plain data, recording positions as we go; a float
    keeps the text the spec wrote it with (ruamel's ScalarFloat does not)."""
    _spend(path, count)
    from ruamel.yaml.comments import CommentedMap, CommentedSeq

    if isinstance(node, CommentedMap):
        result: dict[str, Any] = {}
        for key in node:
            if not isinstance(key, (str, int, float, bool)) and key is not None:
                raise _TooBig(
                    "keys must be plain scalars, not lists or mappings", path, SPEC_SYNTAX
                )
            name = str(key) if key is not None else "null"
            child = (*path, name)
            position = (node.lc.data or {}).get(key)
            if position is None:
                # a key merged in with `<<: *anchor` has no position of its own: use the map's
                source.keys[child] = source.values[child] = source.values.get(path, (1, 1))
            else:
                source.keys[child] = (position[0] + 1, position[1] + 1)
                source.values[child] = (position[2] + 1, position[3] + 1)
            result[name] = _walk_yaml(node[key], child, source, count, lines)
        return result
    if isinstance(node, CommentedSeq):
        items = []
        for index, item in enumerate(node):
            child = (*path, index)
            position = (node.lc.data or {}).get(index)
            if position is None:
                # an item ruamel did not place (e.g. in a sequence merged with `<<:`): the
                # sequence's own position
                source.keys[child] = source.values[child] = source.values.get(path, (1, 1))
            else:
                source.keys[child] = source.values[child] = (position[0] + 1, position[1] + 1)
            items.append(_walk_yaml(item, child, source, count, lines))
        return items
    if isinstance(node, bool) or node is None:
        return node
    if isinstance(node, int):
        return int(node)
    if isinstance(node, float):
        return written_number(float(node), source.values.get(path), lines)
    if isinstance(node, str):
        return str(node)
    # timestamps, binary, ...: keep as text so the schema reports a located type error
    return str(node)


# a number literal, after any YAML anchor (&name) or tag (!!float) written before it
_NUMBER_TEXT = re.compile(r"(?:[&!]\S*\s+)*([-+]?[0-9_]*\.?[0-9_]*(?:[eE][-+]?[0-9_]+)?)")


def written_number(value: float, position: tuple[int, int] | None, lines: list[str]) -> float:
    """``value`` with the text the spec wrote it with, read at its 1-based ``position``: a
    :class:`WrittenNumber` when that text is a number literal giving exactly ``value`` (an
    aliased or merged value is placed elsewhere), else the plain float."""
    if position is None or not 1 <= position[0] <= len(lines):
        return value
    line, column = position
    found = _NUMBER_TEXT.match(lines[line - 1], column - 1)
    text = found.group(1) if found else ""
    try:
        same = repr(float(text.replace("_", ""))) == repr(value)  # repr: -0.0 is not 0.0
    except ValueError:
        return value
    return WrittenNumber(value, text) if same else value


# --------------------------------------------------------------------------------------------
# TOML


def _load_toml(text: str, source: SourceMap) -> tuple[Any, list[Diagnostic]]:
    from robospec.load.toml_parser import tomllib

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        from robospec.load.syntax_hints import duplicate_key, explain_toml
        from robospec.load.toml_positions import tomllib_error_location

        line, column, message = tomllib_error_location(exc, text)
        explained = explain_toml(message, text, line, column)
        if explained is None and ("overwrite" in message or "twice" in message):
            explained = duplicate_key(text, None, line, column, "toml")
        if explained is not None:
            return None, [_explained(explained, source)]
        # "end of document" after a final newline is a line the file does not show
        location = Location(source.file, *_within_text(text, line, column))
        return None, [error(location, SPEC_SYNTAX, f"TOML: {message}")]
    except ValueError as exc:  # an integer longer than Python converts
        return None, [_value_error(exc, text, source, "TOML")]
    except RecursionError:
        return None, [error(Location(source.file), SPEC_TOO_LARGE, "TOML nested too deeply")]
    from robospec.load.toml_positions import toml_positions

    for path, (key_pos, value_pos) in toml_positions(text).items():
        source.keys[path] = key_pos
        source.values[path] = value_pos
    try:
        _check_toml_size(data, (), [0])
    except _TooBig as exc:
        return None, [error(source.key(exc.path), SPEC_TOO_LARGE, str(exc))]
    return _plain_toml(data, (), source, text.split("\n")), []


def _check_toml_size(node: Any, path: KeyPath, count: list[int]) -> None:
    _spend(path, count)
    if isinstance(node, dict):
        for key, value in node.items():
            _check_toml_size(value, (*path, key), count)
    elif isinstance(node, list):
        for index, value in enumerate(node):
            _check_toml_size(value, (*path, index), count)


def _plain_toml(node: Any, path: KeyPath, source: SourceMap, lines: list[str]) -> Any:
    """Plain data; a float keeps the text the spec wrote it with (tomllib's does not)."""
    # dates and times have no meaning in a spec: keep them as text for a located type error
    if isinstance(node, dict):
        return {k: _plain_toml(v, (*path, k), source, lines) for k, v in node.items()}
    if isinstance(node, list):
        return [_plain_toml(v, (*path, i), source, lines) for i, v in enumerate(node)]
    if isinstance(node, float):
        return written_number(node, source.values.get(path), lines)
    if isinstance(node, (str, int, bool)):
        return node
    return str(node)
