"""RS526's rule for the solutions that grasp from above (robospec.solve.reach): a robot is
refused where the objects lie beyond its downward reach in *more than half* of the seeds asked,
and runs where they do in half or fewer (the Z1, beyond in 15 of 20, and the Panda, in 0 of 5,
sit far from the boundary; this pins it).

The counting is what is under test: the reach itself is measured on SAPIEN's kinematics
(tests/test_solve.py, test_pick_scaffolds.py); here a stand-in reaches exactly 0.6 m and the
stand-in task puts its cube, seed by seed, at distances the test chooses.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from robospec.solve import reach

REACH = 0.6  # m: the stand-in arm's downward reach at the cube's height
NEAR, FAR = 0.5, 0.7  # m from the root: within it, beyond it


class _Reach:
    def __init__(self, agent: Any, facts: Any) -> None:
        self.root = np.zeros(3)

    def farthest(self, point: np.ndarray, bound: float) -> float:
        return REACH


class _Task:
    """A task whose reset(seed) puts its one cube at ``distances[seed]`` in front of the root."""

    def __init__(self, distances: list[float]) -> None:
        self.distances = distances
        self.cube = np.zeros(3)
        self.unwrapped = SimpleNamespace(agent=None)

    def reset(self, seed: int) -> None:
        self.cube = np.array([self.distances[seed], 0.0, 0.02])


def _refusal(monkeypatch: pytest.MonkeyPatch, beyond: int, seeds: int) -> str | None:
    task = _Task([FAR] * beyond + [NEAR] * (seeds - beyond))
    monkeypatch.setattr(reach, "DownwardReach", _Reach)
    monkeypatch.setattr(reach, "dynamic_actors", lambda base: {"cube": task.cube})
    return reach.beyond_downward_reach(task, None, list(range(seeds)), bound=1.0)  # type: ignore[arg-type]


def test_objects_beyond_reach_in_half_the_seeds_do_not_refuse_the_robot(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    assert _refusal(monkeypatch, beyond=10, seeds=20) is None


def test_objects_beyond_reach_in_more_than_half_the_seeds_refuse_it_with_the_count(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    why = _refusal(monkeypatch, beyond=11, seeds=20)
    assert why is not None
    assert "'cube' lies 0.70 m" in why and "in 11 of the 20 seeds asked" in why
    assert "(0.60 m with its grasp straight down at the cube's height)" in why
