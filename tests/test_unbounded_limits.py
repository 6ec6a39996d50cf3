"""Every bound ManiSkill accepts: an infinite limit (``.inf``/``-.inf`` in YAML, ``inf`` in
TOML) validates, is written ``np.inf`` as ManiSkill's agents write it, and registers and steps;
NaN is no number at all."""

from __future__ import annotations

import math
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest
from conftest import POSITIVE_SPECS

from robospec.output.modules import robot_files
from robospec.pipeline import compile_spec

SPEC = POSITIVE_SPECS / "unbounded_ee_pose.yaml"


def test_infinite_bounds_validate_and_are_written_as_numpy_writes_them(tmp_path: Path) -> None:
    result = compile_spec(SPEC)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    arm = next(c for c in result.robot.controllers if c.name == "arm")
    kwargs = dict(arm.kwargs)
    assert kwargs["pos_lower"] == -math.inf and kwargs["pos_upper"] == math.inf
    (text,) = [
        t for n, t in robot_files(result.robot, "rs_inf", tmp_path).items() if n.endswith(".py")
    ]
    assert "pos_lower=-np.inf," in text and "pos_upper=np.inf," in text


@pytest.mark.parametrize(
    ("written", "code", "message"),
    [
        (".nan", "RS102", "expected a number, got NaN"),
        (".NaN", "RS102", "expected a number, got NaN"),
        # arithmetic must come out finite: an infinite bound is written as a literal
        ("1e999 - 1e999", "RS010", "'1e999 - 1e999' is not a finite number"),
    ],
)
def test_nan_is_no_number(tmp_path: Path, written: str, code: str, message: str) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC.read_text().replace("pos_lower: -.inf", f"pos_lower: {written}"))
    errors = [d for d in compile_spec(spec).diagnostics if d.is_error]
    assert [(d.code, d.message) for d in errors] == [
        (code, f"{message} in 'controllers.arm.pos_lower'")
    ]


@pytest.fixture(scope="module")
def agent_class(maniskill: ModuleType, tmp_path_factory: pytest.TempPathFactory) -> Iterator[type]:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    import robospec

    ((uid, cls),) = robospec.register(SPEC, cache_dir=tmp_path_factory.mktemp("cache")).items()
    try:
        yield cls
    finally:
        REGISTERED_AGENTS.pop(uid, None)
        sys.modules.pop(cls.__module__, None)


def test_an_unbounded_ee_pose_controller_registers_and_steps(agent_class: type) -> None:
    import numpy as np

    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(agent_class.uid, "pd_ee_pose")
    try:
        env.reset(seed=0)
        space = env.unwrapped.single_action_space
        assert np.isinf(space.low[:3]).all() and np.isinf(space.high[:3]).all()
        tcp = env.unwrapped.agent.robot.links_map["panda_hand_tcp"].pose.p[0].numpy()
        action = np.zeros(space.shape, dtype=np.float32)
        action[:3] = tcp  # hold the hand where it is: an absolute target
        action[3:6] = 0
        for _ in range(3):
            obs, *_ = env.step(action)
        assert np.isfinite(np.asarray(obs)).all()
    finally:
        env.close()


@pytest.mark.parametrize("missing", ["stiffness", "damping", "ee_link"])
def test_the_fields_maniskill_requires_of_an_ee_controller_are_required(
    tmp_path: Path, missing: str
) -> None:
    # ManiSkill's PDEEPos(e)ControllerConfig has no default for them (nightly also makes
    # ee_link and urdf_path required; robospec always writes urdf_path)
    line = next(n for n in SPEC.read_text().splitlines() if n.startswith("  arm: {type"))
    kept = ", ".join(p for p in line.split(", ") if not p.startswith(f"{missing}:"))
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC.read_text().replace(line, kept))
    errors = [d for d in compile_spec(spec).diagnostics if d.is_error]
    assert [(d.code, d.location.line) for d in errors] == [("RS103", 10)], [
        d.format_text() for d in errors
    ]
    assert f"'{missing}'" in errors[0].message
