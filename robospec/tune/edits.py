"""What ``robospec tune --write`` changes, shared by the YAML and TOML editors: which
controller each new gain is written at (:func:`plan`), and how the numbers are written."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from robospec.physics.findings import significant
from robospec.tune.results import ControllerTuning

FIELDS = ("stiffness", "damping", "force_limit")
WIDTH = 100  # the least line width an edited spec is held to (ruff's and the specs' own)


@dataclass(frozen=True)
class Edit:
    """Set ``field`` of controller ``owner`` to ``values`` (one per joint of ``joints``)."""

    owner: str
    field: str
    joints: tuple[str, ...]
    values: tuple[float, ...]
    insert: bool  # the controller has no such key yet


class WriteError(Exception):
    """The spec cannot be edited as asked (said in the message)."""


def number(value: float) -> int | float:
    """How a gain is written: 3 significant digits, an integer when it is one."""
    rounded = significant(float(value))
    return int(rounded) if rounded.is_integer() and abs(rounded) < 1e15 else rounded


def number_text(value: float) -> str:
    written = number(value)
    return str(written) if isinstance(written, int) else repr(written)


def plan(
    controllers: Mapping[str, Any],
    tunings: Sequence[ControllerTuning],
    current: Mapping[str, Mapping[str, Any]] | None = None,
) -> list[Edit]:
    """The edits that give each changed controller its new gains (``controllers``: the spec's
    ``controllers`` mapping as written; ``current``: each controller's resolved gains by
    field, kept by an override on a controller that inherits a gain changed at its base)."""
    changed = {t.controller: t for t in tunings if t.changed and t.after is not None}
    current = current or {}

    def owner(name: str, field: str, seen: frozenset[str] = frozenset()) -> str | None:
        entry = controllers.get(name)
        if not isinstance(entry, Mapping) or name in seen:
            return None
        if field in entry:
            return name
        base = entry.get("extends")
        return owner(str(base), field, seen | {name}) if isinstance(base, str) else None

    edits: list[Edit] = []
    for field in FIELDS:
        wanted: dict[str, tuple[tuple[str, ...], tuple[float, ...]]] = {}
        for name, tuning in changed.items():
            assert tuning.after is not None and tuning.before is not None
            after, before = getattr(tuning.after, field), getattr(tuning.before, field)
            if after != before:
                wanted[name] = (tuning.joints, tuple(after))
        sources: dict[str | None, list[str]] = {}
        for name in wanted:
            sources.setdefault(owner(name, field), []).append(name)
        for source, names in sources.items():
            if source is None:  # written nowhere yet: a new key at each controller
                edits.extend(Edit(n, field, *wanted[n], insert=True) for n in names)
                continue
            users = [c for c in controllers if owner(c, field) == source]
            values = {wanted.get(u) for u in users}
            if len(values) == 1 and None not in values:  # they all agree: change it at the base
                edits.append(Edit(source, field, *wanted[names[0]], insert=False))
                continue
            if source not in wanted:  # override at the tuned controllers only
                edits.extend(Edit(n, field, *wanted[n], insert=True) for n in names)
                continue
            # the base changes; its other users keep theirs by an override
            edits.append(Edit(source, field, *wanted[source], insert=False))
            for user in users:
                if user == source:
                    continue
                if user in wanted:
                    edits.append(Edit(user, field, *wanted[user], insert=True))
                    continue
                kept = current.get(user, {}).get(field)
                if kept is None:
                    raise WriteError(
                        f"controller '{user}' inherits {field} from '{source}' and was not "
                        f"tuned with it: tune both (--controller {user})"
                    )
                joints = tuple(current[user].get("joint_names") or ())
                kept_values = (
                    tuple(float(v) for v in kept)
                    if isinstance(kept, (list, tuple))
                    else (float(kept),) * max(len(joints), 1)
                )
                edits.append(Edit(user, field, joints, kept_values, insert=True))
    return edits


def uniform(values: Sequence[float]) -> bool:
    return len({number(v) for v in values}) == 1


def line_width(text: str) -> int:
    """The width an edit of ``text`` keeps to: its own longest line, at least :data:`WIDTH`."""
    return max([WIDTH, *(len(line) for line in text.splitlines())])


def flow_list(
    values: Sequence[float], column: int, indent: int | None = None, width: int = WIDTH
) -> str:
    """``[a, b, ...]`` starting at ``column`` (0-based): on one line when it fits on a line
    of its own; else wrapped before ``width``, the continuation lines aligned after the
    bracket, or at ``indent`` when the bracket stands so far right that little would fit.
    (Whole but past ``width`` where it starts, the line it stands on is broken before it
    afterwards: :func:`fit_lines`.)"""
    items = [number_text(v) for v in values]
    whole = "[" + ", ".join(items) + "]"
    # a list that can be read whole on one line stays whole, even where it starts far right:
    # broken after its first items (`damping: [150,` / `100, ...]`) it reads as two values
    if len(whole) <= width - (indent if indent is not None else 0) or column + len(whole) <= width:
        return whole
    hang = column + 1 if indent is None or column + 1 <= width // 2 else indent
    lines: list[str] = []
    current = "["
    for index, item in enumerate(items):
        piece = item + ("]" if index == len(items) - 1 else ",")
        start = column if not lines else hang
        if current not in ("[", "") and start + len(current) + 1 + len(piece) > width:
            lines.append(current)
            current = ""
        current += ("" if current in ("[", "") else " ") + piece
    lines.append(current)
    return ("\n" + " " * hang).join(lines)


def fit_lines(edited: str, original: str, width: int, breakable: str) -> str:
    """``edited`` with each line the edit made longer than ``width`` broken after commas, as
    a person wraps a flow collection: after the commas of the outermost collection that
    ``breakable`` allows on that line (YAML: lists and mappings; TOML: arrays, as an inline
    table must stay on one line), each continuation aligned after that collection's bracket
    (or at the line's own indentation, on a line that continues one; four columns in from it
    when the bracket stands past the middle of the line). Lines the spec already had are left
    as they are."""
    had = set(original.splitlines())
    lines = []
    for line in edited.split("\n"):
        if len(line) > width and line not in had:
            lines.extend(_broken(line, width, breakable))
        else:
            lines.append(line)
    return "\n".join(lines)


def _broken(line: str, width: int, breakable: str) -> list[str]:
    indent = len(line) - len(line.lstrip(" "))
    # each comma outside quotes and comments: its offset, its depth, where its line goes on
    commas: list[tuple[int, int, int]] = []
    stack: list[tuple[str, int]] = []  # open brackets on this line: (bracket, column after it)
    depth, quote = 0, ""
    for i, char in enumerate(line):
        if quote:
            quote = "" if char == quote and line[i - 1] != "\\" else quote
        elif char in "'\"":
            quote = char
        elif char == "#" and (i == 0 or line[i - 1] in " \t"):
            break
        elif char in "[{":
            depth += 1
            stack.append((char, i + 1))
        elif char in "]}":
            depth -= 1
            if stack:
                stack.pop()
        elif char == ",":
            bracket, hang = stack[-1] if stack else ("", indent)
            if hang > width // 2:  # a bracket far right: little would fit after it
                hang = indent + 4
            if bracket in breakable or not stack:
                commas.append((i, depth, hang))
    if not commas:
        return [line]
    level = min(d for _, d, _ in commas)
    cuts = [(i, hang) for i, d, hang in commas if d == level]
    pieces, hangs, start = [], [], 0
    for i, hang in cuts:
        pieces.append(line[start : i + 1])
        hangs.append(hang)
        start = i + 1
    pieces.append(line[start:])
    out = [pieces[0]]
    for piece, hang in zip(pieces[1:], hangs, strict=True):
        piece = piece.strip(" ")
        if not piece:  # after the line's last comma (the collection goes on below)
            continue
        if len(out[-1]) + 1 + len(piece) <= width:
            out[-1] += " " + piece
        else:
            out.append(" " * hang + piece)
    return out
