"""Stage 3 of `robospec import`: spec data → YAML text, written with ruamel.yaml.

Sections are block mappings (a section that is a list of mappings, or of lists too long for
one line, is a block sequence: one item a line); a mapping below a section that fits on a few
lines, and every other list, is written in flow style, laid out as in the hand-written specs (a
long flow mapping starts on its own line and breaks after commas, never between a key and its
value). Numbers
are Python's ``repr`` (which reads back exactly), or a ``pi`` expression where that evaluates to
exactly the same float.
"""

from __future__ import annotations

import io
import math
import re
from functools import cache
from typing import Any

from robospec.importer.specdata import KeyPath, SpecDoc

WIDTH = 100
FLOW_LINES = 3  # a mapping below a section is written in flow style up to this many lines
NESTED_FLOW = 48  # ... when no list or mapping nested in it is longer than this
BLANK_BEFORE = (
    "materials",
    "groups",
    "keyframes",
    "controllers",
    "control_modes",
    "cameras",
    "collision_rules",
    "tcp",
)
_TOKEN = "RSFLOW{}X"
_TOKEN_LINE = re.compile(r"^(?P<head>\s*(?:\S.*?:|-))\s+RSFLOW(?P<n>\d+)X(?P<comment>\s+#.*)?$")


class _Plain(str):
    """A string written without quotes (a ``pi`` expression)."""


@cache
def _pi_table() -> dict[float, str]:
    from robospec.model.expressions import evaluate

    table: dict[float, str] = {}
    for denominator in range(1, 13):
        for numerator in range(-24, 25):
            if numerator == 0 or math.gcd(numerator, denominator) != 1:
                continue
            k = abs(numerator)
            text = ("-" if numerator < 0 else "") + ("pi" if k == 1 else f"{k}*pi")
            if denominator != 1:
                text += f"/{denominator}"
            table.setdefault(evaluate(text), text)
    return table


def number_text(value: float | int) -> str:
    if isinstance(value, int):
        return str(value)
    if math.isnan(value):
        return ".nan"
    if math.isinf(value):
        return ".inf" if value > 0 else "-.inf"
    return _pi_table().get(value) or repr(value)


def _yaml() -> Any:
    from ruamel.yaml import YAML

    yaml = YAML()
    yaml.width = WIDTH
    yaml.indent(mapping=2, sequence=4, offset=2)
    yaml.representer.add_representer(
        _Plain, lambda r, data: r.represent_scalar("tag:yaml.org,2002:str", str(data), style="")
    )
    yaml.representer.add_representer(
        float, lambda r, data: r.represent_scalar("tag:yaml.org,2002:float", number_text(data))
    )
    yaml.representer.add_representer(
        type(None), lambda r, data: r.represent_scalar("tag:yaml.org,2002:null", "null")
    )
    return yaml


def _scalar(value: Any) -> Any:
    if isinstance(value, float) and not isinstance(value, bool):
        text = number_text(value)
        return _Plain(text) if "pi" in text else value
    return value


@cache
def _flow_scalar(value: Any, kind: type) -> str:
    """How ruamel writes one scalar inside a flow collection (quoted where it must be)."""
    from ruamel.yaml.comments import CommentedSeq

    seq = CommentedSeq([_scalar(value)])
    seq.fa.set_flow_style()
    stream = io.StringIO()
    yaml = _yaml()
    yaml.width = 10**6
    yaml.dump(seq, stream)
    return stream.getvalue().strip()[1:-1]


def _text(value: object) -> str:
    return _flow_scalar(value, type(value))  # type: ignore[arg-type]  # a class is hashable


def flow_pieces(value: Any) -> list[str]:
    """The flow text of ``value`` cut after each comma, at any depth."""
    if isinstance(value, dict):
        items = [(f"{_text(k)}: ", v) for k, v in value.items()]
        opening, closing = "{", "}"
    elif isinstance(value, list):
        items = [("", v) for v in value]
        opening, closing = "[", "]"
    else:
        return [_text(value)]
    if not items:
        return [opening + closing]
    pieces: list[str] = []
    for index, (prefix, item) in enumerate(items):
        inner = flow_pieces(item)
        inner[0] = prefix + inner[0]
        if index == 0:
            inner[0] = opening + inner[0]
        inner[-1] += closing if index == len(items) - 1 else ","
        pieces.extend(inner)
    return pieces


def layout(pieces: list[str], column: int) -> list[str]:
    """Join pieces into lines of at most WIDTH characters; continuation lines start one
    column after the opening bracket at ``column``."""
    lines = [pieces[0]]
    for piece in pieces[1:]:
        if column + len(lines[-1]) + 1 + len(piece) <= WIDTH:
            lines[-1] += " " + piece
        else:
            lines.append(piece)
    return [lines[0]] + [" " * (column + 1) + line for line in lines[1:]]


def _has_note(path: KeyPath, notes: dict[KeyPath, str]) -> bool:
    return any(p[: len(path)] == path and len(p) > len(path) for p in notes)


def _fits_flow(value: dict[str, Any], indent: int) -> bool:
    """One line; or a few lines when nothing nested in it is long (a long list inside reads
    better on its own line of a block mapping)."""
    lines = layout(flow_pieces(value), indent)
    if len(lines) == 1:
        return True
    nested = [v for v in value.values() if isinstance(v, (list, dict))]
    return len(lines) <= FLOW_LINES and all(
        len(" ".join(flow_pieces(v))) <= NESTED_FLOW for v in nested
    )


class _Writer:
    def __init__(self, notes: dict[KeyPath, str]) -> None:
        self.notes = notes
        self.flows: list[Any] = []

    def node(self, value: Any, path: KeyPath, indent: int) -> Any:
        from ruamel.yaml.comments import CommentedMap, CommentedSeq

        if (
            len(path) == 1
            and isinstance(value, list)
            and value
            and all(isinstance(item, dict) for item in value)
        ):  # a section that is a list of mappings (collision_rules): one mapping a line
            seq = CommentedSeq()
            seq.extend(self.node(item, (*path, i), indent + 2) for i, item in enumerate(value))
            return seq
        if (
            len(path) == 1
            and isinstance(value, list)
            and value
            and all(isinstance(item, list) for item in value)
            and len(layout(flow_pieces(value), len(str(path[0])) + 2)) > 1
        ):  # a section that is a list of lists too long for a line (never_collide): one a line
            seq = CommentedSeq()
            seq.extend(self.node(item, (*path, i), indent + 2) for i, item in enumerate(value))
            return seq
        if isinstance(value, list) or (
            isinstance(value, dict)
            and (len(path) >= 2 or path == ("loader",))
            and not _has_note(path, self.notes)
            and _fits_flow(value, indent)
        ):
            self.flows.append(value)
            return _Plain(_TOKEN.format(len(self.flows) - 1))
        if isinstance(value, dict):
            node = CommentedMap()
            for key, item in value.items():
                where = (*path, key)
                node[key] = self.node(item, where, indent + 2)
                if where in self.notes:
                    node.yaml_add_eol_comment("# " + self.notes[where], key)
            return node
        return _scalar(value)

    def expand(self, line: str) -> list[str]:
        match = _TOKEN_LINE.match(line)
        if match is None:
            return [line.rstrip()]
        head = match.group("head")
        comment = (match.group("comment") or "").strip()
        pieces = flow_pieces(self.flows[int(match.group("n"))])
        one_line = layout(pieces, len(head) + 1)
        if len(one_line) == 1 or isinstance(self.flows[int(match.group("n"))], list):
            first = head + " " + one_line[0] + (f"  {comment}" if comment else "")
            return [first, *one_line[1:]]
        if comment:
            head += f"  {comment}"
        indent = len(head) - len(head.lstrip()) + 2
        return [
            head,
            *(
                " " * indent + text if i == 0 else text
                for i, text in enumerate(layout(pieces, indent))
            ),
        ]


def to_yaml(doc: SpecDoc, schema_ref: str) -> str:
    writer = _Writer(doc.notes)
    root = writer.node(doc.data, (), 0)
    stream = io.StringIO()
    yaml = _yaml()
    yaml.width = 10**6  # flow collections are laid out by `layout`
    yaml.dump(root, stream)
    lines = [f"# yaml-language-server: $schema={schema_ref}"]
    lines += [f"# {line}" if line else "#" for line in doc.header]
    for line in stream.getvalue().splitlines():
        if not line.startswith(" ") and line.split(":", 1)[0] in BLANK_BEFORE:
            lines.append("")
        lines.extend(writer.expand(line))
    return "\n".join(lines) + "\n"
