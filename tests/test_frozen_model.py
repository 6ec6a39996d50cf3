"""The frozen spec models (robospec/model/frozen.py) validate exactly as the pydantic models do.

`robospec validate`, `build` and `register` validate with the frozen pydantic-core schemas and
return record objects, so they never import pydantic. These tests hold the frozen module to
the pydantic models: it must be up to date and reproducible, and on every spec we ship or test
with, and on mutated ones, both must give the same errors (type, place, message) or the same
values, class for class.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st
from pydantic import BaseModel, ValidationError
from test_fuzz_properties import SEEDS, budget, mutated_data

from robospec.load.reader import read_spec
from robospec.model import core, freeze, frozen
from robospec.model.record import Record
from robospec.model.spec import Spec as PydanticSpec
from robospec.model.validate import SpecModelResult, _merge_extends

ROOT = Path(__file__).resolve().parent.parent


def _corpus() -> list[Path]:
    found: list[Path] = []
    for folder in ("specs", "tests/specs", "docs/examples"):
        for suffix in ("*.yaml", "*.toml"):
            found += sorted((ROOT / folder).rglob(suffix))
    return [p for p in found if b"robospec" in p.read_bytes()[:400]]


CORPUS = _corpus()


def _data(path: Path) -> Any:
    """The spec's data as the models get it: controllers' ``extends`` merged."""
    loaded, _ = read_spec(path)
    if loaded is None:
        pytest.skip(f"{path} does not load")
    data = dict(loaded.data)
    if isinstance(data.get("controllers"), dict):
        merged = _merge_extends(data["controllers"], loaded, SpecModelResult(None, []))
        data["controllers"] = merged
    return data


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
    return core.validator_for("Spec").validate_python(data)


# -- the frozen module is current and reproducible ---------------------------------------


def test_the_frozen_module_is_what_the_freezer_writes_for_the_models_as_they_are() -> None:
    assert freeze.FROZEN_PATH.read_text(encoding="utf-8") == freeze.frozen_source(), (
        "robospec/model/frozen.py is out of date: python -m robospec.model.freeze --write"
    )


def test_the_freezer_writes_the_same_module_under_any_hash_seed() -> None:
    digests = set()
    for seed in ("0", "1", "4242"):
        result = subprocess.run(
            [sys.executable, "-m", "robospec.model.freeze"],
            cwd=ROOT,
            env={**os.environ, "PYTHONHASHSEED": seed},
            capture_output=True,
            check=True,
        )
        digests.add(hashlib.sha256(result.stdout).hexdigest())
    assert len(digests) == 1


def test_the_freezer_writes_the_same_module_whatever_pydantic_built_before() -> None:
    # pydantic inlines nested models' schemas as it finds them: built, or not yet
    code = (
        "import sys\n"
        "from robospec.model.spec import Spec\n"
        "from robospec.model.controllers import PDJointPosMimicConfig\n"
        "Spec.model_json_schema()\n"
        "PDJointPosMimicConfig.model_rebuild(force=True)\n"
        "from robospec.model import freeze\n"
        "sys.stdout.write(freeze.frozen_source())\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    assert result.stdout == freeze.FROZEN_PATH.read_text(encoding="utf-8")


def test_the_freezer_refuses_a_function_the_frozen_module_cannot_name() -> None:
    with pytest.raises(freeze.FreezeError, match="cannot be frozen"):
        freeze._name(lambda: [0.0], "Pose.p.default_factory", {})


# -- it validates as pydantic does --------------------------------------------------------


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_spec_validates_to_the_same_values_or_errors_as_with_pydantic(path: Path) -> None:
    data = _data(path)
    assert _outcome(_frozen, data) == _outcome(_pydantic, data)


@given(st.sampled_from(SEEDS).flatmap(lambda p: mutated_data(_data(p))))
@budget(150)
def test_mutated_specs_validate_as_with_pydantic(data: dict[str, Any]) -> None:
    assert _outcome(_frozen, data) == _outcome(_pydantic, data)


def test_the_corpus_has_valid_and_invalid_specs_of_every_kind() -> None:
    # the comparison above means something only if both outcomes occur often
    outcomes = [_outcome(_frozen, _data(p))[0] for p in CORPUS]
    assert outcomes.count("valid") >= 40 and outcomes.count("invalid") >= 20, outcomes


def test_another_pydantic_core_gets_schemas_built_afresh_from_the_models(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(frozen, "PYDANTIC_CORE_VERSION", "0.0.0")
    core.validator_for.cache_clear()
    try:
        assert not core.frozen_schemas_usable()
        for path in CORPUS[::3]:
            data = _data(path)
            assert _outcome(_frozen, data) == _outcome(_pydantic, data), path
    finally:
        monkeypatch.undo()
        core.validator_for.cache_clear()


# -- records behave as frozen pydantic models ---------------------------------------------


def _panda() -> Any:
    return _frozen(_data(ROOT / "specs/maniskill/panda.yaml"))


def test_a_record_is_immutable() -> None:
    spec = _panda()
    with pytest.raises(TypeError, match="immutable"):
        spec.uid = "other"
    with pytest.raises(TypeError, match="immutable"):
        del spec.uid


def test_a_record_made_from_defaults_equals_pydantics() -> None:
    for name in ("Pose", "Checks", "Hooks", "Loader", "StepResponse"):
        record = getattr(frozen, name)()
        pydantic_class = next(c for c in freeze.model_classes() if c.__name__ == name)
        assert _shape(record) == _shape(pydantic_class())


def test_model_copy_replaces_fields_and_counts_them_as_given() -> None:
    hold = _panda().checks.keyframe_hold
    copied = hold.model_copy(update={"steps": 7})
    assert copied.steps == 7 and hold.steps != 7
    assert "steps" in copied.model_fields_set and "steps" not in hold.model_fields_set
    assert copied != hold and copied.model_copy(update={"steps": hold.steps}) == hold


def test_records_dump_compare_hash_and_pickle_as_pydantic_models_do() -> None:
    spec = _panda()
    assert (
        spec.model_dump()
        == PydanticSpec.model_validate(_data(ROOT / "specs/maniskill/panda.yaml")).model_dump()
    )
    pose = frozen.Pose(p=[1, 2, 3])
    assert pose == frozen.Pose(p=[1.0, 2.0, 3.0]) and pose != frozen.Pose()
    assert hash(frozen.MimicTarget(joint="a")) == hash(frozen.MimicTarget(joint="a"))
    restored = pickle.loads(pickle.dumps(spec))
    assert restored == spec and restored.model_fields_set == spec.model_fields_set


def test_required_fields_are_known_to_the_later_stages() -> None:
    fields = frozen.PDJointPosConfig.model_fields
    assert fields["stiffness"].is_required() and not fields["use_delta"].is_required()
    assert list(fields) == list(
        next(c for c in freeze.model_classes() if c.__name__ == "PDJointPosConfig").model_fields
    )
