"""headless_loading(): any robot loads without a render device, with unchanged physics."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT

from robospec.maniskill.headless import (
    headless_loading,
    is_active,
    make_empty_env,
    strip_urdf_visuals,
)

TREE_URDF = Path(__file__).parent / "data" / "tree.urdf"


def test_strip_urdf_visuals_removes_link_visuals_only() -> None:
    text = (
        '<robot name="r"><link name="a"><visual><geometry><box size="1 1 1"/></geometry>'
        '<material name="m"><color rgba="1 0 0 1"/></material></visual>'
        '<collision><geometry><box size="1 1 1"/></geometry></collision></link>'
        '<gazebo reference="a"><visual>kept</visual></gazebo></robot>'
    )
    stripped = strip_urdf_visuals(text)
    assert "<material" not in stripped
    assert "<collision>" in stripped
    assert "<visual>kept</visual>" in stripped


def test_strip_urdf_visuals_leaves_text_without_visuals_or_malformed_text_alone() -> None:
    assert strip_urdf_visuals('<robot name="r"><link name="a"/></robot>') == (
        '<robot name="r"><link name="a"/></robot>'
    )
    assert strip_urdf_visuals("<robot><link>") == "<robot><link>"


def test_strip_urdf_visuals_keeps_every_link_and_joint_of_a_urdf() -> None:
    from robospec.description.urdf import parse_urdf

    original, _ = parse_urdf(TREE_URDF.read_text(), "tree.urdf")
    stripped, _ = parse_urdf(strip_urdf_visuals(TREE_URDF.read_text()), "tree.urdf")
    assert original is not None and stripped is not None
    assert original.link_names == stripped.link_names
    # Lines move (the text before <robot> and the visuals are gone); nothing else may.
    assert [replace(j, line=0) for j in original.joints] == [
        replace(j, line=0) for j in stripped.joints
    ]


def test_importing_headless_module_imports_neither_sapien_nor_mani_skill() -> None:
    code = (
        "import sys\n"
        "import robospec.maniskill.headless\n"
        "assert 'sapien' not in sys.modules and 'mani_skill' not in sys.modules\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=False
    )
    assert result.returncode == 0, result.stderr


# -- with ManiSkill --------------------------------------------------------------------------------


def _make_env(uid: str, control_mode: str | None = None) -> Any:
    # callers choose whether the headless patches are in place
    return make_empty_env(uid, control_mode, headless=False)


def _patch_targets() -> dict[str, Any]:
    import importlib

    urdf_module = importlib.import_module("sapien.wrapper.urdf_loader")
    mjcf_module = importlib.import_module("mani_skill.utils.building._mjcf_loader")
    return {
        "urdf_parse": urdf_module.URDFLoader.__dict__["_parse_urdf"],
        "mjcf_parse": mjcf_module.MJCFLoader.__dict__["_parse_mjcf"],
        "render_material": mjcf_module.RenderMaterial,
        "render_texture": mjcf_module.RenderTexture2D,
    }


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("uid", ["fetch", "humanoid", "panda"])
def test_headless_loading_lets_robots_load_without_a_render_device(uid: str) -> None:
    import mani_skill.envs  # noqa: F401

    with headless_loading():
        env = _make_env(uid)
    try:
        env.reset(seed=0)
        robot = env.unwrapped.agent.robot
        assert len(robot.active_joints) == {"fetch": 15, "humanoid": 21, "panda": 9}[uid]
        env.step(env.action_space.sample())
    finally:
        env.close()


def _rollout(steps: int = 50) -> list[Any]:
    import numpy as np
    import torch

    env = _make_env("panda", control_mode="pd_joint_delta_pos")
    try:
        observation, _ = env.reset(seed=7)
        rng = np.random.default_rng(1234)
        trajectory = [observation.clone()]
        low, high = env.action_space.low, env.action_space.high
        for _ in range(steps):
            action = torch.as_tensor(rng.uniform(low, high), dtype=torch.float32)
            observation, *_ = env.step(action)
            qpos = env.unwrapped.agent.robot.get_qpos()
            trajectory.append(torch.cat([observation.flatten(), qpos.flatten()]).clone())
        return trajectory
    finally:
        env.close()


@pytest.mark.usefixtures("maniskill")
def test_panda_rollout_is_bit_identical_with_and_without_headless_loading() -> None:
    import mani_skill.envs  # noqa: F401
    import torch

    plain = _rollout()
    with headless_loading():
        headless = _rollout()
    assert len(plain) == len(headless) == 51
    for step, (a, b) in enumerate(zip(plain, headless, strict=True)):
        assert torch.equal(a, b), f"step {step} differs"
    # The rollout moved the robot: equality is not two idle arms.
    assert not torch.equal(plain[1], plain[-1])


@pytest.mark.usefixtures("maniskill")
def test_patches_are_gone_after_the_block_even_after_an_error() -> None:
    import mani_skill.envs  # noqa: F401
    import sapien

    before = _patch_targets()
    assert before["render_material"] is sapien.render.RenderMaterial
    assert not is_active()
    with headless_loading():
        assert is_active()
        during = _patch_targets()
        assert all(during[key] is not before[key] for key in before)
    assert _patch_targets() == before
    assert not is_active()

    with pytest.raises(RuntimeError), headless_loading():
        raise RuntimeError("boom")
    assert _patch_targets() == before


@pytest.mark.usefixtures("maniskill")
def test_headless_loading_is_reentrant() -> None:
    import mani_skill.envs  # noqa: F401

    before = _patch_targets()
    with headless_loading():
        during = _patch_targets()
        with headless_loading():
            assert _patch_targets() == during
        # Leaving the inner block keeps the outer block's patches.
        assert _patch_targets() == during
        assert is_active()
    assert _patch_targets() == before
