"""Joint groups for an imported spec: named after ManiSkill's mode-dict keys, written as a glob
when one matches exactly the group's joints, and keyframes split by group when groups
partition the robot's joints."""

from __future__ import annotations

import fnmatch
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from robospec.importer.records import ALL_JOINTS, ModeRecord

FALLBACK_GROUP = "joints"


@dataclass
class GroupPlan:
    """Group name → joints, and for each joint tuple the selection a controller writes."""

    groups: dict[str, tuple[str, ...]] = field(default_factory=dict)
    selections: dict[tuple[str, ...], str | list[str]] = field(default_factory=dict)
    values: dict[str, Any] = field(default_factory=dict)  # group name → spec value

    def selection(self, joints: tuple[str, ...]) -> str | list[str]:
        return self.selections[joints]


def plan_groups(modes: Sequence[ModeRecord], all_joints: tuple[str, ...] | None) -> GroupPlan:
    plan = GroupPlan()
    users: dict[tuple[str, ...], set[str]] = {}
    for mode in modes:
        for _, controller in mode.entries:
            users.setdefault(controller.joints, set()).add(controller.key)
    for mode in modes:
        for key, controller in mode.entries:
            joints = controller.joints
            if joints in plan.selections:
                continue
            if key is None and (joints == (ALL_JOINTS,) or joints == all_joints):
                plan.selections[joints] = ALL_JOINTS
                continue
            base = _safe_name(key) if key is not None else FALLBACK_GROUP
            name, number = base, 1
            while name in plan.groups:
                number += 1
                name = f"{base}_{number}"
            if number > 1 and len(users.get(joints, ())) < 2:
                # the key names another selection already: one controller writes its own list
                plan.selections[joints] = selection_for(joints, all_joints)
                continue
            plan.groups[name] = joints
            plan.values[name] = selection_for(joints, all_joints)
            plan.selections[joints] = name
    if all_joints is not None:  # "every joint but another group's": later groups first
        for name, joints in reversed(plan.groups.items()):
            for other, others in plan.groups.items():
                if other == name or not isinstance(plan.values[other], (str, list)):
                    continue
                rest = tuple(j for j in all_joints if j not in others)
                if isinstance(plan.values[name], list) and rest == joints:
                    plan.values[name] = {"all_but": other}
    return plan


def _safe_name(key: str) -> str:
    name = re.sub(r"[^A-Za-z0-9_.\-]", "_", key)[:64] or FALLBACK_GROUP
    return name if re.match(r"[A-Za-z0-9_]", name) else "_" + name[:63]


def selection_for(joints: tuple[str, ...], all_joints: tuple[str, ...] | None) -> str | list[str]:
    """``"*"`` for every joint, a glob that selects exactly ``joints`` in order, or a list."""
    if joints == (ALL_JOINTS,) or (all_joints is not None and joints == all_joints):
        return ALL_JOINTS
    if all_joints is not None and len(joints) >= 2:
        for pattern in glob_candidates(joints):
            if tuple(j for j in all_joints if fnmatch.fnmatchcase(j, pattern)) == joints:
                return pattern
    return list(joints)


def glob_candidates(joints: tuple[str, ...]) -> list[str]:
    if any(re.search(r"[*?\[\]]", j) for j in joints):
        return []
    prefix = common_prefix(list(joints))
    rests = [j[len(prefix) :] for j in joints]
    suffix = common_prefix([r[::-1] for r in rests])[::-1]
    candidates: list[str] = []
    middles = [r[: len(r) - len(suffix)] for r in rests]
    if all(len(m) == 1 and m.isalnum() for m in middles) and len(set(middles)) == len(middles):
        candidates.append(prefix + "[" + _char_class(middles) + "]" + suffix)
    if prefix or suffix:
        candidates.append(prefix + "*" + suffix)
    if prefix:
        candidates.append(prefix + "*")
    if suffix:
        candidates.append("*" + suffix)
    return list(dict.fromkeys(candidates))  # most specific first


def common_prefix(texts: list[str]) -> str:
    first = min(texts, default="")
    for index, char in enumerate(first):
        if any(text[index] != char for text in texts):
            return first[:index]
    return first


def _char_class(chars: list[str]) -> str:
    ordered = sorted(chars)
    codes = [ord(c) for c in ordered]
    if len(ordered) >= 3 and codes == list(range(codes[0], codes[0] + len(codes))):
        return f"{ordered[0]}-{ordered[-1]}"
    return "".join(ordered)


def split_by_group(
    values: Sequence[Any],
    all_joints: tuple[str, ...],
    partition: Sequence[tuple[str, tuple[str, ...]]],
) -> dict[str, Any] | None:
    """Keyframe values in qpos order → ``{group: value(s)}`` in the groups' own joint order;
    a group whose joints share one value gets that one number."""
    if len(values) != len(all_joints):
        return None
    by_joint = dict(zip(all_joints, values, strict=True))
    out: dict[str, Any] = {}
    for name, joints in partition:
        items = [by_joint[j] for j in joints]
        if len(items) > 1 and all(_identical(i, items[0]) for i in items):
            out[name] = items[0]
        else:
            out[name] = items[0] if len(items) == 1 else items
    return out


def _identical(a: Any, b: Any) -> bool:
    return type(a) is type(b) and a == b


def partition_of(
    modes: Sequence[ModeRecord], plan: GroupPlan, all_joints: tuple[str, ...] | None
) -> list[tuple[str, tuple[str, ...]]] | None:
    """The groups of the first mode whose groups cover every active joint exactly once."""
    if all_joints is None:
        return None
    for mode in modes:
        names = [plan.selections.get(c.joints) for _, c in mode.entries]
        if len(names) < 2 or any(n is None or n not in plan.groups for n in names):
            continue
        parts = [(str(n), plan.groups[str(n)]) for n in names]
        joined = [j for _, joints in parts for j in joints]
        if len(joined) == len(set(joined)) and set(joined) == set(all_joints):
            return parts
    return None
