"""YAML edits for ``robospec tune --write``: positions from ruamel's round-trip load, changes
made in the text at those positions (a scalar's token, a list's items, a flow collection's
brackets), so every other character of the file stays as it was."""

from __future__ import annotations

import io
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap, CommentedSeq

from robospec.tune.edits import (
    Edit,
    WriteError,
    fit_lines,
    flow_list,
    line_width,
    number_text,
    plan,
    uniform,
)
from robospec.tune.results import ControllerTuning

Span = tuple[int, int]  # offsets into the text: [start, end)
# a replacement's text, or what makes it from the column it will start at in the edited text
# (a wrapped flow list aligns its lines after its bracket, wherever earlier edits moved it)
Replacement = str | Callable[[int, int], str]  # (column, indent of its line + 2) -> text


class Text:
    """The spec's text and the replacements to make in it (applied last to first)."""

    def __init__(self, text: str, width: int) -> None:
        self.text = text
        self.width = width  # what no edited line may pass
        self.starts = [0]
        for line in text.splitlines(keepends=True):
            self.starts.append(self.starts[-1] + len(line))
        self.replacements: list[tuple[Span, Replacement]] = []

    def offset(self, line: int, column: int) -> int:
        return self.starts[line] + column

    def column(self, offset: int) -> int:
        return offset - self.text.rfind("\n", 0, offset) - 1

    def replace(self, span: Span, new: Replacement) -> None:
        for (start, end), _ in self.replacements:
            if start < span[1] and span[0] < end:
                raise WriteError("two edits of the same value")
        self.replacements.append((span, new))

    def result(self) -> str:
        out: list[str] = []
        done = 0
        for (start, end), new in sorted(self.replacements, key=lambda r: r[0]):
            out.append(self.text[done:start])
            if callable(new):
                so_far = "".join(out)
                line = so_far[so_far.rfind("\n") + 1 :]
                new = new(len(line), len(line) - len(line.lstrip(" ")) + 2)
            out.append(new)
            done = end
        out.append(self.text[done:])
        return fit_lines("".join(out), self.text, self.width, "[{")

    # -- token extents -----------------------------------------------------------------

    def scalar(self, start: int, flow: bool) -> Span:
        """The plain or quoted scalar starting at ``start``."""
        text = self.text
        if text[start] in "'\"":
            quote = text[start]
            end = start + 1
            while end < len(text) and text[end] != quote:
                end += 2 if text[end] == "\\" and quote == '"' else 1
            return start, end + 1
        end = start
        stops = ",]}\n" if flow else "\n"
        while end < len(text) and text[end] not in stops:
            if text[end] == "#" and text[end - 1] in " \t":
                break
            end += 1
        while end > start and text[end - 1] in " \t":
            end -= 1
        return start, end

    def flow(self, start: int) -> Span:
        """The flow collection whose bracket is at ``start``."""
        depth = 0
        index = start
        quote: str | None = None
        while index < len(self.text):
            char = self.text[index]
            if quote:
                if char == quote:
                    quote = None
            elif char in "'\"":
                quote = char
            elif char in "[{":
                depth += 1
            elif char in "]}":
                depth -= 1
                if depth == 0:
                    return start, index + 1
            index += 1
        raise WriteError("an unclosed flow collection")


def _load(text: str) -> Any:
    yaml = YAML(typ="rt")
    return yaml.load(io.StringIO(text))


def _is_flow(node: Any) -> bool:
    return bool(node.fa.flow_style()) if hasattr(node, "fa") else False


def _value_start(parent: CommentedMap, key: str, text: Text) -> int:
    line, column = parent.lc.value(key)
    return text.offset(line, column)


def _node_span(parent: CommentedMap, key: str, text: Text, parent_flow: bool) -> Span:
    """Where ``parent[key]``'s value is written."""
    node = parent[key]
    start = _value_start(parent, key, text)
    if isinstance(node, (CommentedMap, CommentedSeq)):
        if _is_flow(node):
            return text.flow(start)
        raise WriteError(
            f"'{key}' is written as a block collection; write it as one value or a flow list "
            "and run tune --write again"
        )
    return text.scalar(start, parent_flow)


def edit_yaml(
    source: str,
    tunings: Sequence[ControllerTuning],
    uid: str | None,
    current: Mapping[str, Mapping[str, Any]] | None = None,
) -> str:
    data = _load(source)
    text = Text(source, line_width(source))
    if uid is not None:
        if "uid" not in data:
            raise WriteError("the spec has no uid to change")
        text.replace(_node_span(data, "uid", text, False), uid)
    controllers = data.get("controllers")
    if not isinstance(controllers, CommentedMap):
        raise WriteError("the spec has no controllers mapping")
    inserts: dict[str, list[Edit]] = {}
    for edit in plan(controllers, tunings, current):
        if edit.insert:
            inserts.setdefault(edit.owner, []).append(edit)
        else:
            _set(text, controllers[edit.owner], edit)
    for owner, edits in inserts.items():
        _insert(text, controllers, owner, edits)
    return text.result()


def _set(text: Text, entry: CommentedMap, edit: Edit) -> None:
    node = entry[edit.field]
    flow = _is_flow(entry)
    values = edit.values
    if uniform(values) and not isinstance(node, (CommentedMap, CommentedSeq)):
        text.replace(_node_span(entry, edit.field, text, flow), number_text(values[0]))
        return
    if isinstance(node, CommentedSeq) and len(node) == len(values):
        item_flow = _is_flow(node)
        for index, value in enumerate(values):
            line, column = node.lc.item(index)
            span = text.scalar(text.offset(line, column), item_flow)
            if text.text[span[0] : span[1]] != number_text(value):
                text.replace(span, number_text(value))
        return
    if isinstance(node, CommentedMap) and set(node) == set(edit.joints):
        item_flow = _is_flow(node)
        for joint, value in zip(edit.joints, values, strict=True):
            line, column = node.lc.value(joint)
            span = text.scalar(text.offset(line, column), item_flow)
            if text.text[span[0] : span[1]] != number_text(value):
                text.replace(span, number_text(value))
        return
    span = _node_span(entry, edit.field, text, flow)
    if uniform(values):
        text.replace(span, number_text(values[0]))
    else:
        width = text.width
        text.replace(span, lambda column, indent: flow_list(values, column, indent, width))


def _insert(text: Text, controllers: CommentedMap, owner: str, edits: Sequence[Edit]) -> None:
    entry = controllers[owner]
    if not isinstance(entry, CommentedMap) or not entry:
        raise WriteError(f"controller '{owner}' is not a mapping")
    if _is_flow(entry):
        start, end = text.flow(_value_start(controllers, owner, text))
        close = end - 1  # the closing brace
        before = text.text[start + 1 : close].rstrip()
        at = start + 1 + len(before)

        def pieces(column: int, indent: int) -> str:
            out = ""
            for edit in edits:
                out += f", {edit.field}: "
                here = column + len(out) if "\n" not in out else len(out) - out.rfind("\n") - 1
                out += (
                    number_text(edit.values[0])
                    if uniform(edit.values)
                    else flow_list(edit.values, here, indent, text.width)
                )
            return out

        text.replace((at, at), pieces)
        return
    keys = list(entry)
    _line, column = entry.lc.key(keys[0])
    last_line = _last_line(text, entry)
    at = text.starts[last_line + 1] if last_line + 1 < len(text.starts) else len(text.text)
    lines = []
    for edit in edits:
        prefix = " " * column + f"{edit.field}: "
        value = (
            number_text(edit.values[0])
            if uniform(edit.values)
            else flow_list(edit.values, len(prefix), width=text.width)
        )
        lines.append(prefix + value + "\n")
    insertion = "".join(lines)
    if at == len(text.text) and not text.text.endswith("\n"):
        insertion = "\n" + insertion
    text.replace((at, at), insertion)


def _last_line(text: Text, entry: CommentedMap) -> int:
    """The last line of a block mapping's own text (0-based): its last key's value, with any
    continuation lines indented deeper than its keys."""
    keys = list(entry)
    key_line, key_column = entry.lc.key(keys[-1])
    lines = text.text.splitlines()
    last = key_line
    for index in range(key_line + 1, len(lines)):
        stripped = lines[index].strip()
        if not stripped or stripped.startswith("#"):
            continue
        indent = len(lines[index]) - len(lines[index].lstrip())
        if indent <= key_column:
            break
        last = index
    return last
