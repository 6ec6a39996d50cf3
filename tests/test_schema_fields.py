"""The generated JSON Schema documents every field: a description, an example that is valid,
and for every optional field a valid default (required fields have none). Editors show these
as hover text and completions; docs are generated from them. That the committed
schemas/robospec.schema.json equals `robospec schema` is tested in tests/test_cli.py."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import jsonschema
import pytest

from robospec.schema import CONTROLLER_EXTENSION, spec_schema

SCHEMA = spec_schema()


def object_schemas(node: Any, where: str = "#") -> Iterator[tuple[str, dict[str, Any]]]:
    """Every schema with `properties`, anywhere in the document, with a readable place; `if`
    conditions only test a value (`type` is X), they define no field."""
    if isinstance(node, dict):
        if isinstance(node.get("properties"), dict):
            yield where, node
        for key, value in node.items():
            if key != "if":
                yield from object_schemas(value, f"{where}/{key}")
    elif isinstance(node, list):
        for index, item in enumerate(node):
            yield from object_schemas(item, f"{where}/{index}")


def map_value_schemas(node: Any, where: str = "#") -> Iterator[tuple[str, dict[str, Any]]]:
    """The value schemas of name-keyed maps (additionalProperties / patternProperties)."""
    if isinstance(node, dict):
        if isinstance(node.get("additionalProperties"), dict):
            yield f"{where}/additionalProperties", node["additionalProperties"]
        for pattern, value in (node.get("patternProperties") or {}).items():
            yield f"{where}/patternProperties/{pattern}", value
        for key, value in node.items():
            yield from map_value_schemas(value, f"{where}/{key}")
    elif isinstance(node, list):
        for index, item in enumerate(node):
            yield from map_value_schemas(item, f"{where}/{index}")


def fields() -> Iterator[tuple[str, str, dict[str, Any], bool]]:
    for where, obj in object_schemas(SCHEMA):
        required = set(obj.get("required", []))
        for name, prop in obj["properties"].items():
            yield f"{where}/properties/{name}", name, prop, name in required


def standalone(subschema: dict[str, Any]) -> jsonschema.Draft202012Validator:
    """A validator for one subschema whose `#/$defs/...` references still resolve."""
    return jsonschema.Draft202012Validator({**subschema, "$defs": SCHEMA["$defs"]})


def in_extension(place: str) -> bool:
    return place.startswith(f"#/$defs/{CONTROLLER_EXTENSION}/")


def test_the_schema_documents_many_fields() -> None:
    # guards the walk itself: if it found nothing, every test below would pass vacuously
    assert sum(1 for _ in fields()) > 150


def test_every_field_has_a_description() -> None:
    missing = [place for place, _, prop, _ in fields() if not prop.get("description")]
    assert not missing, "fields without a description:\n" + "\n".join(missing)


def test_every_field_has_an_example() -> None:
    missing = [place for place, _, prop, _ in fields() if not prop.get("examples")]
    assert not missing, "fields without examples:\n" + "\n".join(missing)


def test_every_optional_field_has_a_default_and_no_required_field_has_one() -> None:
    problems = []
    for place, _, prop, required in fields():
        if in_extension(place):
            continue  # a field left out of an `extends` controller is the base's: no default
        if required and "default" in prop:
            problems.append(f"{place}: required, yet has a default")
        if not required and "default" not in prop:
            problems.append(f"{place}: optional, without a default")
    assert not problems, "\n".join(problems)


def test_every_example_and_default_is_valid_for_its_field() -> None:
    problems = []
    for place, _, prop, _ in fields():
        validator = standalone(prop)
        values = [("example", e) for e in prop.get("examples", [])]
        if "default" in prop:
            values.append(("default", prop["default"]))
        for kind, value in values:
            for err in validator.iter_errors(value):
                problems.append(f"{place}: {kind} {value!r}: {err.message[:120]}")
    assert not problems, "\n".join(problems)


def test_every_model_and_the_root_have_a_description() -> None:
    assert SCHEMA.get("description")
    missing = [name for name, model in SCHEMA["$defs"].items() if not model.get("description")]
    assert not missing, f"models without a description: {missing}"


def test_every_map_describes_its_values() -> None:
    def described(schema: dict[str, Any]) -> bool:
        if schema.get("description"):
            return True
        ref = schema.get("$ref", "")
        return bool(ref) and bool(SCHEMA["$defs"][ref.rsplit("/", 1)[-1]].get("description"))

    missing = [place for place, value in map_value_schemas(SCHEMA) if not described(value)]
    assert not missing, "maps whose values have no description:\n" + "\n".join(missing)


def test_an_extends_controller_offers_exactly_the_fields_of_the_controller_types() -> None:
    extension = SCHEMA["$defs"][CONTROLLER_EXTENSION]
    controller_fields: set[str] = set()
    for member in SCHEMA["properties"]["controllers"]["patternProperties"].values():
        for case in member["else"]["allOf"]:
            name = case["then"]["$ref"].rsplit("/", 1)[-1]
            controller_fields |= set(SCHEMA["$defs"][name]["properties"])
    assert set(extension["properties"]) == controller_fields | {"extends"}
    assert extension["required"] == ["extends"]
    assert extension["additionalProperties"] is False


@pytest.mark.parametrize(
    "controller,valid",
    [
        ({"extends": "arm_pos", "use_delta": True, "lower": -0.1}, True),
        ({"extends": "arm_ee", "type": "pd_ee_pose", "rot_lower": -0.1}, True),
        ({"extends": "arm_pos", "use_delat": True}, False),  # a misspelled field
        ({"type": "pd_joint_pos", "joints": "arm"}, False),  # no extends: all required fields
        ({"extends": "arm_pos", "type": "pd_joint_position"}, False),  # no such type
    ],
)
def test_the_schema_accepts_extends_controllers_and_still_checks_their_fields(
    controller: dict[str, Any], valid: bool
) -> None:
    spec = {
        "robospec": 1,
        "uid": "rs_arm",
        "description": {"urdf": "arm.urdf"},
        "controllers": {"x": controller},
        "control_modes": {"pd_joint_pos": "x"},
    }
    errors = list(jsonschema.Draft202012Validator(SCHEMA).iter_errors(spec))
    assert (not errors) == valid, [e.message[:200] for e in errors]
