"""``robospec tune --write``: the new gains into the spec, as a person would edit it.

Only gain values change: comments, key order, flow style, quoting and ``extends`` stay. A gain
a controller inherits (``extends``) changes at the controller that writes it when every
controller inheriting it was tuned to the same values; otherwise it is written at the tuned
controller (a new key, after its others). Values are one number when every joint got the same,
else one per joint: in place where the spec already lists one per joint (a list, or a mapping
by joint name), else as a flow list.

YAML: ruamel's round-trip load gives every node's position, and the edits are made in the
text at those positions (ruamel's dump would reflow flow collections that span lines). TOML:
tomlkit, whose documents keep everything they do not change. The result is compiled again
before it is written, and must give every tuned controller exactly its new gains; it is
written atomically (a reader sees the old spec or the new, never a part).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from robospec.diagnostics import Diagnostic, error
from robospec.pipeline import CompiledSpec, compile_spec
from robospec.tune.results import ControllerTuning
from robospec.tune.search import significant

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


def write_gains(
    item: CompiledSpec, tunings: Sequence[ControllerTuning], uid: str | None = None
) -> tuple[bool, list[Diagnostic]]:
    """Write the changed controllers' gains (and ``uid``) into ``item``'s spec file; whether
    it was written, and RS622 when it could not be."""
    from robospec.diagnostics import Location

    path = item.path
    where = Location(item.display)
    if not any(t.changed for t in tunings) and uid is None:
        return False, []
    try:
        text = path.read_text(encoding="utf-8")
        assert item.robot is not None
        current = {c.name: dict(c.kwargs) for c in item.robot.controllers}
        if path.suffix.lower() == ".toml":
            from robospec.tune.toml_write import edit_toml

            new_text = edit_toml(text, tunings, uid, current)
        else:
            from robospec.tune.yaml_write import edit_yaml

            new_text = edit_yaml(text, tunings, uid, current)
        _verify(item, new_text, tunings, uid)
    except WriteError as exc:
        return False, [_cannot(where, str(exc))]
    except OSError as exc:
        return False, [_cannot(where, f"{exc.strerror or exc}")]
    if new_text == text:
        return False, []
    try:
        from robospec.files import write_atomically

        mode = path.stat().st_mode
        write_atomically(path, new_text)
        os.chmod(path, mode & 0o7777)
    except OSError as exc:
        return False, [_cannot(where, f"{exc.strerror or exc}")]
    return True, []


def _cannot(where: Any, why: str) -> Diagnostic:
    return error(
        where,
        "RS622",
        f"robospec tune cannot write the new gains into this spec: {why}",
        "nothing was written; the table above gives the gains to write by hand",
    )


def _verify(
    item: CompiledSpec, text: str, tunings: Sequence[ControllerTuning], uid: str | None
) -> None:
    """The edited spec compiles and gives each changed controller exactly its new gains."""
    compiled = compile_spec(item.path, item.display, text=text.encode("utf-8"))
    if not compiled.ok or compiled.robot is None:
        problems = "; ".join(d.format_text() for d in compiled.diagnostics if d.is_error)
        raise WriteError(f"the edited spec does not compile ({problems})")
    if uid is not None and compiled.robot.uid != uid:
        raise WriteError(f"the edited spec's uid is {compiled.robot.uid!r}, not {uid!r}")
    resolved = {c.name: dict(c.kwargs) for c in compiled.robot.controllers}
    for tuning in tunings:
        if not tuning.changed or tuning.after is None:
            continue
        kwargs = resolved.get(tuning.controller, {})
        for field in FIELDS:
            want = [number(v) for v in getattr(tuning.after, field)]
            got = kwargs.get(field)
            if got is None and field == "force_limit" and all(v >= 1e9 for v in want):
                continue
            if not _same(got, want):
                raise WriteError(
                    f"controller '{tuning.controller}' would get {field} {got!r}, "
                    f"not the tuned {want!r}"
                )


def _same(got: object, want: list[int | float]) -> bool:
    if isinstance(got, (int, float)):
        return all(abs(float(got) - w) <= 1e-9 * max(1.0, abs(w)) for w in want)
    if isinstance(got, (list, tuple)) and len(got) == len(want):
        return all(
            abs(float(g) - w) <= 1e-9 * max(1.0, abs(w)) for g, w in zip(got, want, strict=True)
        )
    return False


def uniform(values: Sequence[float]) -> bool:
    return len({number(v) for v in values}) == 1


def flow_list(values: Sequence[float], column: int, indent: int | None = None) -> str:
    """``[a, b, ...]`` starting at ``column`` (0-based), wrapped before :data:`WIDTH`: the
    continuation lines aligned after the bracket, or at ``indent`` when the bracket stands
    so far right that little would fit there."""
    items = [number_text(v) for v in values]
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
