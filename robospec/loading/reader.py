"""Read a spec file (YAML or TOML) into plain data and a source map. Never raises on bad input."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from robospec.diagnostics import Diagnostic, Location, error
from robospec.loading.source import KeyPath, LoadedSpec, SourceMap

SPEC_SUFFIXES = {".yaml": "yaml", ".yml": "yaml", ".toml": "toml"}
MAX_BYTES = 2 * 1024 * 1024
MAX_NODES = 200_000  # an alias bomb expands far past this while the file stays tiny
MAX_DEPTH = 64


class _TooBig(Exception):
    def __init__(self, message: str, path: KeyPath) -> None:
        super().__init__(message)
        self.path = path


def read_spec(path: Path, display: str | None = None) -> tuple[LoadedSpec | None, list[Diagnostic]]:
    display = display or str(path)
    fmt = SPEC_SUFFIXES.get(path.suffix.lower())
    if fmt is None:
        return None, [
            error(
                Location(display),
                "RS005",
                f"unsupported spec file type '{path.suffix}'",
                "use .yaml, .yml or .toml",
            )
        ]
    try:
        raw = path.read_bytes()
    except OSError as exc:
        return None, [error(Location(display), "RS001", f"cannot read spec: {exc.strerror}")]
    return parse_spec_bytes(raw, display, fmt)


def parse_spec_bytes(
    raw: bytes, display: str, fmt: str
) -> tuple[LoadedSpec | None, list[Diagnostic]]:
    if len(raw) > MAX_BYTES:
        return None, [
            error(Location(display), "RS006", f"spec is larger than {MAX_BYTES // 1024} KiB")
        ]
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        column = exc.start - (raw.rfind(b"\n", 0, exc.start) + 1) + 1
        return None, [
            error(Location(display, line, column), "RS001", "spec is not valid UTF-8 text")
        ]
    if text.startswith("\ufeff"):
        text = text[1:]
    source = SourceMap(display)
    if fmt == "yaml":
        data, diagnostics = _load_yaml(text, source)
    else:
        data, diagnostics = _load_toml(text, source)
    if diagnostics:
        return None, diagnostics
    if data is None or (isinstance(data, dict) and not data):
        return None, [error(Location(display), "RS004", "spec is empty")]
    if not isinstance(data, dict):
        return None, [
            error(source.value(()), "RS004", "a spec must be a mapping of keys to values")
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
        document = yaml.load(text)
    except DuplicateKeyError as exc:
        return None, [_marked(exc, source, "RS003", _duplicate_message(exc))]
    except MarkedYAMLError as exc:
        message = " ".join(p for p in (exc.context, exc.problem) if p) or "YAML syntax error"
        return None, [_marked(exc, source, "RS002", message)]
    except ReaderError as exc:
        return None, [_unreadable_character(exc, text, source)]
    except (YAMLError, RecursionError, ValueError) as exc:
        return None, [error(Location(source.file), "RS002", f"YAML error: {exc}")]
    try:
        data = _walk_yaml(document, (), source, [0])
    except _TooBig as exc:
        return None, [error(source.key(exc.path), "RS006", str(exc))]
    return data, []


def _unreadable_character(exc: Any, text: str, source: SourceMap) -> Diagnostic:
    """A character YAML forbids (a control character): located by its offset in the text,
    which is all ruamel's reader gives."""
    position = exc.position if isinstance(exc.position, int) else 0
    line = text.count("\n", 0, position) + 1
    column = position - (text.rfind("\n", 0, position) + 1) + 1
    character = exc.character  # an int (the code point), or a str in some ruamel versions
    code_point = ord(character) if isinstance(character, str) else int(character)
    shown = f"U+{code_point:04X}"
    return error(
        Location(source.file, line, column),
        "RS002",
        f"YAML does not allow the character {shown} here",
        "control characters (other than tab and line breaks) must be escaped in a quoted string",
    )


def _duplicate_message(exc: Any) -> str:
    match = re.search(r'found duplicate key "([^"]*)"', str(exc))
    return f"duplicate key '{match.group(1)}'" if match else "duplicate key"


def _marked(exc: Any, source: SourceMap, code: str, message: str) -> Diagnostic:
    mark = exc.problem_mark or exc.context_mark
    if mark is None:
        return error(Location(source.file), code, message)
    return error(Location(source.file, mark.line + 1, mark.column + 1), code, message)


def _spend(path: KeyPath, count: list[int]) -> None:
    """Count one value against the size and depth budget (an alias bomb exhausts it early)."""
    count[0] += 1
    if count[0] > MAX_NODES:
        raise _TooBig(f"spec expands to more than {MAX_NODES} values (alias bomb?)", path)
    if len(path) > MAX_DEPTH:
        raise _TooBig(f"spec is nested deeper than {MAX_DEPTH} levels", path)


def _walk_yaml(node: Any, path: KeyPath, source: SourceMap, count: list[int]) -> Any:
    """Turn ruamel's round-trip nodes into plain data, recording positions as we go."""
    _spend(path, count)
    from ruamel.yaml.comments import CommentedMap, CommentedSeq

    if isinstance(node, CommentedMap):
        result: dict[str, Any] = {}
        for key in node:
            if not isinstance(key, (str, int, float, bool)) and key is not None:
                raise _TooBig("keys must be plain scalars", path)
            name = str(key) if key is not None else "null"
            child = (*path, name)
            line, column = node.lc.key(key)
            source.keys[child] = (line + 1, column + 1)
            vline, vcolumn = node.lc.value(key)
            source.values[child] = (vline + 1, vcolumn + 1)
            result[name] = _walk_yaml(node[key], child, source, count)
        return result
    if isinstance(node, CommentedSeq):
        items = []
        for index, item in enumerate(node):
            child = (*path, index)
            line, column = node.lc.item(index)
            source.keys[child] = source.values[child] = (line + 1, column + 1)
            items.append(_walk_yaml(item, child, source, count))
        return items
    if isinstance(node, bool) or node is None:
        return node
    if isinstance(node, int):
        return int(node)
    if isinstance(node, float):
        return float(node)
    if isinstance(node, str):
        return str(node)
    # timestamps, binary, ...: keep as text so the schema reports a located type error
    return str(node)


# --------------------------------------------------------------------------------------------
# TOML

_TOML_POSITION = re.compile(r"\(at line (\d+), column (\d+)\)")


def _load_toml(text: str, source: SourceMap) -> tuple[Any, list[Diagnostic]]:
    import tomllib

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        match = _TOML_POSITION.search(message)
        location = Location(source.file)
        if match:
            location = Location(source.file, int(match.group(1)), int(match.group(2)))
            message = message[: match.start()].strip()
        code = "RS003" if "overwrite" in message.lower() else "RS002"
        return None, [error(location, code, f"TOML: {message}")]
    except RecursionError:
        return None, [error(Location(source.file), "RS006", "TOML nested too deeply")]
    from robospec.loading.toml_positions import toml_positions

    for path, (key_pos, value_pos) in toml_positions(text).items():
        source.keys[path] = key_pos
        source.values[path] = value_pos
    try:
        _check_toml_size(data, (), [0])
    except _TooBig as exc:
        return None, [error(source.key(exc.path), "RS006", str(exc))]
    return _plain_toml(data), []


def _check_toml_size(node: Any, path: KeyPath, count: list[int]) -> None:
    _spend(path, count)
    if isinstance(node, dict):
        for key, value in node.items():
            _check_toml_size(value, (*path, key), count)
    elif isinstance(node, list):
        for index, value in enumerate(node):
            _check_toml_size(value, (*path, index), count)


def _plain_toml(node: Any) -> Any:
    # dates and times have no meaning in a spec: keep them as text for a located type error
    if isinstance(node, dict):
        return {key: _plain_toml(value) for key, value in node.items()}
    if isinstance(node, list):
        return [_plain_toml(value) for value in node]
    if isinstance(node, (str, int, float, bool)):
        return node
    return str(node)
