"""A spec's touch sensors read what ManiSkill's tactile Allegro hand reads.

specs/maniskill/allegro_hand_right_touch.yaml declares the hand's force-sensing links under
``touch:`` (no ``extends``). RotateSingleObjectInHandLevel0-v1 loads the robot it names itself
(``allegro_hand_right_touch``), so the spec's agent stands in for ManiSkill's under that uid
(``override: true``), and both take the same random actions from the same seed: their
``get_fsr_impulse()``, ``get_fsr_obj_impulse(obj)`` and proprioception must be equal at every
step, on the CPU (the GPU path runs on a machine with CUDA: tests/gpu/).
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore:__array_wrap__ must accept context:DeprecationWarning"),
]

SPEC = Path(__file__).resolve().parent.parent / "specs/maniskill/allegro_hand_right_touch.yaml"
TASK = "RotateSingleObjectInHandLevel0-v1"
UPSTREAM = "allegro_hand_right_touch"
STEPS, SEED = 12, 3


def _readings(steps: int) -> list[dict[str, Any]]:
    """The sensors' readings after each of ``steps`` random steps of the task."""
    import gymnasium as gym
    import torch

    from robospec.maniskill.headless import headless_loading

    with headless_loading():
        env = gym.make(TASK, obs_mode="state_dict", sim_backend="physx_cpu", render_backend="none")
    try:
        env.reset(seed=SEED)
        env.action_space.seed(SEED)
        agent, obj = env.unwrapped.agent, env.unwrapped.obj
        out = []
        for _ in range(steps):
            env.step(torch.as_tensor(env.action_space.sample()))
            proprioception = agent.get_proprioception()
            out.append(
                {
                    "impulse": np.asarray(agent.get_fsr_impulse()),
                    "obj_impulse": np.asarray(agent.get_fsr_obj_impulse(obj)),
                    "proprioception": {k: np.asarray(v) for k, v in proprioception.items()},
                }
            )
        return out
    finally:
        env.close()


@pytest.fixture
def registrations(tmp_path: Path) -> Any:
    """ManiSkill's registration of the tactile hand and the spec's under the same uid; the
    registry as it was afterwards."""
    import robospec

    registry = importlib.import_module("mani_skill.agents.registration").REGISTERED_AGENTS
    upstream = registry[UPSTREAM]
    text = SPEC.read_text(encoding="utf-8").replace(
        "uid: rs_allegro_hand_right_touch", f"uid: {UPSTREAM}\noverride: true"
    )
    spec = tmp_path / SPEC.name
    spec.write_text(text, encoding="utf-8")
    agents = robospec.register(str(spec), cache_dir=tmp_path / "cache")
    try:
        yield registry, upstream, registry[UPSTREAM]
    finally:
        registry[UPSTREAM] = upstream
        for cls in agents.values():
            sys.modules.pop(cls.__module__, None)


def test_touch_readings_equal_maniskill_tactile_hand_over_random_steps(registrations: Any) -> None:
    registry, upstream, spec = registrations
    assert spec.agent_cls is not upstream.agent_cls
    ours = _readings(STEPS)
    registry[UPSTREAM] = upstream
    theirs = _readings(STEPS)
    touched = 0
    for step, (mine, expected) in enumerate(zip(ours, theirs, strict=True)):
        assert mine["impulse"].shape == (1, 16, 3), step
        np.testing.assert_array_equal(mine["impulse"], expected["impulse"], err_msg=f"{step}")
        np.testing.assert_array_equal(mine["obj_impulse"], expected["obj_impulse"])
        assert list(mine["proprioception"]) == list(expected["proprioception"])
        for key, value in mine["proprioception"].items():
            np.testing.assert_array_equal(value, expected["proprioception"][key], err_msg=key)
        touched += int(np.abs(expected["obj_impulse"]).sum() > 0)
    assert touched, "the random steps never touched the object: the comparison proves nothing"
