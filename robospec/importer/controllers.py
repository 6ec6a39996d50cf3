"""Controllers for an imported spec: each distinct ManiSkill config once, with a readable name,
only its non-default fields, and ``extends:`` where it differs from an earlier one in a few
fields; control modes refer to them by name."""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from robospec.importer.groups import GroupPlan
from robospec.importer.records import ControllerRecord, ModeRecord

MAX_OVERRIDES = 4


def written_fields(
    record: ControllerRecord,
    joints: Any,
    path_text: Callable[[str], str | None],
    *,
    with_defaults: bool = False,
) -> dict[str, Any]:
    """The spec mapping for one config: ``type``, ``joints``, then every field that is
    required or differs from ManiSkill's default. ``path_text`` turns a file path into how the
    spec names it (None: the robot's own description, which IK controllers use by default)."""
    data: dict[str, Any] = {"type": record.type, "joints": joints}
    for name, value in record.fields:
        if name in record.defaults and not with_defaults:
            continue
        if name == "urdf_path" and isinstance(value, str):
            text = path_text(value)
            if text is None:
                continue
            value = text
        elif name == "mimic" and isinstance(value, dict):
            value = {
                follower: target["joint"]
                if isinstance(target, dict) and set(target) == {"joint"}
                else target
                for follower, target in value.items()
            }
        data[name] = listify(value)
    return data


def listify(value: Any) -> Any:
    if isinstance(value, tuple):
        return [listify(v) for v in value]
    if isinstance(value, dict):
        return {k: listify(v) for k, v in value.items()}
    return value


def same_value(a: Any, b: Any) -> bool:
    """Equal as a spec reads them: numbers by value (1000 is 1e3), booleans only as booleans."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return float(a) == float(b)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same_value(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict) and isinstance(b, dict):
        return list(a) == list(b) and all(same_value(a[k], b[k]) for k in a)
    return type(a) is type(b) and a == b


def suffix_for(record: ControllerRecord) -> str:
    """The kind's short name (``ee_delta_pose``, ``target_delta_pos``, ``vel``, ...)."""
    delta = "delta_" if record.get("use_delta") else ""
    target = "target_" if record.get("use_target") else ""
    return record.kind.short_name.format(how=target + delta)


@dataclass
class ControllerPlan:
    controllers: dict[str, dict[str, Any]] = field(default_factory=dict)  # name → spec data
    names: dict[str, str] = field(default_factory=dict)  # record key → name
    modes: dict[str, Any] = field(default_factory=dict)  # mode name → spec data
    records: dict[str, ControllerRecord] = field(default_factory=dict)  # name → record


def plan_controllers(
    modes: Sequence[ModeRecord], groups: GroupPlan, path_text: Callable[[str], str | None]
) -> ControllerPlan:
    plan = ControllerPlan()
    ordered: list[tuple[str | None, ControllerRecord, str]] = []
    seen: set[str] = set()
    per_group: dict[str, set[str]] = {}
    for mode in modes:
        for key, record in mode.entries:
            selection = groups.selection(record.joints)
            if isinstance(selection, str) and selection in groups.groups:
                label: str | None = selection
            else:
                label = key  # named after the mode-dict key even without a group
            per_group.setdefault(str(label), set()).add(record.key)
            if record.key not in seen:
                seen.add(record.key)
                ordered.append((label, record, mode.name))
    full: dict[str, dict[str, Any]] = {}
    for label, record, mode_name in ordered:
        name = _name_for(label, record, mode_name, per_group, plan.controllers)
        plan.names[record.key] = name
        plan.records[name] = record
        own = written_fields(record, groups.selection(record.joints), path_text)
        every = written_fields(
            record, groups.selection(record.joints), path_text, with_defaults=True
        )
        plan.controllers[name] = _with_extends(name, own, every, full)
        full[name] = own
    for mode in modes:
        if mode.single:
            plan.modes[mode.name] = plan.names[mode.entries[0][1].key]
            continue
        entry: dict[str, Any] = {str(key): plan.names[r.key] for key, r in mode.entries}
        if mode.balance_passive_force is not None:
            entry["balance_passive_force"] = mode.balance_passive_force
        plan.modes[mode.name] = entry
    return plan


def _name_for(
    label: str | None,
    record: ControllerRecord,
    mode_name: str,
    per_group: dict[str, set[str]],
    taken: dict[str, Any],
) -> str:
    suffix = suffix_for(record)
    if label is not None and len(per_group.get(label, ())) == 1:
        candidates = [label, f"{label}_{suffix}"]
    elif label is not None:
        candidates = [f"{label}_{suffix}"]
    else:
        candidates = [suffix]
    if len(record.joints) == 1 and re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*", record.joints[0]):
        candidates.append(f"{record.joints[0]}_{suffix}")  # one joint: named after it
    short = mode_name.removeprefix("pd_")
    candidates.append(f"{label}_{short}" if label is not None else short)
    for candidate in candidates:
        candidate = candidate[:64]
        if candidate not in taken:
            return candidate
    base, number = candidates[0][:60], 2
    while f"{base}_{number}" in taken:
        number += 1
    return f"{base}_{number}"


def _with_extends(
    name: str, own: dict[str, Any], every: dict[str, Any], earlier: dict[str, dict[str, Any]]
) -> dict[str, Any]:
    """``own`` as written, or as ``extends: <earlier>`` plus the fields that differ, when that
    is at most MAX_OVERRIDES fields and about half as long. ``every`` is ``own`` with the
    default-valued fields too."""
    best: tuple[int, str, dict[str, Any]] | None = None
    for base_name, base in earlier.items():
        if base["type"] != own["type"] or base["joints"] != own["joints"]:
            continue
        if "urdf_path" in base and "urdf_path" not in own:
            continue  # a spec cannot write "the robot's own URDF" as a value
        overrides: dict[str, Any] = {}
        for key, value in own.items():
            if key not in base or not same_value(base[key], value):
                overrides[key] = value
        for key in base:
            if key not in own:  # own has ManiSkill's default there
                overrides[key] = every[key]
        if best is None or len(overrides) < best[0]:
            best = (len(overrides), base_name, overrides)
    if best is None:
        return own
    count, base_name, overrides = best
    if count > MAX_OVERRIDES or 2 * (count + 1) > len(own) + 2:
        return own
    return {"extends": base_name, **overrides}
