"""Hover: a joint's type, limits, axis, parent and child and mimic; a link's parent chain and
mass; a group's joints; a controller's fields through ``extends``; a diagnostic code's title and
the message it carries here."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from robospec.diagnostics import Diagnostic
from robospec.diagnostics.codes import CODES
from robospec.lsp.documents import Analysis
from robospec.lsp.positions import CODE, Cursor
from robospec.lsp.robot import (
    controller_fields,
    element_facts,
    group_joints,
    joint_detail,
    parent_chain,
)
from robospec.lsp.schema_paths import allowed_at


def hover_text(
    analysis: Analysis,
    cursor: Cursor | None,
    line_text: str,
    character: int,
    diagnostics: list[Diagnostic],
    code_href: Callable[[str], str | None],
) -> str | None:
    """Markdown for the hover at the cursor, or None."""
    code = _code_under(line_text, character)
    if code is not None:
        return code_text(code, [d for d in diagnostics if d.code == code], code_href)
    if cursor is None:
        return _diagnostics_text(diagnostics, code_href)
    name = cursor.word
    kinds = _kinds(cursor)
    data = analysis.data if analysis.data is not None else cursor.data
    description = analysis.description
    if description is not None and (kinds & {"joint", "joint-selection"} or not kinds):
        joint = description.joint(name)
        if joint is not None:
            return _joint(analysis, name)
    if "joint-selection" in kinds or (cursor.path[:1] == ("groups",) and len(cursor.path) == 2):
        if isinstance(data, dict) and name in (data.get("groups") or {}):
            joints = group_joints(name, description, data)
            listed = "\n".join(f"- `{j}`" for j in joints) or "(no joints)"
            return f"**{name}**: group of {len(joints)} joints\n\n{listed}"
    if description is not None and description.link(name) is not None:
        return _link(analysis, name)
    if "controller" in kinds or (cursor.path[:1] == ("controllers",) and len(cursor.path) == 2):
        if isinstance(data, dict) and name in (data.get("controllers") or {}):
            return _controller(name, data)
    if cursor.path[-1:] == ("extends",) and isinstance(data, dict):
        if name in (data.get("controllers") or {}):
            return _controller(name, data)
    return _diagnostics_text(diagnostics, code_href)


def _kinds(cursor: Cursor) -> set[str]:
    if cursor.role == "key":
        return allowed_at(cursor.path[:-1], cursor.data).key_kinds
    return allowed_at(cursor.path, cursor.data).value_kinds


def _code_under(line_text: str, character: int) -> str | None:
    for found in CODE.finditer(line_text):
        if found.start() <= character <= found.end():
            return found.group(0)
    return None


def code_text(code: str, here: list[Diagnostic], code_href: Callable[[str], str | None]) -> str:
    known = CODES.get(code)
    title = known.title if known else "unknown code"
    lines = [f"**{code}**: {title}"]
    for diagnostic in here:
        lines.append(f"\n{diagnostic.severity.value}: {diagnostic.message}")
        if diagnostic.hint:
            lines.append(f"\nhint: {diagnostic.hint}")
    href = code_href(code)
    if href:
        lines.append(f"\n[{code} in the docs]({href})")
    return "\n".join(lines)


def _diagnostics_text(
    diagnostics: list[Diagnostic], code_href: Callable[[str], str | None]
) -> str | None:
    if not diagnostics:
        return None
    return "\n\n---\n\n".join(code_text(d.code, [d], code_href) for d in diagnostics)


def _joint(analysis: Analysis, name: str) -> str:
    description = analysis.description
    assert description is not None
    joint = description.joint(name)
    assert joint is not None
    facts = element_facts(description, analysis.expanded)
    lines = [f"**{name}**: {joint_detail(joint)}", ""]
    if joint.lower is not None or joint.upper is not None:
        lines.append(f"- limits: [{joint.lower}, {joint.upper}]")
    else:
        lines.append("- limits: none")
    if joint.velocity is not None or joint.effort is not None:
        lines.append(f"- velocity limit: {joint.velocity}, effort limit: {joint.effort}")
    if name in facts.axes:
        lines.append(f"- axis: {facts.axes[name]}")
    lines.append(f"- {joint.parent} -> {joint.child}")
    if joint.mimic is not None:
        m = joint.mimic
        lines.append(f"- mimics {m.joint} (multiplier {m.multiplier:g}, offset {m.offset:g})")
    if not joint.is_active:
        lines.append("- not active: it adds no entry to qpos")
    lines.append(f"\n{_file_line(analysis, joint.line)}")
    return "\n".join(lines)


def _link(analysis: Analysis, name: str) -> str:
    description = analysis.description
    assert description is not None
    link = description.link(name)
    assert link is not None
    facts = element_facts(description, analysis.expanded)
    chain = parent_chain(description, name)
    lines = [f"**{name}**: link", ""]
    if chain:
        path = " <- ".join([name, *(f"{joint} <- {parent}" for joint, parent in chain)])
        lines.append(f"- parent chain: {path}")
    else:
        lines.append("- the root link")
    lines.append(f"- mass: {facts.masses.get(name, 'not given (SAPIEN computes it)')}")
    lines.append(f"\n{_file_line(analysis, link.line)}")
    return "\n".join(lines)


def _controller(name: str, data: Any) -> str:
    fields = controller_fields(name, data)
    lines = [f"**{name}**: controller", ""]
    for key, value, owner in fields:
        origin = "" if owner == name else f" (from {owner})"
        lines.append(f"- {key}: {_show(value)}{origin}")
    return "\n".join(lines)


def _show(value: Any) -> str:
    text = getattr(value, "text", None)
    if isinstance(text, str):
        return text
    if value is None:
        return "null"
    if isinstance(value, bool):
        return str(value).lower()
    return str(value)


def _file_line(analysis: Analysis, line: int) -> str:
    file = analysis.description_file
    shown = file.name if file is not None else "description"
    where = " (expanded)" if analysis.expanded else ""
    return f"{shown}{where}:{line}"
