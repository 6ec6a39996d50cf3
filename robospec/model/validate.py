"""Validate loaded data into a :class:`Spec`; pydantic errors become located diagnostics.

Controllers may ``extends`` another controller: that is resolved here, on the data, before
validation, and each merged field remembers the controller it came from so an error in an
inherited field points at the line where it was written.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

from pydantic_core import ValidationError

import robospec.model.frozen as frozen
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import (
    BAD_EXPRESSION,
    CIRCULAR_INHERITANCE,
    INVALID_IDENTIFIER,
    INVALID_VALUE,
    MISSING_FIELD,
    SPEC_VERSION,
    UNKNOWN_CONTROLLER,
    UNKNOWN_KEY,
)
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath, LoadedSpec
from robospec.model.frozen import Spec
from robospec.model.schema_info import fields_for

_ERROR_CODES = {
    "expression": BAD_EXPRESSION,
    "number": INVALID_VALUE,
    "missing": MISSING_FIELD,
    "union_tag_not_found": MISSING_FIELD,
    "extra_forbidden": UNKNOWN_KEY,
    "python_keyword": INVALID_IDENTIFIER,
}


@dataclass
class SpecModelResult:
    spec: Spec | None
    diagnostics: list[Diagnostic]
    # for fields merged through ``extends``: merged path -> the path where it was written
    origins: dict[KeyPath, KeyPath] = field(default_factory=dict)
    # controller name -> the controller it extends
    bases: dict[str, str] = field(default_factory=dict)

    def first_lacking(self, path: KeyPath) -> KeyPath:
        """Where a required controller field missing at ``path`` is missing first: the root of
        its ``extends`` chain (every controller in the chain lacks it, and the children's errors
        would only repeat the base's)."""
        if len(path) != 3 or path[0] != "controllers" or not isinstance(path[1], str):
            return path
        name = path[1]
        while name in self.bases:
            name = self.bases[name]
        return ("controllers", name, path[2])

    def origin(self, path: KeyPath) -> KeyPath:
        for length in range(len(path), 0, -1):
            if path[:length] in self.origins:
                return self.origins[path[:length]] + path[length:]
        return path


def build_spec(loaded: LoadedSpec) -> SpecModelResult:
    data = dict(loaded.data)
    diagnostics: list[Diagnostic] = []
    version = data.get("robospec")
    if version is None:
        diagnostics.append(
            error(
                loaded.source.key(()),
                MISSING_FIELD,
                "missing 'robospec: 1' (the spec format version)",
                "add `robospec: 1` as the first key",
            )
        )
        return SpecModelResult(None, diagnostics)
    if version != 1 or isinstance(version, bool):
        diagnostics.append(
            error(
                loaded.source.value(("robospec",)),
                SPEC_VERSION,
                f"unsupported spec version {version!r}; this robospec reads version 1",
            )
        )
        return SpecModelResult(None, diagnostics)

    result = SpecModelResult(None, diagnostics)
    controllers = data.get("controllers")
    if isinstance(controllers, dict):
        data["controllers"] = _merge_extends(controllers, loaded, result)
    if diagnostics:
        return result
    try:
        # the frozen schema: pydantic's validation of robospec.model.spec.Spec, without pydantic
        result.spec = frozen.validator_for("Spec").validate_python(data)
    except ValidationError as exc:
        diagnostics.extend(_diagnostics_from(exc, data, loaded, result))
    return result


def _merge_extends(
    controllers: dict[str, Any], loaded: LoadedSpec, result: SpecModelResult
) -> dict[str, Any]:
    merged: dict[str, Any] = {}

    def resolve(name: str, chain: tuple[str, ...]) -> Any:
        if name in merged:
            return merged[name]
        body = controllers[name]
        if not isinstance(body, dict) or "extends" not in body:
            merged[name] = body
            return body
        base_name = body["extends"]
        extends_path: KeyPath = ("controllers", name, "extends")
        if not isinstance(base_name, str) or base_name not in controllers:
            result.diagnostics.append(
                error(
                    loaded.source.value(extends_path),
                    UNKNOWN_CONTROLLER,
                    f"'{name}' extends unknown controller {base_name!r}",
                    did_you_mean(str(base_name), [c for c in controllers if c != name]),
                )
            )
            merged[name] = {k: v for k, v in body.items() if k != "extends"}
            return merged[name]
        if base_name in chain:
            cycle = " -> ".join((*chain, name, base_name)[chain.index(base_name) :])
            result.diagnostics.append(
                error(
                    loaded.source.value(extends_path),
                    CIRCULAR_INHERITANCE,
                    f"controller inheritance is circular: {cycle}",
                )
            )
            merged[name] = {k: v for k, v in body.items() if k != "extends"}
            return merged[name]
        base = resolve(base_name, (*chain, name))
        result.bases[name] = base_name
        combined = dict(base) if isinstance(base, dict) else {}
        for key in combined:
            base_path = ("controllers", base_name, key)
            result.origins[("controllers", name, key)] = result.origin(base_path)
        for key, value in body.items():
            if key != "extends":
                combined[key] = value
                result.origins.pop(("controllers", name, key), None)
        merged[name] = combined
        return combined

    for controller_name in controllers:
        resolve(controller_name, ())
    return merged


def _diagnostics_from(
    exc: ValidationError, data: Any, loaded: LoadedSpec, result: SpecModelResult
) -> list[Diagnostic]:
    diagnostics: list[tuple[KeyPath, Diagnostic]] = []
    seen: set[KeyPath] = set()
    missing: dict[KeyPath, str] = {}  # where a required key is missing -> its name
    unknown: list[tuple[KeyPath, str]] = []  # where an unknown key is -> the key
    # our own errors (bad arithmetic, ...) say more than "should be a valid list": first
    errors = sorted(exc.errors(include_url=False), key=lambda e: e["type"] not in _ERROR_CODES)
    for err in errors:
        kind = err["type"]
        if kind == "extra_forbidden":
            path, _ = _data_path(err["loc"][:-1], data)
            path = (*path, err["loc"][-1])
        else:
            path, _ = _data_path(err["loc"], data)
        if kind == "missing":
            path = result.first_lacking((*path, err["loc"][-1]))[:-1]
        if kind == "union_tag_invalid" and isinstance(_node(data, path), dict):
            path = (*path, "type")
        code = _ERROR_CODES.get(kind, INVALID_VALUE)
        source_path = result.origin(path)
        message, hint = _message(kind, err, path, data)
        if kind in ("missing", "extra_forbidden") or err["loc"][-1:] == ("[key]",):
            location = loaded.source.key(source_path)
        else:
            location = loaded.source.value(source_path)
        # a union reports one error per member type: keep the first per place
        if source_path in seen:
            continue
        seen.add(source_path)
        diagnostics.append((source_path, error(location, code, message, hint)))
        if kind == "missing":
            missing[source_path] = str(err["loc"][-1])
        elif kind == "extra_forbidden":
            unknown.append((source_path[:-1], str(err["loc"][-1])))
    return [
        d for path, d in diagnostics if not _said_by_another(path, d, diagnostics, missing, unknown)
    ]


def _said_by_another(
    path: KeyPath,
    diagnostic: Diagnostic,
    diagnostics: list[tuple[KeyPath, Diagnostic]],
    missing: dict[KeyPath, str],
    unknown: list[tuple[KeyPath, str]],
) -> bool:
    """Whether ``diagnostic`` only repeats what another error at the same place says."""
    if diagnostic.code == INVALID_VALUE:
        # A union (number | list | mapping) that fails deep inside one member also reports
        # "not a mapping" for the others at the outer place: the deeper error is the real one.
        return any(len(o) > len(path) and o[: len(path)] == path for o, _ in diagnostics)
    if path in missing:
        # a required key spelled wrong is one mistake: the unknown key says it, with the hint
        field_name = missing[path]
        return any(where == path and did_you_mean(key, [field_name]) for where, key in unknown)
    return False


def _data_path(loc: tuple[Any, ...], data: Any) -> tuple[KeyPath, KeyPath]:
    """Follow pydantic's error location through the data, dropping union/type tags."""
    path: list[str | int] = []
    leftover: list[str | int] = []
    node = data
    for element in loc:
        if isinstance(node, dict) and element in node:
            path.append(element)
            node = node[element]
        elif isinstance(node, list) and isinstance(element, int) and element < len(node):
            path.append(element)
            node = node[element]
        else:
            leftover.append(element)
    return tuple(path), tuple(leftover)


def _message(kind: str, err: Any, path: KeyPath, data: Any) -> tuple[str, str | None]:
    where = _describe(path)
    if kind == "missing":
        field_name = err["loc"][-1]
        return f"missing required field '{field_name}'{where}", None
    if kind == "extra_forbidden":
        key = str(err["loc"][-1])
        # the schema that validated says which keys it knows
        known = fields_for(frozen.SCHEMAS["Spec"], err["loc"][:-1])
        return f"unknown key '{key}'{_describe(path[:-1])}", did_you_mean(key, known)
    if kind == "union_tag_invalid":
        from robospec.model.controller_kinds import CONTROLLER_TYPES

        got = str(_node(data, path))
        hint = did_you_mean(got, CONTROLLER_TYPES) or "types: " + ", ".join(CONTROLLER_TYPES)
        return f"unknown controller type {got!r}{_describe(path[:-1])}", hint
    if kind == "union_tag_not_found":
        return f"missing 'type'{where}", None
    if kind == "literal_error":
        expected = err.get("ctx", {}).get("expected") or err.get("ctx", {}).get("expected_tags")
        got = _node(data, path)
        if not expected:
            return f"invalid value {got!r}{where}", None
        # pydantic says the choices as "'a', 'b' or 'c'": a misspelt one gets its suggestion
        choices = re.findall(r"'([^']*)'", str(expected))
        suggestion = did_you_mean(str(got), choices) if isinstance(got, str) else None
        hint = f"expected one of {expected}"
        return f"invalid value {got!r}{where}", f"{suggestion} ({hint})" if suggestion else hint
    if kind == "string_pattern_mismatch":
        got = _node(data, path)
        return f"invalid name {got!r}{where}", "use letters, digits, '_', '-' and '.'"
    return f"{err['msg']}{where}", None


def _describe(path: KeyPath) -> str:
    if not path:
        return ""
    return " in '" + ".".join(str(p) for p in path) + "'"


def _node(data: Any, path: KeyPath) -> Any:
    node = data
    for element in path:
        try:
            node = node[element]
        except (KeyError, IndexError, TypeError):
            return None
    return node
