"""What the spec's JSON Schema allows at a key path: the keys an object may have, the values a
place takes (enums, booleans) and which robot names it takes (the ``x-robospec-ref`` markers
of :mod:`robospec.model.refs`).

The schema is walked with the document's own data at hand, so a controller offers the fields of
its ``type`` only (the schema dispatches with ``if``/``then`` on it) and an ``anyOf`` keeps the
alternatives the data can still be.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cache
from typing import Any

from robospec.load.source_map import KeyPath
from robospec.lsp.positions import value_at
from robospec.model.refs import REF_KEY

Schema = dict[str, Any]
_MISSING = object()


@cache
def spec_schema() -> Schema:
    """The generic schema (built from the models once: it takes a third of a second)."""
    from robospec.schema import spec_schema as build

    return build()


@dataclass
class Allowed:
    """What a place in the spec accepts."""

    keys: dict[str, str] = field(default_factory=dict)  # key -> its description
    key_kinds: set[str] = field(default_factory=set)  # robot names allowed as keys
    values: dict[str, str] = field(default_factory=dict)  # enum value -> description
    value_kinds: set[str] = field(default_factory=set)  # robot names allowed as the value
    descriptions: list[str] = field(default_factory=list)  # of the place itself


def allowed_at(path: KeyPath, data: Any, schema: Schema | None = None) -> Allowed:
    """What the schema allows at ``path`` (as a value, and as an object's keys) in ``data``."""
    root = schema or spec_schema()
    nodes = _expand(root, [root], data)
    for depth, key in enumerate(path):
        here = value_at(data, path[: depth + 1], _MISSING)
        following: list[Schema] = []
        for node in nodes:
            following.extend(_child(node, key))
        nodes = _expand(root, following, None if here is _MISSING else here)
    allowed = Allowed()
    for node in nodes:
        _collect(node, allowed)
    return allowed


def _child(node: Schema, key: str | int) -> list[Schema]:
    if isinstance(key, int):
        items = node.get("items")
        prefix = node.get("prefixItems")
        if isinstance(prefix, list) and key < len(prefix):
            return [prefix[key]]
        return [items] if isinstance(items, dict) else []
    properties = node.get("properties", {})
    if key in properties:
        return [properties[key]]
    found = [
        value
        for pattern, value in node.get("patternProperties", {}).items()
        if re.search(pattern, key)
    ]
    if found:
        return found
    extra = node.get("additionalProperties")
    return [extra] if isinstance(extra, dict) else []


def _expand(root: Schema, nodes: list[Schema], data: Any) -> list[Schema]:
    """The nodes with every ``$ref``, ``allOf``, ``anyOf``/``oneOf`` and ``if``/``then``/``else``
    opened, keeping the alternatives ``data`` (None: unknown) may be."""
    out: list[Schema] = []
    seen: set[int] = set()
    pending = list(nodes)
    while pending:
        node = pending.pop(0)
        if not isinstance(node, dict) or id(node) in seen:
            continue
        seen.add(id(node))
        if not _fits(node, data):
            continue
        out.append(node)
        ref = node.get("$ref")
        if isinstance(ref, str) and ref.startswith("#/$defs/"):
            pending.append(root["$defs"].get(ref[len("#/$defs/") :], {}))
        pending.extend(node.get("allOf", []))
        pending.extend(node.get("anyOf", []))
        pending.extend(node.get("oneOf", []))
        if "if" in node:
            condition = _satisfies(node["if"], data)
            if condition is not False and "then" in node:
                pending.append(node["then"])
            if condition is not True and "else" in node:
                pending.append(node["else"])
    return out


_TYPES: dict[str, tuple[type, ...]] = {
    "object": (dict,),
    "array": (list,),
    "string": (str,),
    "number": (int, float),
    "integer": (int,),
    "boolean": (bool,),
}


def _fits(node: Schema, data: Any) -> bool:
    """Whether ``data`` can be of ``node``'s type; a string (the word being typed) fits any
    scalar, and unknown data fits everything."""
    kind = node.get("type")
    if data is None or not isinstance(kind, str) or kind not in _TYPES:
        return True
    if isinstance(data, str):
        return kind not in ("object", "array")
    return isinstance(data, _TYPES[kind])


def _satisfies(condition: Schema, data: Any) -> bool | None:
    """Whether ``data`` meets an ``if`` (required keys and constant properties); None when
    the data is unknown."""
    if data is None:
        return None
    if not isinstance(data, dict):
        return condition.get("type") not in ("object",) and not condition.get("required")
    if any(key not in data for key in condition.get("required", [])):
        return False
    for key, rule in condition.get("properties", {}).items():
        if key not in data or not isinstance(rule, dict):
            continue
        if "const" in rule and data[key] != rule["const"]:
            return False
        if "enum" in rule and data[key] not in rule["enum"]:
            return False
    return True


def _collect(node: Schema, allowed: Allowed) -> None:
    description = node.get("description")
    if isinstance(description, str) and description not in allowed.descriptions:
        allowed.descriptions.append(description)
    for key, value in node.get("properties", {}).items():
        text = value.get("description", "") if isinstance(value, dict) else ""
        allowed.keys.setdefault(key, text)
    names = node.get("propertyNames")
    if isinstance(names, dict) and REF_KEY in names:
        allowed.key_kinds.add(names[REF_KEY])
    if REF_KEY in node:
        allowed.value_kinds.add(node[REF_KEY])
    for value in node.get("enum", []):
        if isinstance(value, str):
            allowed.values.setdefault(value, node.get("description", ""))
    if isinstance(node.get("const"), str):
        allowed.values.setdefault(node["const"], node.get("description", ""))
    if node.get("type") == "boolean":
        allowed.values.setdefault("true", "")
        allowed.values.setdefault("false", "")
