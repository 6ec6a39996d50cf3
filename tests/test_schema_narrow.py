"""`robospec schema --for SPEC`: a schema narrowed to one robot's names accepts that robot's
spec, rejects misspelled names (joints, links, controllers, materials, ...), keeps accepting
globs where globs are allowed, and a spec with errors gets diagnostics, not a schema."""

from __future__ import annotations

import copy
import json
from functools import cache
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import tomllib
from conftest import MISSPELLED_JOINT_SPEC, PANDA_SPEC, ROOT, run_robospec, sample_fast, spec_params
from ruamel.yaml import YAML

from robospec.model.refs import REF_KEY
from robospec.schema import SCHEMA_ID, spec_schema
from robospec.schema.command import narrowed_schema_text

SPEC_FILES = sorted(
    p
    for folder in ("specs", "tests/specs/positive")
    for p in (ROOT / folder).rglob("*")
    if p.suffix in (".yaml", ".yml", ".toml")
)
GENERIC = spec_schema()
# the sweep over every spec costs seconds each (a narrowed schema is ~1.5 MB to check against
# the meta-schema): the fast loop takes the Panda (a TOML robot: test_editor_toml)
FAST_SAMPLE = {PANDA_SPEC}


def load_spec_data(path: Path) -> Any:
    if path.suffix == ".toml":
        return tomllib.loads(path.read_text(encoding="utf-8"))
    return YAML(typ="safe").load(path.read_text(encoding="utf-8"))


def narrowed(path: Path) -> dict[str, Any]:
    text, diagnostics = narrowed_schema_text(path)
    assert text is not None, [d.message for d in diagnostics]
    return json.loads(text)


def check_schema(schema: dict[str, Any]) -> None:
    """``schema`` is a valid JSON Schema (checked against the meta-schema, seconds for a schema of
    this size): each distinct schema once per process, by its content (the sweep below checks
    the generic schema for every spec)."""
    _check_schema_text(json.dumps(schema, sort_keys=True))


@cache
def _check_schema_text(text: str) -> None:
    jsonschema.Draft202012Validator.check_schema(json.loads(text))


def errors(schema: dict[str, Any], data: Any) -> list[jsonschema.ValidationError]:
    return list(jsonschema.Draft202012Validator(schema).iter_errors(data))


def markers(node: Any) -> list[str]:
    if isinstance(node, list):
        return [m for item in node for m in markers(item)]
    if not isinstance(node, dict):
        return []
    own = [node[REF_KEY]] if REF_KEY in node else []
    return own + [m for value in node.values() for m in markers(value)]


@pytest.fixture(scope="module")
def panda_schema() -> dict[str, Any]:
    return narrowed(PANDA_SPEC)


@pytest.fixture(scope="module")
def panda_data() -> Any:
    return load_spec_data(PANDA_SPEC)


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@pytest.mark.parametrize("path", sample_fast(spec_params(SPEC_FILES, ROOT), FAST_SAMPLE))
def test_every_shipped_spec_is_valid_under_the_schema_and_its_own_narrowed_schema(
    path: Path,
) -> None:
    data = load_spec_data(path)
    for schema in (GENERIC, narrowed(path)):
        check_schema(schema)
        problems = errors(schema, data)
        assert not problems, [(list(e.absolute_path), e.message[:200]) for e in problems]


def test_narrowed_schema_has_its_own_id_and_no_markers_left(panda_schema: dict) -> None:
    assert panda_schema["$id"] != SCHEMA_ID
    assert "rs_panda" in panda_schema["$id"]
    assert markers(spec_schema()), "the generic schema marks the places that name things"
    assert markers(panda_schema) == []


def test_narrowed_schema_lists_the_robots_joint_link_and_group_names(panda_schema: dict) -> None:
    defs = panda_schema["$defs"]
    joints = [f"panda_joint{i}" for i in range(1, 8)] + [
        "panda_finger_joint1",
        "panda_finger_joint2",
    ]
    assert defs["robot-joint"]["enum"] == joints
    assert defs["robot-joint-selection"]["enum"] == [*joints, "arm", "gripper"]
    assert "panda_hand_tcp" in defs["robot-link"]["enum"]
    assert "finger1_link" in defs["robot-link-or-named"]["enum"]
    assert defs["robot-material"]["enum"] == ["gripper"]
    # a dictionary keyed by joints offers each joint as a property (editors complete keys)
    qpos = panda_schema["$defs"]["Keyframe"]["properties"]["qpos"]
    by_name = next(alt for alt in qpos["anyOf"] if alt.get("type") == "object")
    assert list(by_name["properties"]) == [*joints, "arm", "gripper"]
    assert by_name["additionalProperties"] is False


def _set(path: tuple, value: Any):
    def mutate(data: Any) -> None:
        node = data
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value

    return mutate


MISSPELLINGS = {
    "group member": (("groups", "gripper", 1), "panda_finger_joint3"),
    "controller joints": (("controllers", "arm_pos", "joints"), "panda_joint8"),
    "per-joint value key": (("controllers", "arm_pos", "stiffness"), {"panda_joint8": 1}),
    "keyframe qpos key": (("keyframes", "rest", "qpos", "panda_joint8"), 0.0),
    "mimic follower": (("controllers", "gripper", "mimic"), {"panda_fingr_joint2": "arm"}),
    "mimic leader": (("controllers", "gripper", "mimic", "panda_finger_joint2"), "panda_joint0"),
    "tcp link": (("tcp",), "panda_hand_tpc"),
    "ee_link": (("controllers", "arm_ee_delta_pos", "ee_link"), "panda_hnd_tcp"),
    "link rule key": (("links", "panda_leftfinger_typo"), {"material": "gripper"}),
    "link rule material": (("links", "panda_*finger", "material"), "griper"),
    "control mode controller": (("control_modes", "pd_joint_pos", "arm"), "arm_pso"),
    "extends base": (("controllers", "arm_delta_pos", "extends"), "arm_pso"),
    "named link": (("named_links", "finger1_link"), "panda_leftfingr"),
    "is_static joints": (("is_static", "joints"), "armm"),
}


@pytest.mark.parametrize("place", list(MISSPELLINGS))
def test_a_misspelled_name_is_rejected_where_the_spec_names_it(
    place: str, panda_schema: dict, panda_data: Any
) -> None:
    path, value = MISSPELLINGS[place]
    data = copy.deepcopy(panda_data)
    _set(path, value)(data)
    problems = errors(panda_schema, data)
    assert problems, f"{place}: {value!r} was accepted"
    # the generic schema takes any name: the narrowing is what catches it
    assert not errors(spec_schema(), data)


@pytest.mark.parametrize(
    "path,value",
    [
        (("groups", "arm"), "panda_joint[1-6]"),
        (("keyframes", "rest", "qpos"), {"panda_joint*": 0.0}),
        (("links", "*_hand"), {"material": "gripper"}),
        (("never_collide",), [["panda_link*", "panda_hand"]]),
    ],
)
def test_globs_stay_allowed_where_the_spec_accepts_them(
    path: tuple, value: Any, panda_schema: dict, panda_data: Any
) -> None:
    data = copy.deepcopy(panda_data)
    _set(path, value)(data)
    assert not errors(panda_schema, data)


def test_a_glob_is_not_accepted_where_only_an_exact_name_is(
    panda_schema: dict, panda_data: Any
) -> None:
    data = copy.deepcopy(panda_data)
    data["tcp"] = "panda_hand*"
    assert errors(panda_schema, data)


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_schema_for_writes_the_narrowed_schema_to_a_file(tmp_path: Path) -> None:
    out = tmp_path / "panda.schema.json"
    result = run_robospec("schema", "--for", str(PANDA_SPEC), "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert json.loads(out.read_text(encoding="utf-8")) == narrowed(PANDA_SPEC)


def test_schema_for_a_spec_with_errors_prints_located_diagnostics_and_exits_one() -> None:
    result = run_robospec("schema", "--for", str(MISSPELLED_JOINT_SPEC.relative_to(ROOT)))
    assert result.returncode == 1
    assert result.stdout == ""
    assert "RS201/fail.yaml:6:51: error[RS201] unknown joint 'panda_joint77'" in (result.stderr)
    assert "Traceback" not in result.stderr


def test_schema_for_a_missing_file_is_a_located_error_not_a_traceback() -> None:
    result = run_robospec("schema", "--for", "no/such/spec.yaml")
    assert result.returncode == 1
    assert "error[RS001]" in result.stderr
    assert "Traceback" not in result.stderr


def test_schema_for_a_folder_is_a_usage_error() -> None:
    result = run_robospec("schema", "--for", "specs")
    assert result.returncode == 2
    assert "Traceback" not in result.stderr


def name_places(node: Any) -> list[dict[str, Any]]:
    """Every narrowed place: a schema referring to one of the robot's name lists."""
    if isinstance(node, list):
        return [p for item in node for p in name_places(item)]
    if not isinstance(node, dict):
        return []
    refs = [node.get("$ref", "")] + [alt.get("$ref", "") for alt in node.get("anyOf", [])]
    own = [node] if any(r.startswith("#/$defs/robot-") for r in refs) else []
    return own + [p for value in node.values() for p in name_places(value)]


def with_examples(node: Any) -> list[dict[str, Any]]:
    if isinstance(node, list):
        return [p for item in node for p in with_examples(item)]
    if not isinstance(node, dict):
        return []
    own = [node] if "examples" in node else []
    return own + [
        p for key, value in node.items() if key != "examples" for p in with_examples(value)
    ]


@pytest.mark.parametrize("spec", ["fetch.yaml", "humanoid.yaml"])
def test_every_example_in_a_narrowed_schema_is_valid_for_that_robot(spec: str) -> None:
    # the generic schema's examples are Panda names; fetch and the humanoid have none of them
    schema = narrowed(ROOT / "specs/maniskill" / spec)
    assert len(name_places(schema)) > 20
    problems = []
    for place in with_examples(schema):
        validator = jsonschema.Draft202012Validator({**place, "$defs": schema["$defs"]})
        problems += [
            (place.get("title"), e) for e in place["examples"] if not validator.is_valid(e)
        ]
    assert not problems
    # the places that name a link still offer one as an example
    mount = schema["$defs"]["Camera"]["properties"]["mount"]
    assert mount["examples"][0] in schema["$defs"]["robot-link"]["enum"]
