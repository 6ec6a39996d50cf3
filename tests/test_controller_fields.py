"""The controller kinds (robospec.model.controller_kinds) and the spec's controller models against
each other and against the controller configs of the installed ManiSkill, on 3.0.1 and on the
nightly alike (which made ``ee_link`` and ``urdf_path`` required in the end-effector configs):

- the registry names each config class where the generated modules import it from, lists
  exactly the fields the config takes, states its defaults and the drive targets its controller
  sets as ManiSkill has them;
- every field ManiSkill requires (no default) is required by the spec too or written by robospec
  itself, and every field a spec can write is one the config takes."""

from __future__ import annotations

import dataclasses
import importlib
import typing

import pytest

from robospec.model.controller_kinds import (
    CONFIG_MODULE,
    CONTROLLER_KINDS,
    CONTROLLER_TYPES,
    FIELD_ORDER,
    ControllerKind,
    controller_kind,
    kind_of_config,
)
from robospec.model.controllers import ControllerConfig

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
KINDS = pytest.mark.parametrize("kind", CONTROLLER_KINDS, ids=CONTROLLER_TYPES)


def _config_class(kind: ControllerKind) -> type:
    return getattr(importlib.import_module(CONFIG_MODULE), kind.config_class)


def _maniskill_fields(kind: ControllerKind) -> dict[str, dataclasses.Field]:
    return {field.name: field for field in dataclasses.fields(_config_class(kind)) if field.init}


def _required(field: dataclasses.Field) -> bool:
    return field.default is dataclasses.MISSING and field.default_factory is dataclasses.MISSING


# -- the registry and the spec's models (no ManiSkill needed) --------------------------------


def test_every_controller_kind_has_a_model_in_the_registrys_order() -> None:
    # the registry's order is the one the schema's union and the hints list them in
    assert list(MODELS) == list(CONTROLLER_TYPES)


def test_each_kind_is_found_by_its_name_and_by_its_config_class() -> None:
    for kind in CONTROLLER_KINDS:
        assert controller_kind(kind.name) is kind
        assert kind_of_config(kind.config_class) is kind
    assert kind_of_config("DictController") is None


@KINDS
def test_every_spec_field_is_one_the_registry_lists(kind: ControllerKind) -> None:
    spec_fields = {RENAMED.get(name, name) for name in MODELS[kind.name].model_fields}
    assert spec_fields - SPEC_ONLY <= {"joint_names", *kind.fields}


@KINDS
def test_the_fields_the_registry_reads_are_the_kinds_own(kind: ControllerKind) -> None:
    bounds = {name for part in kind.action for name in (part.lower, part.upper)}
    assert bounds | set(kind.defaults) | set(kind.per_joint) | set(kind.gains) <= set(kind.fields)
    # robospec writes every field in one order: each must have its place in it
    assert set(kind.fields) <= set(FIELD_ORDER)


def test_the_kinds_facts_as_the_consumers_ask_them() -> None:
    """Which kinds count as what: a flipped fact in a record shows here by name."""

    def kinds(fact: typing.Callable[[ControllerKind], object]) -> set[str]:
        return {kind.name for kind in CONTROLLER_KINDS if fact(kind)}

    joint_positions = {"pd_joint_pos", "pd_joint_pos_mimic", "pd_joint_pos_vel"}
    assert kinds(lambda k: k.joint_position_targets) == joint_positions
    assert kinds(lambda k: k.end_effector) == {"pd_ee_pos", "pd_ee_pose"}
    assert kinds(lambda k: k.mimic) == {"pd_joint_pos_mimic"}
    assert kinds(lambda k: k.min_joints) == {"pd_base_vel", "pd_base_forward_vel"}
    assert kinds(lambda k: not k.action) == {"passive"}
    assert kinds(lambda k: k.sets_target_qpos and k.sets_target_qvel) == {"pd_joint_pos_vel"}
    assert controller_kind("pd_ee_pose").axis_names == ("x", "y", "z", "rx", "ry", "rz")
    forward = controller_kind("pd_base_forward_vel")
    assert [forward.axes_bounded_by(f) for f in ("lower", "upper")] == [("v", "wz")] * 2
    assert "lower" not in forward.per_joint and "damping" in forward.per_joint
    # pos_lower bounds x, y, z but is no per-joint field: it is left as written
    assert controller_kind("pd_ee_pos").axes_bounded_by("pos_lower") == ()
    assert controller_kind("pd_joint_vel").gains == ("damping", "force_limit", "friction")


# -- the registry and the installed ManiSkill --------------------------------------------------


@pytest.mark.usefixtures("maniskill")
@KINDS
def test_the_config_class_is_a_maniskill_config_where_the_generated_modules_import_it(
    kind: ControllerKind,
) -> None:
    from mani_skill.agents.controllers.base_controller import ControllerConfig as Base

    config = _config_class(kind)
    assert dataclasses.is_dataclass(config) and issubclass(config, Base)
    assert config.__name__ == kind.config_class


@pytest.mark.usefixtures("maniskill")
@KINDS
def test_the_registry_lists_exactly_the_fields_of_the_installed_config(
    kind: ControllerKind,
) -> None:
    assert set(kind.fields) == set(_maniskill_fields(kind)) - {"joint_names"}


@pytest.mark.usefixtures("maniskill")
@KINDS
def test_the_registry_states_the_installed_configs_defaults(kind: ControllerKind) -> None:
    fields = _maniskill_fields(kind)
    assert {name: fields[name].default for name in kind.defaults} == dict(kind.defaults)


@pytest.mark.usefixtures("maniskill")
@KINDS
def test_the_registry_says_which_drive_targets_the_controller_sets(kind: ControllerKind) -> None:
    controller = _config_class(kind).controller_cls
    assert (kind.sets_target_qpos, kind.sets_target_qvel) == (
        controller.sets_target_qpos,
        controller.sets_target_qvel,
    )


@pytest.mark.usefixtures("maniskill")
@KINDS
def test_the_spec_requires_what_the_installed_maniskill_requires(kind: ControllerKind) -> None:
    required_here = {name for name, f in _maniskill_fields(kind).items() if _required(f)}
    spec_required = {
        RENAMED.get(name, name)
        for name, field in MODELS[kind.name].model_fields.items()
        if field.is_required()
    }
    assert required_here - WRITTEN_BY_ROBOSPEC <= spec_required


@pytest.mark.usefixtures("maniskill")
@KINDS
def test_every_spec_field_is_one_the_installed_maniskill_takes(kind: ControllerKind) -> None:
    spec_fields = {RENAMED.get(name, name) for name in MODELS[kind.name].model_fields} - SPEC_ONLY
    assert spec_fields <= set(_maniskill_fields(kind))
