"""A ManiSkill scene to load MJCF files into with ManiSkill's own loader, for the tests that
prove what that loader does (tests/test_mjcf_loader_gaps_sim.py, tests/test_mjcf_corpus.py).
Import ``scene_fixture`` into a test module to have the ``scene`` fixture."""

from __future__ import annotations

from collections.abc import Iterator
from itertools import count
from pathlib import Path
from typing import Any

import pytest

_names = count(1)


@pytest.fixture(scope="module", name="scene")
def scene_fixture() -> Iterator[Any]:
    """A CPU scene with ManiSkill's ground, as ``Empty-v1`` makes it (panda at the origin)."""
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401

    from robospec.maniskill.headless import headless_loading

    with headless_loading():
        env = gym.make(
            "Empty-v1",
            robot_uids="panda",
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
        )
    try:
        yield env.unwrapped.scene  # type: ignore[attr-defined]
    finally:
        env.close()


def parse(scene: Any, path: Path) -> Any:
    """ManiSkill's loader's parse of ``path``: the robot's articulation builder (each under a
    name of its own: a scene refuses a name twice)."""
    from robospec.maniskill.headless import headless_loading

    with headless_loading():
        loader = scene.create_mjcf_loader()
        loader.name = f"mjcf{next(_names)}"
        return loader.parse(str(path))["articulation_builders"][0]
