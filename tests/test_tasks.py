"""ManiSkill's own tasks run the same with the spec-built panda standing in for ``panda``.

Table-top tasks choose the robot's start pose by uid string, so the spec is registered over
ManiSkill's ``panda`` on purpose (``register(..., override=...)``). Each task is run twice under
the same seed and actions — once with ManiSkill's hand-written Panda, once with the spec-built
one — and observations, rewards, terminations and every ``info`` entry must be equal, step for
step. Besides random actions, a grasp scenario puts the cube between the open fingers and closes
them, so ``is_grasping``, ``tcp_pose`` and ``is_static`` are exercised with real contacts (the
test first checks that the hand-written agent really does grasp, so it cannot pass vacuously).
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
import torch
from maniskill_compare import MANISKILL_SPECS, assert_same_value

import robospec
from robospec.maniskill.headless import headless_loading

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore:__array_wrap__ must accept context:DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
]

TASKS = ["PickCube-v1", "PushCube-v1", "StackCube-v1", "PullCube-v1"]
SEED = 7
STEPS = 25
GRASP_STEPS = 15
# the object each grasp scenario places between the fingers
GRASPED = {"PickCube-v1": "cube", "StackCube-v1": "cubeA"}


def _make(task: str) -> Any:
    with headless_loading():
        env = gym.make(
            task,
            robot_uids="panda",
            obs_mode="state_dict",
            sim_backend="physx_cpu",
            render_backend="none",
            control_mode="pd_joint_delta_pos",
        )
        env.reset(seed=SEED)
    return env


def _snapshot(value: Any) -> Any:
    """A deep copy of observations/info with tensors as numpy arrays."""
    if isinstance(value, dict):
        return {k: _snapshot(v) for k, v in value.items()}
    if isinstance(value, torch.Tensor):
        return value.detach().cpu().numpy().copy()
    return value


def _episode(task: str, actions: np.ndarray, grasp: bool) -> list[Any]:
    env = _make(task)
    try:
        with headless_loading():
            obs, info = env.reset(seed=SEED)
        record = [("reset", _snapshot(obs), _snapshot(info))]
        agent = env.unwrapped.agent
        if grasp:
            target = getattr(env.unwrapped, GRASPED[task])
            target.set_pose(agent.tcp.pose)  # between the open fingers
        for step, action in enumerate(actions):
            obs, reward, terminated, truncated, info = env.step(torch.as_tensor(action))
            extra = {}
            if grasp:
                target = getattr(env.unwrapped, GRASPED[task])
                extra = {
                    "is_grasping": _snapshot(agent.is_grasping(target)),
                    "tcp_pose": _snapshot(agent.tcp_pose.raw_pose),
                    "tcp_pos": _snapshot(agent.tcp_pos),
                    "is_static": _snapshot(agent.is_static()),
                }
            record.append(
                (
                    step,
                    _snapshot(obs),
                    _snapshot(reward),
                    _snapshot(terminated),
                    _snapshot(truncated),
                    _snapshot(info),
                    extra,
                )
            )
        return record
    finally:
        env.close()


def _actions(task: str, grasp: bool) -> np.ndarray:
    env = _make(task)
    try:
        space = env.action_space
        if grasp:  # hold the arm, close the gripper (last action entry)
            actions = np.zeros((GRASP_STEPS, *space.shape), dtype=np.float32)
            actions[..., -1] = -1.0
            return actions
        space.seed(SEED)
        return np.stack([space.sample() for _ in range(STEPS)])
    finally:
        env.close()


@pytest.fixture(scope="module")
def upstream_and_spec_runs(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict]:
    """Every scenario run with ManiSkill's panda, then with the spec's panda standing in."""
    from mani_skill.agents.registration import REGISTERED_AGENTS

    scenarios = [(task, False) for task in TASKS] + [(task, True) for task in GRASPED]
    actions = {s: _actions(*s) for s in scenarios}
    theirs = {s: _episode(s[0], actions[s], s[1]) for s in scenarios}

    folder = tmp_path_factory.mktemp("standin")
    spec = (MANISKILL_SPECS / "panda.yaml").read_text(encoding="utf-8")
    assert "uid: rs_panda\n" in spec
    (folder / "panda.yaml").write_text(spec.replace("uid: rs_panda\n", "uid: panda\n"))
    original = REGISTERED_AGENTS["panda"]
    try:
        agents = robospec.register(
            folder, cache_dir=tmp_path_factory.mktemp("cache"), override={"panda"}
        )
        assert REGISTERED_AGENTS["panda"].agent_cls is agents["panda"]
        assert agents["panda"] is not original.agent_cls
        ours = {s: _episode(s[0], actions[s], s[1]) for s in scenarios}
        yield {"theirs": theirs, "ours": ours}
    finally:
        REGISTERED_AGENTS["panda"] = original
        for name in [m for m in sys.modules if m.startswith("robospec_agents.")]:
            del sys.modules[name]


@pytest.mark.parametrize("task", TASKS)
def test_task_gives_the_same_observations_rewards_and_info_with_the_spec_built_panda(
    task: str, upstream_and_spec_runs: dict
) -> None:
    theirs = upstream_and_spec_runs["theirs"][(task, False)]
    ours = upstream_and_spec_runs["ours"][(task, False)]
    assert len(ours) == len(theirs) == STEPS + 1
    for mine, upstream in zip(ours, theirs, strict=True):
        assert_same_value(mine, upstream, f"{task} step {upstream[0]}")


@pytest.mark.parametrize("task", sorted(GRASPED))
def test_grasp_helpers_give_the_same_numbers_as_the_hand_written_panda(
    task: str, upstream_and_spec_runs: dict
) -> None:
    theirs = upstream_and_spec_runs["theirs"][(task, True)]
    ours = upstream_and_spec_runs["ours"][(task, True)]
    grasped = [bool(step[-1]["is_grasping"].any()) for step in theirs[1:]]
    assert any(grasped), "the scenario must really grasp with ManiSkill's panda"
    assert not all(grasped), "and start from not grasping"
    for mine, upstream in zip(ours, theirs, strict=True):
        assert_same_value(mine, upstream, f"{task} grasp step {upstream[0]}")


def test_spec_override_replaces_only_on_purpose(tmp_path: Path) -> None:
    """Without override, taking ManiSkill's uid is refused before anything is registered."""
    spec = (MANISKILL_SPECS / "panda.yaml").read_text(encoding="utf-8")
    (tmp_path / "panda.yaml").write_text(spec.replace("uid: rs_panda\n", "uid: panda\n"))
    with pytest.raises(robospec.SpecError) as raised:
        robospec.register(tmp_path, cache_dir=tmp_path / "cache")
    assert [d.code for d in raised.value.diagnostics] == ["RS306"]
    assert "override: true" in (raised.value.diagnostics[0].hint or "")
