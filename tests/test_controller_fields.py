"""The spec's controller fields against the controller configs of the installed ManiSkill: every
field ManiSkill requires (no default) is required by the spec too or written by robospec itself,
and every field a spec can write is one this ManiSkill's config takes — on 3.0.1 and on the
nightly alike (which made ``ee_link`` and ``urdf_path`` required in the end-effector configs)."""

from __future__ import annotations

import dataclasses
import typing

import pytest

from robospec.emit.controllers import CONFIG_CLASSES
from robospec.model.controllers import ControllerConfig

pytestmark = pytest.mark.maniskill

# the spec's names for ManiSkill's fields, and the fields robospec writes on its own: the joints
# from the spec's selection, the IK's URDF from the robot's description (unless the spec names one)
RENAMED = {"joints": "joint_names"}
WRITTEN_BY_ROBOSPEC = {"joint_names", "urdf_path"}
# what only the spec has: which controller it is
SPEC_ONLY = {"type"}
MODELS = {
    typing.get_args(model.model_fields["type"].annotation)[0]: model
    for model in typing.get_args(typing.get_args(ControllerConfig)[0])
}


def _maniskill_fields(kind: str) -> dict[str, dataclasses.Field]:
    import mani_skill.agents.controllers as controllers

    config = getattr(controllers, CONFIG_CLASSES[kind])
    return {field.name: field for field in dataclasses.fields(config) if field.init}


def _required(field: dataclasses.Field) -> bool:
    return field.default is dataclasses.MISSING and field.default_factory is dataclasses.MISSING


def test_every_controller_type_has_a_model() -> None:
    assert set(MODELS) == set(CONFIG_CLASSES)


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("kind", sorted(CONFIG_CLASSES))
def test_the_spec_requires_what_the_installed_maniskill_requires(kind: str) -> None:
    required_here = {name for name, f in _maniskill_fields(kind).items() if _required(f)}
    spec_required = {
        RENAMED.get(name, name)
        for name, field in MODELS[kind].model_fields.items()
        if field.is_required()
    }
    assert required_here - WRITTEN_BY_ROBOSPEC <= spec_required


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("kind", sorted(CONFIG_CLASSES))
def test_every_spec_field_is_one_the_installed_maniskill_takes(kind: str) -> None:
    spec_fields = {RENAMED.get(name, name) for name in MODELS[kind].model_fields} - SPEC_ONLY
    assert spec_fields <= set(_maniskill_fields(kind))
