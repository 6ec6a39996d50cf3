"""Load any ManiSkill robot on a machine without a render device, for robospec's own runs.

:func:`headless_loading` puts :mod:`robospec.maniskill.render_fallback`'s patches in place for
the duration of a block, device or not: robospec's checks never render, so they never load
visuals (a test proves panda's rollout bit-identical with and without it). Users get the same
patches process-wide, and only where SAPIEN finds no rendering device, from
``robospec.register`` and from every package ``robospec build`` writes
(:func:`robospec.maniskill.render_fallback.install`).

sapien and mani_skill are imported inside the functions: importing this module stays cheap.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from robospec.maniskill import render_fallback
from robospec.maniskill.render_fallback import strip_urdf_visuals

if TYPE_CHECKING:
    import gymnasium as gym

__all__ = ["headless_loading", "is_active", "make_empty_env", "strip_urdf_visuals"]

_depth = 0  # how many headless_loading blocks are open


@contextmanager
def headless_loading() -> Iterator[None]:
    """Within this block, ManiSkill loads robots without visual bodies (see the module doc).

    Re-entrant (nested blocks share one set of patches) and exception-safe: everything is
    restored when the outermost block exits (unless the process-wide fallback holds them).
    """
    global _depth
    render_fallback.acquire()
    _depth += 1
    try:
        yield
    finally:
        _depth -= 1
        render_fallback.release()


def is_active() -> bool:
    """Whether a headless_loading block is open right now."""
    return _depth > 0


def make_empty_env(
    uid: str,
    control_mode: str | None = None,
    *,
    headless: bool = True,
    num_envs: int = 1,
    sim_backend: str = "physx_cpu",
    sim_config: dict[str, Any] | None = None,
) -> gym.Env:
    """ManiSkill's ``Empty-v1`` with robot ``uid``, state observations, no renderer: the
    environment every headless run and comparison in robospec uses (on the CPU unless
    ``sim_backend`` says ``physx_cuda``; ``sim_config``: what ManiSkill merges over the task's,
    e.g. a spec's recommended one)."""
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    kwargs: dict[str, Any] = {}
    if control_mode is not None:
        kwargs["control_mode"] = control_mode
    if sim_config:
        kwargs["sim_config"] = sim_config
    if not headless:
        return gym.make(
            "Empty-v1",
            robot_uids=uid,
            obs_mode="state",
            sim_backend=sim_backend,
            render_backend="none",
            num_envs=num_envs,
            **kwargs,
        )
    with headless_loading():
        return make_empty_env(
            uid,
            control_mode,
            headless=False,
            num_envs=num_envs,
            sim_backend=sim_backend,
            sim_config=sim_config,
        )
