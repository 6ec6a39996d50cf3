"""Stepping two environments side by side: the same random actions, timed in alternating rounds
(so drift of the machine's load hits both alike). Imported by the worker processes only: it
needs ManiSkill and torch."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import torch

SEED = 0
WARM_UP_STEPS = 5


def random_actions(space: Any, steps: int, seed: int = SEED) -> torch.Tensor:
    """``steps`` uniform actions within ``space``, infinite bounds cut to ±π."""
    low = np.maximum(np.asarray(space.low, dtype=np.float64), -np.pi)
    high = np.minimum(np.asarray(space.high, dtype=np.float64), np.pi)
    rng = np.random.default_rng(seed)
    return torch.from_numpy(rng.uniform(low, high, size=(steps, *low.shape)).astype(np.float32))


def alternating_rates(
    envs: dict[str, Any], actions: torch.Tensor, rounds: int
) -> dict[str, list[float]]:
    """Steps per second of each environment in each round, after a short warm-up; the order
    alternates between rounds."""
    rates: dict[str, list[float]] = {name: [] for name in envs}
    for env in envs.values():
        env.reset(seed=SEED)
        for action in actions[:WARM_UP_STEPS]:
            env.step(action)
    for round_ in range(rounds):
        order = list(envs) if round_ % 2 == 0 else list(reversed(envs))
        for name in order:
            rates[name].append(_steps_per_second(envs[name], actions))
    return rates


def ratios(fast: list[float], slow: list[float]) -> list[float]:
    """Round by round, how many times as fast the first environment stepped as the second."""
    return [f / s for f, s in zip(fast, slow, strict=True)]


def physx_share(env: Any, actions: torch.Tensor) -> float:
    """The fraction of ``env.step`` spent in ``ManiSkillScene.step`` (PhysX) over ``actions``;
    the rest is ManiSkill's Python."""
    from mani_skill.envs.scene import ManiSkillScene

    spent = [0.0]
    step = ManiSkillScene.step

    def timed(scene: Any) -> None:
        started = time.perf_counter()
        step(scene)
        spent[0] += time.perf_counter() - started

    ManiSkillScene.step = timed  # type: ignore[method-assign]
    try:
        rate = _steps_per_second(env, actions)
    finally:
        ManiSkillScene.step = step  # type: ignore[method-assign]
    return spent[0] * rate / len(actions)


def _steps_per_second(env: Any, actions: torch.Tensor) -> float:
    env.reset(seed=SEED)
    started = time.perf_counter()
    for action in actions:
        env.step(action)
    return len(actions) / (time.perf_counter() - started)


def failure_reason(exc: BaseException) -> str:
    """Why a robot could not be loaded here, in one short line for the report."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else ''}"[:200]
