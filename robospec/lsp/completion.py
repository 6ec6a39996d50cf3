"""Completion: the robot's own names where the spec names something (joints, groups, links,
controllers, materials, ...) and the schema's keys and enum values everywhere else."""

from __future__ import annotations

from lsprotocol import types

from robospec.lsp.documents import Analysis
from robospec.lsp.positions import MARKER, Cursor, value_at
from robospec.lsp.robot import names, part_names
from robospec.lsp.schema_paths import allowed_at

_KIND_ITEM = {
    "joint": types.CompletionItemKind.Field,
    "joint-selection": types.CompletionItemKind.Field,
    "link": types.CompletionItemKind.Class,
    "link-pattern": types.CompletionItemKind.Class,
    "link-or-named": types.CompletionItemKind.Class,
    "mount-link": types.CompletionItemKind.Class,
}


def complete(analysis: Analysis, cursor: Cursor) -> list[types.CompletionItem]:
    if cursor.role == "key":
        return _keys(analysis, cursor)
    allowed = allowed_at(cursor.path, cursor.data)
    items: dict[str, types.CompletionItem] = {}
    for kind in sorted(allowed.value_kinds):
        for name, detail in names(kind, analysis.description, cursor.data).items():
            items.setdefault(name, _item(name, detail, _KIND_ITEM.get(kind), cursor))
        for name, detail in part_names(kind, analysis.compiled.part_origins).items():
            items.setdefault(name, _item(name, detail, _KIND_ITEM.get(kind), cursor))
    for value, text in allowed.values.items():
        items.setdefault(value, _item(value, text, types.CompletionItemKind.EnumMember, cursor))
    return list(items.values())


def _keys(analysis: Analysis, cursor: Cursor) -> list[types.CompletionItem]:
    parent = cursor.path[:-1]
    allowed = allowed_at(parent, cursor.data)
    present = value_at(cursor.data, parent)
    taken = (
        {str(k) for k in present if MARKER not in str(k)} if isinstance(present, dict) else set()
    )
    items: dict[str, types.CompletionItem] = {}
    for kind in sorted(allowed.key_kinds):
        for name, detail in names(kind, analysis.description, cursor.data).items():
            if name not in taken:
                items.setdefault(name, _item(name, detail, _KIND_ITEM.get(kind), cursor))
    for key, text in allowed.keys.items():
        if key not in taken:
            items.setdefault(key, _item(key, text, types.CompletionItemKind.Property, cursor))
    return list(items.values())


def _item(
    label: str, detail: str, kind: types.CompletionItemKind | None, cursor: Cursor
) -> types.CompletionItem:
    # the edit replaces the whole word under the cursor, so completing inside a name works
    edit = types.TextEdit(
        range=types.Range(
            start=types.Position(line=cursor.line, character=cursor.start),
            end=types.Position(line=cursor.line, character=cursor.end),
        ),
        new_text=label,
    )
    short = detail.split("\n", 1)[0]
    return types.CompletionItem(
        label=label,
        kind=kind,
        detail=short[:120] or None,
        documentation=detail if detail and detail != short else None,
        text_edit=edit,
    )
