"""TOML edits for ``robospec tune --write``, through tomlkit: its documents keep every comment,
key order, quoting and inline table they do not change. A list of gains is changed item by
item, so its layout stays too."""

from __future__ import annotations

from collections.abc import Mapping, MutableMapping, Sequence
from typing import Any

from robospec.tune.edits import Edit, WriteError, fit_lines, line_width, number, plan, uniform
from robospec.tune.results import ControllerTuning


def edit_toml(
    source: str,
    tunings: Sequence[ControllerTuning],
    uid: str | None,
    current: Mapping[str, Mapping[str, Any]] | None = None,
) -> str:
    import tomlkit
    from tomlkit.exceptions import TOMLKitError

    try:
        document = tomlkit.parse(source)
    except TOMLKitError as exc:
        raise WriteError(f"tomlkit cannot read it ({exc})") from exc
    if uid is not None:
        if "uid" not in document:
            raise WriteError("the spec has no uid to change")
        document["uid"] = uid
    controllers = document.get("controllers")
    if not isinstance(controllers, Mapping):
        raise WriteError("the spec has no controllers table")
    for edit in plan(controllers, tunings, current):
        _set(controllers[edit.owner], edit)
    # (a list tomlkit writes is one line: broken after its commas where it passes the width)
    return fit_lines(tomlkit.dumps(document), source, line_width(source), "[")


def _set(entry: Any, edit: Edit) -> None:
    import tomlkit

    values = [number(v) for v in edit.values]
    node = entry.get(edit.field)
    if uniform(edit.values) and not isinstance(node, (list, Mapping)):
        entry[edit.field] = values[0]
    elif isinstance(node, list) and len(node) == len(values):
        for index, value in enumerate(values):
            if node[index] != value:
                node[index] = value
    elif isinstance(node, MutableMapping) and set(node) == set(edit.joints):
        for joint, value in zip(edit.joints, values, strict=True):
            if node[joint] != value:
                node[joint] = value
    else:
        array = tomlkit.array()
        array.extend(values)
        entry[edit.field] = array
