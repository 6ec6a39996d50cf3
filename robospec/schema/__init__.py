"""The JSON Schema of the spec format, generated from the pydantic models (one source of truth).
``schemas/robospec.schema.json`` is this text; a test keeps the two equal.

What the models cannot say by themselves is added here, derived from the models: the
defaults of fields whose default is built by a factory (``default_factory``); the ``extends``
form of a controller, which :mod:`robospec.model.validate` merges away before the models ever see
it; and a dispatch on a controller's ``type`` that validators report precisely.
"""

from __future__ import annotations

import copy
import json
from typing import Any

from pydantic import BaseModel
from pydantic.json_schema import GenerateJsonSchema, NoDefault
from pydantic_core import core_schema

SCHEMA_ID = "https://robospec.dev/schemas/robospec.schema.json"
DRAFT = "https://json-schema.org/draft/2020-12/schema"
CONTROLLER_EXTENSION = "ControllerExtension"


class _SpecSchemaGenerator(GenerateJsonSchema):
    """Pydantic's generator, but a factory-made default is shown too (editors and docs need
    the value a left-out field takes, however the model builds it)."""

    def get_default_value(self, schema: core_schema.WithDefaultSchema) -> Any:
        if "default" in schema:
            default = schema["default"]
        elif "default_factory" in schema and not schema.get("default_factory_takes_data"):
            default = schema["default_factory"]()  # type: ignore[call-arg]
        else:
            return NoDefault
        if isinstance(default, BaseModel):
            # what a user would write: fields that stay unset (None) are left out
            return default.model_dump(mode="json", exclude_none=True)
        return default


def spec_schema() -> dict[str, Any]:
    from robospec.model.spec import Spec

    schema = Spec.model_json_schema(schema_generator=_SpecSchemaGenerator)
    _allow_controller_extends(schema)
    return {"$schema": DRAFT, "$id": SCHEMA_ID, **schema}


def schema_text(schema: dict[str, Any] | None = None) -> str:
    """``schema`` (default: the spec schema) as the text robospec writes: stable, indented."""
    chosen = spec_schema() if schema is None else schema
    return json.dumps(chosen, indent=2, ensure_ascii=False) + "\n"


def _allow_controller_extends(schema: dict[str, Any]) -> None:
    """A controller with ``extends`` is a partial config of any type: validate it against
    :data:`CONTROLLER_EXTENSION` (every controller field, none required); any other controller
    against the config its ``type`` names."""
    controllers = schema["properties"]["controllers"]
    (pattern, union), *_ = controllers["patternProperties"].items()
    members = [_ref_target(schema, member["$ref"]) for member in union["oneOf"]]
    schema["$defs"][CONTROLLER_EXTENSION] = _extension_schema(members)
    controllers["patternProperties"][pattern] = {
        "description": union.get("description", ""),
        "if": {"type": "object", "required": ["extends"]},
        "then": {"$ref": f"#/$defs/{CONTROLLER_EXTENSION}"},
        # in the models' order (pydantic's discriminator mapping is sorted by name)
        "else": _dispatch_on_type(
            {
                member["properties"]["type"]["const"]: ref["$ref"]
                for member, ref in zip(members, union["oneOf"], strict=True)
            }
        ),
    }


def _dispatch_on_type(mapping: dict[str, str]) -> dict[str, Any]:
    """``if type is X then X's config`` for each type, instead of pydantic's ``oneOf``: a
    validator then reports a bad field at the field, not "no oneOf member matched" at every
    key of the controller (taplo does the latter)."""
    return {
        "type": "object",
        "required": ["type"],
        "properties": {
            "type": {
                "enum": list(mapping),
                "description": "Which ManiSkill controller this is; its other fields follow "
                "from it.",
                "examples": ["pd_joint_pos"],
            }
        },
        "allOf": [
            {
                "if": {"properties": {"type": {"const": name}}, "required": ["type"]},
                "then": {"$ref": ref},
            }
            for name, ref in mapping.items()
        ],
    }


def _extension_schema(members: list[dict[str, Any]]) -> dict[str, Any]:
    variants: dict[str, list[dict[str, Any]]] = {}
    for member in members:
        for name, prop in member["properties"].items():
            # a left-out field is the base controller's, not the type's default
            prop = {k: v for k, v in prop.items() if k not in ("default", "title")}
            if prop not in variants.setdefault(name, []):
                variants[name].append(prop)
    properties: dict[str, Any] = {
        "extends": {
            "type": "string",
            "x-robospec-ref": "controller",
            "description": "The controller this one is based on: every field not given here "
            "(`type` included) is taken from it.",
            "examples": ["arm_pos"],
        }
    }
    for name, schemas in variants.items():
        if len(schemas) == 1:
            properties[name] = copy.deepcopy(schemas[0])
            continue
        first = schemas[0]
        properties[name] = {
            "anyOf": [
                {k: v for k, v in s.items() if k not in ("description", "examples")}
                for s in schemas
            ],
            "description": first.get("description", ""),
            "examples": first.get("examples", []),
        }
    return {
        "type": "object",
        "description": "A controller written as changes to another one (`extends`); fields "
        "left out keep the base controller's values.",
        "properties": properties,
        "required": ["extends"],
        "additionalProperties": False,
    }


def _ref_target(schema: dict[str, Any], ref: str) -> dict[str, Any]:
    prefix = "#/$defs/"
    assert ref.startswith(prefix), ref
    return schema["$defs"][ref[len(prefix) :]]
