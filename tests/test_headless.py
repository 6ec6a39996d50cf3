"""headless_loading(): any robot loads without a render device, with unchanged physics."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT

from robospec.maniskill.headless import (
    headless_loading,
    make_empty_env,
    strip_urdf_visuals,
)

pytestmark = pytest.mark.minutes  # CI starts it first (tests/conftest.py)

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


# -- the patches come and go; the process-wide fallback stays -----------------------------------
# In a fresh process: another test of this session may have installed the process-wide fallback
# (robospec.register does), after which no block changes anything.

PATCHES_COME_AND_GO = """
import mani_skill.envs, sapien
from robospec.maniskill import render_fallback
from robospec.maniskill.headless import headless_loading, is_active

def targets():
    import importlib
    urdf = importlib.import_module("sapien.wrapper.urdf_loader")
    mjcf = importlib.import_module("mani_skill.utils.building._mjcf_loader")
    return {
        "urdf_parse": urdf.URDFLoader.__dict__["_parse_urdf"],
        "mjcf_parse": mjcf.MJCFLoader.__dict__["_parse_mjcf"],
        "render_material": mjcf.RenderMaterial,
        "render_texture": mjcf.RenderTexture2D,
        "sapien_material": sapien.render.RenderMaterial,
    }

before = targets()
assert not render_fallback.installed() and not is_active()
with headless_loading():
    during = targets()
    assert is_active() and all(during[k] is not before[k] for k in before)
    with headless_loading():
        assert targets() == during
    assert targets() == during and is_active()  # the outer block's patches stay
assert targets() == before and not is_active()
try:
    with headless_loading():
        raise RuntimeError("boom")
except RuntimeError:
    pass
assert targets() == before
if render_fallback.render_device_available():
    assert not render_fallback.install() and targets() == before  # visuals load as before
else:
    assert render_fallback.install() and render_fallback.install()  # idempotent
    installed = targets()
    assert all(installed[k] is not before[k] for k in before)
    with headless_loading():
        assert targets() == installed
    assert targets() == installed  # a block ends, the process-wide fallback stays
print("ok")
"""


@pytest.mark.usefixtures("maniskill")
def test_patches_come_and_go_with_blocks_and_the_process_wide_fallback_stays() -> None:
    result = subprocess.run(
        [sys.executable, "-c", PATCHES_COME_AND_GO],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0 and result.stdout.strip() == "ok", result.stderr[-3000:]


def test_strip_urdf_visuals_keeps_every_other_element_on_its_line() -> None:
    # SAPIEN parses the stripped text: an element it chokes on is then reported at its line in
    # the user's file (robospec.maniskill.crash reads the line from the parser's element)
    from lxml import etree

    original = TREE_URDF.read_text()
    stripped = strip_urdf_visuals(original)
    assert "<visual" in original and "<visual" not in stripped

    def lines(text: str) -> list[tuple[str, str | None, int]]:
        root = etree.fromstring(text.encode())
        return [
            (str(e.tag), e.get("name"), e.sourceline)
            for e in root.iter()
            if isinstance(e.tag, str)
            and not any(a.tag == "visual" for a in e.iterancestors())
            and e.tag != "visual"
        ]

    assert lines(stripped) == lines(original)


# -- headless for real: plain gym.make, where SAPIEN finds no rendering device ---------------------


def _python(code: str, cache: Path, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    """``code`` in a fresh Python, as a user runs it (robospec's cache in ``cache``)."""
    import os

    return subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=600,
        check=False,
        env={**os.environ, "ROBOSPEC_CACHE_DIR": str(cache)},
    )


def readme_python_usage() -> str:
    """The Python block of the README's "At import time" item, as written there."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("- At import time:", 1)[1]
    block = section.split("```python\n", 1)[1].split("```", 1)[0]
    return textwrap.dedent(block)


@pytest.mark.usefixtures("maniskill")
def test_the_readme_python_usage_runs_as_written_on_this_machine(tmp_path: Path) -> None:
    code = readme_python_usage()
    assert 'render_backend="none"' in code and "robospec.register(" in code
    result = _python(code + "\nprint('stepped', reward.shape)\n", tmp_path / "cache")
    assert result.returncode == 0, result.stderr[-4000:]
    assert "stepped" in result.stdout


NO_DEVICE = "failed to find a rendering device"
# fetch's URDF visuals carry <material>s: SAPIEN needs a rendering device to load them
MAKE_FETCH = (
    "import gymnasium as gym\n"
    "import mani_skill.envs\n"
    "{before}\n"
    "env = gym.make('Empty-v1', robot_uids='{uid}', obs_mode='state', sim_backend='physx_cpu',"
    " render_backend='none')\n"
    "env.reset(seed=0)\n"
    "env.step(env.action_space.sample())\n"
    "print('stepped {uid}')\n"
)


@pytest.mark.usefixtures("maniskill")
def test_a_registered_spec_loads_headless_with_a_plain_gym_make(tmp_path: Path) -> None:
    from robospec.maniskill.render_fallback import render_device_available

    fetch = ROOT / "specs" / "maniskill" / "fetch.yaml"
    registered = _python(
        MAKE_FETCH.format(
            before=f"import robospec; robospec.register({str(fetch)!r})", uid="rs_fetch"
        ),
        tmp_path / "cache",
    )
    assert registered.returncode == 0, registered.stderr[-4000:]
    assert "stepped rs_fetch" in registered.stdout
    if not render_device_available():
        # without robospec, ManiSkill's own fetch does not load here: the fallback is what works
        plain = _python(MAKE_FETCH.format(before="", uid="fetch"), tmp_path / "cache")
        assert plain.returncode != 0 and NO_DEVICE in plain.stderr


def test_a_built_package_carries_the_fallback_as_robospec_has_it(tmp_path: Path) -> None:
    import ast

    from robospec.emit.package import HEADLESS_MODULE
    from robospec.output.package import plan_package
    from robospec.pipeline import compile_spec

    files = plan_package([compile_spec(ROOT / "specs" / "twolink.toml")], tmp_path / "agents")
    source = (ROOT / "robospec" / "maniskill" / "render_fallback.py").read_text()
    header, copy = files[f"{HEADLESS_MODULE}.py"].split("\n", 1)
    assert copy == source and header.startswith("# generated by robospec")
    # it needs nothing from robospec: a built package works where robospec is not installed.
    # The one import of robospec is guard_loading's, which does nothing where it fails
    tree = ast.parse(source)
    optional = {
        id(node)
        for handler in ast.walk(tree)
        if isinstance(handler, ast.Try)
        and any(
            isinstance(h.type, ast.Name) and h.type.id == "ImportError" for h in handler.handlers
        )
        for statement in handler.body
        for node in ast.walk(statement)
    }
    imported = {
        (node.module or "") if isinstance(node, ast.ImportFrom) else alias.name
        for node in ast.walk(tree)
        if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in optional
        for alias in node.names
    }
    assert not any(name.split(".")[0] == "robospec" for name in imported), imported
    assert f"from . import {HEADLESS_MODULE}" in files["__init__.py"]
    assert f"{HEADLESS_MODULE}.install()" in files["__init__.py"]
    assert f"{HEADLESS_MODULE}.guard_loading(AGENTS.values())" in files["__init__.py"]


WITHOUT_ROBOSPEC = (
    "import sys\n"
    "class NoRobospec:\n"
    "    def find_spec(self, name, path, target=None):\n"
    "        if name.split('.')[0] == 'robospec':\n"
    "            raise ImportError('robospec is not installed here')\n"
    "sys.meta_path.insert(0, NoRobospec())\n"
    "sys.path.insert(0, {folder!r})\n"
    "import agents\n"
)


@pytest.mark.usefixtures("maniskill")
def test_a_built_package_loads_headless_where_robospec_is_not_installed(tmp_path: Path) -> None:
    out = tmp_path / "agents"
    built = subprocess.run(
        [
            sys.executable,
            "-m",
            "robospec.cli",
            "build",
            "specs/maniskill/fetch.yaml",
            "-o",
            str(out),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert built.returncode == 0, built.stdout + built.stderr
    code = MAKE_FETCH.format(before=WITHOUT_ROBOSPEC.format(folder=str(tmp_path)), uid="rs_fetch")
    code += "assert not any(m.split('.')[0] == 'robospec' for m in sys.modules)\n"
    result = _python(code, tmp_path / "cache", cwd=tmp_path)
    assert result.returncode == 0, result.stderr[-4000:]
    assert "stepped rs_fetch" in result.stdout
