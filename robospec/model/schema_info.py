"""Which keys a spec model accepts at a given place, for did-you-mean hints on unknown keys.

Read from the pydantic-core schema that validated (``robospec.model.frozen.SCHEMAS``) by
following pydantic's error location through it, so a hint loads no pydantic and names the
keys of the very schema that rejected one.
"""

from __future__ import annotations

from typing import Any

# schemas that wrap one other schema: the place is the same
_WRAPPERS = frozenset(
    {"definitions", "default", "nullable", "function-before", "function-after", "model"}
)


def fields_for(root: Any, loc: tuple[Any, ...]) -> list[str]:
    """The field names of the models an error location ``loc`` (of a validation with the
    schema ``root``) can point into."""
    definitions = {d["ref"]: d for d in root.get("definitions", [])}
    places = _members(root, definitions)
    for element in loc:
        following = [n for place in places for n in _step(place, element, definitions)]
        # an element that names no field, key or item is a union member's label
        # (`AllBut`, `list[str]`): the place stays, its other members fall away later
        places = following or places
    names: list[str] = []
    for place in places:
        if place["type"] == "model-fields":
            names.extend(n for n in place["fields"] if n not in names)
    return names


def _members(schema: Any, definitions: dict[str, Any]) -> list[dict[str, Any]]:
    """The schemas a value at this place is checked against, wrappers and unions unwrapped."""
    kind = schema["type"]
    if kind == "definition-ref":
        return _members(definitions[schema["schema_ref"]], definitions)
    if kind in _WRAPPERS:
        return _members(schema["schema"], definitions)
    if kind == "union":
        out: list[dict[str, Any]] = []
        for choice in schema["choices"]:
            out.extend(_members(choice[0] if isinstance(choice, tuple) else choice, definitions))
        return out
    return [schema]


def _step(place: dict[str, Any], element: Any, definitions: dict[str, Any]) -> list[Any]:
    kind = place["type"]
    if kind == "model-fields" and element in place["fields"]:
        inner = place["fields"][element]["schema"]
    elif kind == "dict" and isinstance(element, str):
        inner = place.get("values_schema")
    elif kind == "list" and isinstance(element, int):
        inner = place.get("items_schema")
    elif kind == "tagged-union" and element in place["choices"]:
        inner = place["choices"][element]
    else:
        return []
    return _members(inner, definitions) if inner is not None else []
