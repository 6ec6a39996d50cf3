"""The frozen spec model validates exactly as the pydantic models do, and its cache holds.

`robospec validate`, `build` and `register` validate with pydantic-core schemas that the
freezer (robospec.model.freeze) writes from the pydantic models for the pydantic installed, and
that robospec.model.frozen caches per pydantic and model source. These tests hold the frozen
model to the pydantic models (on every spec we ship or test with, on targeted invalid ones and
on mutated ones, both give the same errors, or the same values, class for class), the cache to
its key (another pydantic-core or a changed model source makes a new entry; a damaged entry is
made again; an unwritable cache still validates), and the hints to the schema that validated.
"""

from __future__ import annotations

import ast
import copy
import dataclasses
import functools
import os
import pickle
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pydantic_core
import pytest
from conftest import PANDA_SPEC, ROOT
from hypothesis import given
from hypothesis import strategies as st
from pydantic import BaseModel, ValidationError
from pydantic_core import SchemaValidator
from test_fuzz_properties import SEEDS, budget, mutated_data

import robospec.model.frozen as frozen
import robospec.model.frozen_cache as frozen_cache
from robospec.load.reader import read_spec
from robospec.load.source_map import LoadedSpec
from robospec.model.freeze import FreezeError, _name, frozen_source, model_classes
from robospec.model.record import Record
from robospec.model.spec import Spec as PydanticSpec
from robospec.model.validate import SpecModelResult, _merge_extends, build_spec


def _corpus_files() -> list[Path]:
    found: list[Path] = []
    for folder in ("specs", "tests/specs", "docs/examples"):
        for suffix in ("*.yaml", "*.toml"):
            found += sorted((ROOT / folder).rglob(suffix))
    return [p for p in found if b"robospec" in p.read_bytes()[:400]]


@functools.cache
def _loaded(path: Path) -> LoadedSpec | None:
    """The spec as loaded, or None where loading itself fails (a syntax error: those specs
    never reach the model, so they have nothing to compare)."""
    loaded, _ = read_spec(path)
    return loaded


def _data(loaded: LoadedSpec) -> dict[str, Any]:
    """The spec's data as the models get it: controllers' ``extends`` merged."""
    data = dict(loaded.data)
    if isinstance(data.get("controllers"), dict):
        merged = _merge_extends(data["controllers"], loaded, SpecModelResult(None, []))
        data["controllers"] = merged
    return data


FILES = _corpus_files()

_DROP = object()  # in an overlay: the key is removed

# Invalid specs made from the panda spec, one per kind of check the schemas hold, so that each
# way the freezer converts a check is compared with pydantic on input that fails it.
INVALID_OVERLAYS: dict[str, dict[str, Any]] = {
    "a string version (literal)": {"robospec": "1"},
    "a uid with a space (pattern)": {"uid": "rs panda"},
    "an unknown key in a nested model": {"loader": {"fix_root": True}},
    "an unknown controller type (tagged union)": {"controllers": {"arm_pos": {"type": "pd"}}},
    "a controller without a type": {"controllers": {"arm_pos": {"type": _DROP}}},
    "a controller without a required field": {"controllers": {"arm_pos": {"damping": _DROP}}},
    "a boolean where a number goes": {"controllers": {"arm_pos": {"stiffness": True}}},
    "arithmetic that does not parse": {"keyframes": {"rest": {"qpos": {"arm": "pi/"}}}},
    "a check duration of 0 (gt on a number)": {"checks": {"step_response": {"duration": 0}}},
    "a negative overshoot (ge on a number)": {"checks": {"step_response": {"max_overshoot": -1}}},
    "zero steps (ge on an integer)": {"checks": {"keyframe_hold": {"steps": 0}}},
    "a collision bit of 32 (le on an integer)": {"scene_collision_bits": [32]},
    "a pose with two coordinates (list length)": {"keyframes": {"rest": {"pose": {"p": [0, 0]}}}},
    "two description files (a model's own rule)": {"description": {"mjcf": "robot.xml"}},
    "a tcp with neither link nor midpoint (a model's own rule)": {"tcp": {"orientation": "a"}},
    "a list where a mapping goes": {"materials": ["gripper"]},
    "a Python keyword as a class name": {"class_name": "class"},
}


def _overlaid(base: Any, overlay: Any) -> Any:
    if not isinstance(overlay, dict) or not isinstance(base, dict):
        return overlay
    out = dict(base)
    for key, value in overlay.items():
        if value is _DROP:
            out.pop(key, None)
        else:
            out[key] = _overlaid(base.get(key), value)
    return out


def _invalid_variant(name: str) -> dict[str, Any]:
    loaded = _loaded(PANDA_SPEC)
    assert loaded is not None
    return _overlaid(_data(loaded), INVALID_OVERLAYS[name])


def _shape(value: Any) -> Any:
    """A value as plain data that names every model's class and its given fields, for pydantic
    models and records alike."""
    if isinstance(value, (BaseModel, Record)):
        fields = {name: _shape(v) for name, v in value.__dict__.items()}
        return (type(value).__name__, sorted(value.model_fields_set), fields)
    if isinstance(value, dict):
        return {k: _shape(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_shape(v) for v in value]
    return value


def _errors(exc: ValidationError) -> list[tuple[Any, ...]]:
    return [
        (
            e["type"],
            e["loc"],
            e["msg"],
            repr(e["input"]) if not isinstance(e["input"], dict) else "",
        )
        for e in exc.errors(include_url=False)
    ]


def _outcome(validate: Any, data: Any) -> Any:
    try:
        return ("valid", _shape(validate(data)))
    except ValidationError as exc:
        return ("invalid", _errors(exc))


def _pydantic(data: Any) -> Any:
    return PydanticSpec.model_validate(data)


def _frozen(data: Any) -> Any:
    return frozen.validator_for("Spec").validate_python(data)


# -- it validates as pydantic does --------------------------------------------------------


# parsed in the test, not at collection: parsing them all costs seconds, in each worker
@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_spec_validates_to_the_same_values_or_errors_as_with_pydantic(path: Path) -> None:
    loaded = _loaded(path)
    if loaded is None:
        # a syntax error: the spec never reaches either model, and the loader says why
        assert any(d.is_error for d in read_spec(path)[1])
        return
    data = _data(loaded)
    assert _outcome(_frozen, data) == _outcome(_pydantic, data)


@pytest.mark.parametrize("name", INVALID_OVERLAYS)
def test_each_kind_of_invalid_spec_fails_with_the_same_errors_as_with_pydantic(name: str) -> None:
    data = _invalid_variant(name)
    outcome = _outcome(_frozen, data)
    assert outcome[0] == "invalid", name
    assert outcome == _outcome(_pydantic, data)


SEED_FILES = sorted({seed.path for seed in SEEDS})  # the fuzz tests' seeds, each file once


@given(st.sampled_from(SEED_FILES).flatmap(lambda p: mutated_data(_data(_loaded(p)))))
@budget(150)
def test_mutated_specs_validate_as_with_pydantic(data: dict[str, Any]) -> None:
    assert _outcome(_frozen, data) == _outcome(_pydantic, data)


def test_the_comparison_sees_many_valid_and_invalid_specs_and_every_kind_of_error() -> None:
    # the comparisons above mean something only if both outcomes occur often, and every way a
    # schema can reject a value does
    outcomes = [_outcome(_frozen, _data(loaded)) for p in FILES if (loaded := _loaded(p))]
    outcomes += [_outcome(_frozen, _invalid_variant(name)) for name in INVALID_OVERLAYS]
    kinds = [kind for kind, _ in outcomes]
    assert kinds.count("valid") >= 40 and kinds.count("invalid") >= 20, kinds
    seen = {error[0] for kind, errors in outcomes if kind == "invalid" for error in errors}
    expected = {
        "literal_error",
        "string_pattern_mismatch",
        "extra_forbidden",
        "union_tag_invalid",
        "union_tag_not_found",
        "missing",
        "number",
        "expression",
        "greater_than",
        "greater_than_equal",
        "less_than_equal",
        "too_short",
        "value_error",
        "dict_type",
        "python_keyword",
    }
    assert expected <= seen, sorted(expected - seen)
    # and the files that never reach the model are the syntax errors' examples only (the
    # failing examples of the reader's codes, RS0xx)
    unread = [p for p in FILES if _loaded(p) is None]
    assert all(re.fullmatch(r"RS0\d\d", p.parent.name) for p in unread), unread
    assert all(p.name.startswith("fail") for p in unread), unread


# -- the freezer ---------------------------------------------------------------------------


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_the_freezer_writes_the_same_module_under_any_hash_seed() -> None:
    texts = set()
    for seed in ("0", "1", "4242"):
        result = subprocess.run(
            [sys.executable, "-m", "robospec.model.freeze"],
            cwd=ROOT,
            env={**os.environ, "PYTHONHASHSEED": seed},
            capture_output=True,
            check=True,
        )
        texts.add(result.stdout)
    assert texts == {frozen_source().encode()}


def test_the_freezer_writes_the_same_module_whatever_pydantic_built_before() -> None:
    # pydantic inlines nested models' schemas as it finds them: built, or not yet
    code = (
        "import sys\n"
        "from robospec.model.spec import Spec\n"
        "from robospec.model.controllers import PDJointPosMimicConfig\n"
        "Spec.model_json_schema()\n"
        "PDJointPosMimicConfig.model_rebuild(force=True)\n"
        "from robospec.model.freeze import frozen_source\n"
        "sys.stdout.write(frozen_source())\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    assert result.stdout == frozen_source()


def test_the_freezer_refuses_a_function_the_frozen_module_cannot_name() -> None:
    with pytest.raises(FreezeError, match="cannot be frozen"):
        _name(lambda: [0.0], "Pose.p.default_factory")
    with pytest.raises(FreezeError, match="no frozen equivalent"):
        _name(functools.partial(max, 0), "Checks.steps")


# -- the cache -------------------------------------------------------------------------------


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An empty model cache of this test's own."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(folder))
    return folder / "model"


def _defined() -> dict[str, Any]:
    """The frozen module run afresh, as robospec.model.frozen runs it, in a namespace of its own."""
    namespace: dict[str, Any] = {"__name__": "frozen_under_test"}
    frozen.load_into(namespace)
    return namespace


def _entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("frozen_*.py"))


def test_a_cold_cache_gets_the_freezers_module_and_a_warm_one_is_read_back(cache: Path) -> None:
    _defined()
    (entry,) = _entries(cache)
    assert entry == frozen_cache.entry_path()
    assert entry.read_text(encoding="utf-8") == frozen_source()
    made = entry.stat().st_mtime_ns
    again = _defined()
    assert _entries(cache) == [entry] and entry.stat().st_mtime_ns == made
    assert set(again["SCHEMAS"]) == set(frozen.SCHEMAS)


def test_a_cache_made_with_another_pydantic_core_is_not_used(
    cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    with monkeypatch.context() as patch:
        patch.setattr(pydantic_core, "__version__", "0.0.1")
        other = frozen_cache.entry_path()
    assert other != frozen_cache.entry_path()
    # what another pydantic-core left behind must not run here: it would fail loudly
    other.parent.mkdir(parents=True)
    other.write_text("raise RuntimeError('a cache for another pydantic-core was used')\n")
    namespace = _defined()
    assert sorted(_entries(cache)) == sorted([other, frozen_cache.entry_path()])
    validator = SchemaValidator(namespace["SCHEMAS"]["Spec"])
    for path in FILES[::5]:
        if (loaded := _loaded(path)) is not None:
            data = _data(loaded)
            assert _outcome(validator.validate_python, data) == _outcome(_pydantic, data), path


def test_the_cache_is_made_again_when_a_model_source_changes(
    cache: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    sources = tmp_path / "model"
    shutil.copytree(frozen_cache.MODEL_FOLDER, sources, ignore=shutil.ignore_patterns("__py*"))
    monkeypatch.setattr(frozen_cache, "MODEL_FOLDER", sources)
    _defined()
    (first,) = _entries(cache)
    common = sources / "common.py"
    common.write_text(common.read_text(encoding="utf-8") + "\n# changed\n", encoding="utf-8")
    _defined()
    (second,) = set(_entries(cache)) - {first}
    assert second == frozen_cache.entry_path()


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_a_damaged_cache_entry_is_made_again(cache: Path) -> None:
    entry = frozen_cache.entry_path()
    entry.parent.mkdir(parents=True)
    entry.write_text("class Spec(:\n")  # cut short by a full disk, say
    _defined()
    assert entry.read_text(encoding="utf-8") == frozen_source()
    entry.write_text("import robospec.model.no_such_module\n")  # runs, then fails
    assert "Spec" in _defined()
    assert entry.read_text(encoding="utf-8") == frozen_source()


def test_an_unwritable_cache_still_validates_and_says_why_it_is_slow(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(blocker / "cache"))  # under a file: no folder
    with pytest.warns(RuntimeWarning, match="ROBOSPEC_CACHE_DIR"):
        namespace = _defined()
    loaded = _loaded(PANDA_SPEC)
    assert loaded is not None
    validated = SchemaValidator(namespace["SCHEMAS"]["Spec"]).validate_python(_data(loaded))
    assert _shape(validated)[2]["uid"] == "rs_panda"


def test_validate_reads_no_pydantic_once_the_cache_is_warm(cache: Path, tmp_path: Path) -> None:
    spec = tmp_path / "typo.yaml"
    spec.write_text("robospec: 1\nuid: rs_typo\ndescription: {urdf: r.urdf}\nloadr: {}\n")
    probe = (
        "import sys\n"
        "from robospec.cli import main\n"
        f"sys.argv = ['robospec', 'validate', {str(spec)!r}]\n"
        "try:\n"
        "    main()\n"
        "except SystemExit:\n"
        "    pass\n"
        "print('PYDANTIC', 'pydantic' in sys.modules)\n"
    )
    runs = [
        subprocess.run(
            [sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, check=True
        )
        for _ in range(2)
    ]
    # the first run makes the cache (with pydantic), the second only reads it
    assert "PYDANTIC True" in runs[0].stdout and "PYDANTIC False" in runs[1].stdout
    assert runs[0].stdout.replace("True", "False") == runs[1].stdout
    assert "did you mean 'loader'?" in runs[1].stdout
    assert len(_entries(cache)) == 1


# -- hints ------------------------------------------------------------------------------------


def _spec_fields(schemas: dict[str, Any]) -> dict[str, Any]:
    """The field schemas of the top-level Spec model inside ``schemas["Spec"]``."""
    node = schemas["Spec"]
    while node.get("type") != "model":
        node = node["schema"]
    return node["schema"]["fields"]


def test_hints_name_the_keys_of_the_schema_that_validated(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # a schema with one more top-level key than the models have: validation accepts it and a
    # misspelling of it is hinted, so both read that schema (before, hints read one schema and
    # another validated)
    schemas = copy.deepcopy(frozen.SCHEMAS)
    _spec_fields(schemas)["handedness"] = {
        "type": "model-field",
        "schema": {"type": "default", "schema": {"type": "str"}, "default": "right"},
    }
    monkeypatch.setattr(frozen, "SCHEMAS", schemas)
    frozen.validator_for.cache_clear()
    try:
        loaded = _loaded(PANDA_SPEC)
        assert loaded is not None
        accepted = build_spec(_with_data(loaded, {**loaded.data, "handedness": "left"}))
        assert accepted.spec is not None and not accepted.diagnostics
        rejected = build_spec(_with_data(loaded, {**loaded.data, "handednes": "left"}))
        (diagnostic,) = rejected.diagnostics
        assert diagnostic.code == "RS101" and "'handedness'" in (diagnostic.hint or "")
    finally:
        monkeypatch.undo()
        frozen.validator_for.cache_clear()


def _with_data(loaded: LoadedSpec, data: dict[str, Any]) -> LoadedSpec:
    return dataclasses.replace(loaded, data=data)


# -- records behave as frozen pydantic models -----------------------------------------------


def _panda() -> Any:
    loaded = _loaded(PANDA_SPEC)
    assert loaded is not None
    return _frozen(_data(loaded))


def _pydantic_class(name: str) -> type[BaseModel]:
    return next(c for c in model_classes() if c.__name__ == name)


def test_there_is_one_record_class_per_pydantic_model() -> None:
    assert list(frozen.RECORDS) == [c.__name__ for c in model_classes()]


def test_a_record_is_immutable() -> None:
    spec = _panda()
    with pytest.raises(TypeError, match="immutable"):
        spec.uid = "other"
    with pytest.raises(TypeError, match="immutable"):
        del spec.uid


def test_a_record_made_from_defaults_equals_pydantics() -> None:
    for name in ("Pose", "Checks", "Hooks", "Loader", "StepResponse"):
        record = frozen.RECORDS[name]()
        assert _shape(record) == _shape(_pydantic_class(name)())


def test_model_copy_replaces_fields_and_counts_them_as_given() -> None:
    hold = _panda().checks.keyframe_hold
    copied = hold.model_copy(update={"steps": 7})
    assert copied.steps == 7 and hold.steps != 7
    assert "steps" in copied.model_fields_set and "steps" not in hold.model_fields_set
    assert copied != hold and copied.model_copy(update={"steps": hold.steps}) == hold


def test_records_dump_compare_hash_and_pickle_as_pydantic_models_do() -> None:
    spec = _panda()
    loaded = _loaded(PANDA_SPEC)
    assert loaded is not None
    assert spec.model_dump() == PydanticSpec.model_validate(_data(loaded)).model_dump()
    pose = frozen.Pose(p=[1, 2, 3])
    assert pose == frozen.Pose(p=[1.0, 2.0, 3.0]) and pose != frozen.Pose()
    assert hash(frozen.MimicTarget(joint="a")) == hash(frozen.MimicTarget(joint="a"))
    restored = pickle.loads(pickle.dumps(spec))
    assert restored == spec and restored.model_fields_set == spec.model_fields_set


def test_a_pickled_record_loads_in_a_fresh_process() -> None:
    code = (
        "import pickle, sys\n"
        "spec = pickle.loads(sys.stdin.buffer.read())\n"
        "print(type(spec).__module__, type(spec).__name__, spec.uid)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code],
        cwd=ROOT,
        input=pickle.dumps(_panda()),
        capture_output=True,
        check=True,
    )
    assert result.stdout.decode().split() == ["robospec.model.frozen", "Spec", "rs_panda"]


def test_required_fields_are_known_to_the_later_stages() -> None:
    fields = frozen.PDJointPosConfig.model_fields
    assert fields["stiffness"].is_required() and not fields["use_delta"].is_required()
    assert list(fields) == list(_pydantic_class("PDJointPosConfig").model_fields)


def test_what_a_type_checker_reads_in_frozen_is_the_model_each_record_is_frozen_from() -> None:
    # model/frozen.py declares, under TYPE_CHECKING, each record it is imported for as the
    # pydantic model of that name: so that holds only while the two have the same fields
    tree = ast.parse(Path(frozen.__file__).read_text(encoding="utf-8"))
    declared = {
        alias.asname or alias.name: node.module
        for block in tree.body
        if isinstance(block, ast.If) and ast.unparse(block.test) == "TYPE_CHECKING"
        for node in block.body
        if isinstance(node, ast.ImportFrom)
        for alias in node.names
    }
    assert declared, "no TYPE_CHECKING declarations found in model/frozen.py"
    models = {model.__name__: model for model in model_classes()}
    for name, module in declared.items():
        model = models[name]
        assert model.__module__ == module
        assert set(frozen.RECORDS[name].model_fields) == set(model.model_fields), name
