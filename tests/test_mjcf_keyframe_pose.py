"""An MJCF robot's keyframe pose means what MuJoCo means (robospec.resolve.root_pose): the
world pose of the robot's root body, as its free joint's qpos in a ``<key>`` holds it; without
a pose, the body stands where the file puts it.

The robot is ManiSkill's humanoid with its torso back at dm_control's ``pos="0 0 1.5"`` (ManiSkill
moved it to the origin "for compatibility with maniskill articulation set_root_pose", as its file
says) and a ``<key>`` that stands it at 1.3 m: registered from a spec, made in ``Empty-v1`` and
set to each keyframe, its torso is where MuJoCo would put it."""

from __future__ import annotations

import importlib
import importlib.util
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import maniskill_assets

from robospec.description import load_description

pytestmark = pytest.mark.maniskill

UID = "rs_tall_humanoid"
JOINTS = 21
KEY = (
    '<keyframe>\n    <key name="stand" qpos="0 0 1.3 1 0 0 0' + " 0" * JOINTS + '"/>\n  </keyframe>'
)
SPEC = f"""robospec: 1
uid: {UID}
description: {{mjcf: humanoid.xml}}
loader: {{fix_root_link: false}}
groups:
  body: "*"
keyframes:
  stand:  # the MJCF's own <key name="stand">: the torso at 1.3 m
    pose: {{p: [0, 0, 1.3]}}
    qpos: {{body: 0}}
  as_drawn:  # no pose: the torso where the file puts it, 1.5 m
    qpos: {{body: 0}}
controllers:
  body: {{type: pd_joint_pos, joints: body, lower: null, upper: null, stiffness: 100, damping: 10,
         normalize_action: false}}
control_modes:
  pd_joint_pos: {{body: body, balance_passive_force: false}}
"""


def _humanoid_folder() -> Path:
    return maniskill_assets() / "robots" / "humanoid"


@pytest.fixture
def tall_humanoid(tmp_path: Path) -> Path:
    shutil.copytree(_humanoid_folder() / "common", tmp_path / "common")
    text = (_humanoid_folder() / "humanoid.xml").read_text()
    torso = '<body name="torso" pos="0 0 0" childclass="body">'
    assert torso in text
    text = text.replace(torso, torso.replace('pos="0 0 0"', 'pos="0 0 1.5"'))
    text = text.replace("</mujoco>", f"  {KEY}\n</mujoco>")
    (tmp_path / "humanoid.xml").write_text(text)
    (tmp_path / "humanoid.yaml").write_text(SPEC)
    return tmp_path


@pytest.fixture
def registered(tall_humanoid: Path) -> Iterator[type]:
    import robospec

    registry = importlib.import_module("mani_skill.agents.registration").REGISTERED_AGENTS
    agents = robospec.register(tall_humanoid / "humanoid.yaml", cache_dir=tall_humanoid / "cache")
    try:
        yield agents[UID]
    finally:
        cls = registry.pop(UID).agent_cls
        sys.modules.pop(cls.__module__, None)


def _torso_height(agent: Any, keyframe: str) -> float:
    frame = agent.keyframes[keyframe]
    agent.robot.set_pose(frame.pose)
    agent.robot.set_qpos(frame.qpos)
    return float(agent.robot.links_map["torso"].pose.p[0, 2])


def test_the_files_key_is_the_root_body_pose(tall_humanoid: Path) -> None:
    description, _ = load_description(str(tall_humanoid / "humanoid.xml"), "mjcf")
    assert description is not None
    (stand,) = description.keyframes
    assert stand.root_pose == ((0.0, 0.0, 1.3), (1.0, 0.0, 0.0, 0.0))
    assert description.root_body_pose == ((0.0, 0.0, 1.5), (1.0, 0.0, 0.0, 0.0))


@pytest.mark.usefixtures("registered")
def test_a_floating_mjcf_robot_stands_where_the_mjcf_says() -> None:
    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(UID)
    try:
        agent = env.unwrapped.agent  # type: ignore[attr-defined]
        # the root link goes to 1.3 - 1.5: the torso hangs 1.5 m below it in ManiSkill's load
        assert list(agent.keyframes["stand"].pose.p) == pytest.approx([0.0, 0.0, -0.2])
        assert _torso_height(agent, "stand") == pytest.approx(1.3, abs=1e-5)
        assert _torso_height(agent, "as_drawn") == pytest.approx(1.5, abs=1e-5)
    finally:
        env.close()
