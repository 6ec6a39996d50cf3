"""What ``robospec tune --write`` changes, shared by the YAML and TOML editors: which
controller each new gain is written at (:func:`plan`), and how the numbers are written."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from robospec.physics.findings import significant
from robospec.tune.results import ControllerTuning

FIELDS = ("stiffness", "damping", "force_limit")
WIDTH = 100  # a flow list longer than this is wrapped


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


def flow_list(values: Sequence[float], column: int, indent: int | None = None) -> str:
    """``[a, b, ...]`` starting at ``column`` (0-based): on one line when it fits on a line
    of its own; else wrapped before :data:`WIDTH`, the continuation lines aligned after the
    bracket, or at ``indent`` when the bracket stands so far right that little would fit."""
    items = [number_text(v) for v in values]
    whole = "[" + ", ".join(items) + "]"
    # a list that can be read whole on one line stays whole, even where it starts far right:
    # broken after its first items (`damping: [150,` / `100, ...]`) it reads as two values
    if len(whole) <= WIDTH - (indent if indent is not None else 0) or column + len(whole) <= WIDTH:
        return whole
    hang = column + 1 if indent is None or column + 1 <= WIDTH // 2 else indent
    lines: list[str] = []
    current = "["
    for index, item in enumerate(items):
        piece = item + ("]" if index == len(items) - 1 else ",")
        start = column if not lines else hang
        if current not in ("[", "") and start + len(current) + 1 + len(piece) > WIDTH:
            lines.append(current)
            current = ""
        current += ("" if current in ("[", "") else " ") + piece
    lines.append(current)
    return ("\n" + " " * hang).join(lines)
