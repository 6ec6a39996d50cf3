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
from collections.abc import Sequence
from typing import Any

from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import TUNED_GAINS_UNWRITABLE
from robospec.pipeline import CompiledSpec, compile_spec
from robospec.tune.edits import FIELDS, WriteError, number
from robospec.tune.results import ControllerTuning


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
        TUNED_GAINS_UNWRITABLE,
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
