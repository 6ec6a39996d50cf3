"""``docs/reference.md``: every spec field, generated from the JSON Schema of the pydantic models
(``robospec.schema.spec_schema()``), so the reference says what the validator accepts.

Each model is a section (the top level first, then the models in the order the fields reach
them); each field a row with its type, its default (or "required"), its description and its
examples, exactly as the schema holds them.
"""

from __future__ import annotations

import json
from typing import Any

from robospec.schema import spec_schema

Schema = dict[str, Any]

TOP = "Spec"


def reference_markdown() -> str:
    schema = spec_schema()
    defs: dict[str, Schema] = schema.get("$defs", {})
    lines = [
        "# Spec field reference",
        "",
        # (generated from the models by `python -m robospec.docgen --write docs`)
        "Every field of a spec, as robospec's models define them; `robospec schema` prints",
        "the same facts as a JSON Schema. Wherever a type says",
        "*number*, a string of arithmetic over `pi` works too (`-5*pi/8`, `1e3`, `pi/2`).",
        "Unknown keys are errors everywhere (RS101). A *name* is a key you choose:",
        "letters, digits, `_`, `.` and `-`, at most 64 characters. A *joint selection* is a",
        "joint name, a glob over the active joints (`panda_joint[1-7]`) or a group's name; a",
        "*link pattern* is a link name or a glob over link names. Defaults and examples are",
        "written as a YAML spec would write them.",
        "",
    ]
    for name in _model_order(schema, defs):
        model = schema if name == TOP else defs[name]
        lines += _model_section(name, model)
    return "\n".join(lines).rstrip() + "\n"


def _model_order(schema: Schema, defs: dict[str, Schema]) -> list[str]:
    """The top level, then every model in the order fields first refer to it (depth first),
    then any model nothing refers to."""
    order: list[str] = []

    def visit(name: str, node: Schema) -> None:
        if name in order:
            return
        order.append(name)
        for ref in _refs(node):
            if ref in defs:
                visit(ref, defs[ref])

    visit(TOP, schema)
    order += [name for name in defs if name not in order]
    return order


def _refs(node: Any) -> list[str]:
    found: list[str] = []
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "$ref" and isinstance(value, str):
                found.append(value.rsplit("/", 1)[-1])
            elif key != "$defs":
                found += _refs(value)
    elif isinstance(node, list):
        for item in node:
            found += _refs(item)
    return found


def _model_section(name: str, model: Schema) -> list[str]:
    lines = [f"## {'Top level' if name == TOP else name}", ""]
    if model.get("description"):
        lines += [_text(model["description"]), ""]
    properties: dict[str, Schema] = model.get("properties", {})
    if not properties:
        return lines
    required = set(model.get("required", []))
    lines += ["| field | type | default | description |", "| --- | --- | --- | --- |"]
    for field, spec in properties.items():
        default = "required" if field in required else _default(spec)
        lines.append(
            f"| `{field}` | {_cell(type_text(spec))} | {_cell(default)} | "
            f"{_cell(_describe(spec))} |"
        )
    lines.append("")
    return lines


# a model's default longer than this reads better as "the defaults of its fields"
LONG_DEFAULT = 40


def _default(spec: Schema) -> str:
    if "default" not in spec:
        return ""
    text = yaml_flow(spec["default"])
    if len(text) > LONG_DEFAULT and "$ref" in spec:
        return "its fields' defaults"
    return f"`{text}`"


# characters that make a plain YAML scalar mean something else, or not parse
_YAML_SPECIAL = set(":{}[],#&*!|>'\"%@`")


def yaml_flow(value: Any) -> str:
    """``value`` as YAML flow style, as a spec would write it: ``{p: [0, 0, 0.5]}``."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        plain = (
            value
            and not (_YAML_SPECIAL & set(value))
            and value == value.strip()
            and value.lower() not in ("null", "true", "false", "yes", "no", "~")
            and not _looks_numeric(value)
        )
        return value if plain else json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(yaml_flow(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{yaml_flow(k)}: {yaml_flow(v)}" for k, v in value.items()) + "}"
    return json.dumps(value)


def _looks_numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return text.startswith(("-", "+", "."))
    return True


def _describe(spec: Schema) -> str:
    parts = []
    if spec.get("description"):
        text = _text(spec["description"])
        parts.append(text if text.endswith(".") else text + ".")
    examples = spec.get("examples") or _nested_examples(spec)
    if examples:
        shown = ", ".join(f"`{yaml_flow(e)}`" for e in examples)
        parts.append(f"*Example:* {shown}")
    return " ".join(parts)


def _nested_examples(spec: Schema) -> list[Any]:
    """Examples pydantic put on one branch of an optional field (``str | None``)."""
    for branch in spec.get("anyOf", []):
        if isinstance(branch, dict) and branch.get("examples"):
            return list(branch["examples"])
    return []


def type_text(spec: Schema) -> str:
    """A schema fragment as a short type: ``list of 3 number``, ``map of name → Material``."""
    if "$ref" in spec:
        name = spec["$ref"].rsplit("/", 1)[-1]
        return f"[{name}](#{name.lower()})"
    if "const" in spec:
        return f"`{yaml_flow(spec['const'])}`"
    if "enum" in spec:
        return "one of " + ", ".join(f"`{yaml_flow(v)}`" for v in spec["enum"])
    if "then" in spec and "else" in spec:  # e.g. a controller: `extends` or a typed config
        return f"{type_text(spec['then'])} or {type_text(spec['else'])}"
    conditional = spec.get("allOf", [])
    if conditional and all(isinstance(b, dict) and "then" in b for b in conditional):
        # one `if <discriminator> then <model>` per case, as schema.py writes tagged unions
        return " or ".join(type_text(branch["then"]) for branch in conditional)
    branches = spec.get("oneOf") or spec.get("anyOf")
    if branches:
        parts: list[str] = []
        for branch in branches:
            text = type_text(branch)
            if text not in parts:
                parts.append(text)
        if "number" in parts and "expression" in parts:
            parts.remove("expression")
        return " or ".join(_bounded(p, spec) for p in parts)
    kind = spec.get("type")
    if kind == "array":
        items = type_text(spec.get("items", {}))
        if " or " in items:
            items = f"({items})"
        size = spec.get("minItems")
        if size is not None and size == spec.get("maxItems"):
            return f"list of {size} {items}"
        return f"list of {items}"
    if kind == "object":
        value = spec.get("additionalProperties")
        if not isinstance(value, dict):
            patterns = list(spec.get("patternProperties", {}).values())
            value = patterns[0] if patterns else None
        if value is None:
            return "mapping"
        key = spec.get("propertyNames", {}).get("x-robospec-ref")
        values = type_text(value)
        if " or " in values:
            values = f"({values})"
        return f"map of {_ref_kind(key) if key else 'name'} → {values}"
    if kind == "string":
        if "pi" in spec.get("pattern", ""):
            return "expression"
        ref = spec.get("x-robospec-ref")
        return _ref_kind(ref) if ref else "string"
    if isinstance(kind, str):
        return _bounded(kind, spec)
    return "any"


# what a string that names something in the robot or the spec is called on the page
REF_KINDS = {
    "joint": "joint name",
    "link": "link name",
    "link-or-named": "link or named_links name",
    "mount-link": "link name (a frame fold_frames leaves out too)",
    "link-pattern": "link pattern",
    "joint-selection": "joint selection",
    "controller": "controller name",
    "control-mode": "control mode name",
    "material": "material name",
    "link-state": "link_states name",
    "keyframe": "keyframe name",
}


def _ref_kind(ref: str) -> str:
    return REF_KINDS.get(ref, ref.replace("-", " ") + " name")


def _bounded(text: str, spec: Schema) -> str:
    bounds = [
        (symbol, spec[key])
        for key, symbol in (
            ("exclusiveMinimum", ">"),
            ("minimum", "≥"),
            ("exclusiveMaximum", "<"),
            ("maximum", "≤"),
        )
        if key in spec
    ]
    if not bounds or text not in ("number", "integer"):
        return text
    return text + " " + ", ".join(f"{symbol} {value}" for symbol, value in bounds)


def _text(description: str) -> str:
    """Docstring-flavoured text (``x`` literals, line breaks) as one Markdown line."""
    return " ".join(description.replace("``", "`").split())


def _cell(text: str) -> str:
    return text.replace("|", "\\|")
