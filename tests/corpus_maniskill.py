"""The journey's ManiSkill steps, run by tests/corpus_journey.py in a child process of their own:

    python tests/corpus_maniskill.py SPEC STEPS RESULT.json [PACKAGE]

1. ``robospec.register(SPEC)``, ``gym.make("Empty-v1", ...)`` headless on the CPU, as the README
   shows it (no other call), then STEPS random actions, the state checked finite;
2. with PACKAGE (what ``robospec build SPEC -o PACKAGE`` wrote): import it, as a fresh process
   would, and make the environment with the agent it registers.

Writes RESULT.json after each part, so a part that kills the process (a segfault in SAPIEN)
leaves the parts before it on record.
"""

from __future__ import annotations

import json
import sys
import time
import traceback
from pathlib import Path
from typing import Any

ENV_ID = "Empty-v1"
BUILT_STEPS = 5  # the built agent: that it loads and acts, not a second soak


def main(spec: str, steps: int, result_file: str, package: str | None) -> None:
    result: dict[str, Any] = {}

    def record(key: str, part: dict[str, Any]) -> None:
        result[key] = part
        Path(result_file).write_text(json.dumps(result), encoding="utf-8")

    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers the environments)
    from mani_skill.agents.registration import REGISTERED_AGENTS

    import robospec

    def registered() -> str:
        agents = robospec.register(spec)
        (uid,) = agents
        result["uid"] = uid
        return _roll_out(gym, uid, steps)

    record("register", _attempt(registered))
    if package is None:
        return

    def imported() -> str:
        uid = result.get("uid")
        # a fresh process that imports the package has no agent under this uid yet; this one
        # has the agent register() made (ManiSkill would keep it and skip the package's)
        if uid is not None:
            REGISTERED_AGENTS.pop(uid, None)
        sys.path.insert(0, str(Path.cwd()))
        module = __import__(package)
        (uid,) = module.AGENTS
        assert REGISTERED_AGENTS[uid].agent_cls is module.AGENTS[uid], "not registered"
        return _roll_out(gym, uid, BUILT_STEPS)

    record("built", _attempt(imported))


def _roll_out(gym: Any, uid: str, steps: int) -> str:
    import numpy as np

    env = gym.make(
        ENV_ID, robot_uids=uid, obs_mode="state", sim_backend="physx_cpu", render_backend="none"
    )
    try:
        obs, _ = env.reset(seed=0)
        env.action_space.seed(0)
        for _ in range(steps):
            obs, *_ = env.step(env.action_space.sample())
        state = np.asarray(obs.cpu() if hasattr(obs, "cpu") else obs)
        if not np.isfinite(state).all():
            raise FloatingPointError(f"the state is not finite after {steps} random steps")
    finally:
        env.close()
    return f"{steps} random steps"


def _attempt(action: Any) -> dict[str, Any]:
    from robospec import SpecError

    start = time.monotonic()
    part: dict[str, Any] = {}
    try:
        part["detail"] = action()
        part["outcome"] = "passed"
    except SpecError as rejected:
        part["outcome"] = "failed"
        part["error"] = "robospec.SpecError"
        part["diagnostics"] = [d.to_json() for d in rejected.diagnostics]
    except Exception as exc:  # what the user would see: the exception and where it was raised
        part["outcome"] = "failed"
        frames = traceback.extract_tb(exc.__traceback__)
        where = f" (at {_module_path(frames[-1].filename)}:{frames[-1].lineno})" if frames else ""
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        part["error"] = f"{type(exc).__name__}: {message}"[:300] + where
    part["seconds"] = time.monotonic() - start
    return part


def _module_path(filename: str) -> str:
    """A frame's file from its top-level package on (``sapien/wrapper/urdf_loader.py``)."""
    path = Path(filename)
    for index, part in enumerate(path.parts):
        if part in ("site-packages", "dist-packages"):
            return "/".join(path.parts[index + 1 :])
    return path.name


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else None)
