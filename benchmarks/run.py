"""Side-by-side benchmarks, measured in one run, written to docs/performance.md.

    .venv/bin/python benchmarks/run.py [--repeat N]

1. Validating one spec with robospec, against the hand-written way of finding the same mistake
   (import ManiSkill, subclass the agent with a misspelled joint, gym.make until it fails).
2. Import-time registration of every example spec on a warm cache, against
   `import mani_skill.envs` alone: the overhead must stay under 10%.
Each measurement is a fresh process (wall time), repeated; medians are reported.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PYTHON = sys.executable

HAND_WRITTEN_MISTAKE = """
import gymnasium as gym
import mani_skill.envs
from mani_skill.agents.registration import register_agent
from mani_skill.agents.robots.panda.panda import Panda

@register_agent()
class MyPanda(Panda):
    uid = "my_panda"
    arm_joint_names = [f"panda_joint{i}" for i in (1, 2, 3, 77, 5, 6, 7)]

try:
    gym.make("Empty-v1", robot_uids="my_panda", obs_mode="state", sim_backend="physx_cpu",
             render_backend="none")
except Exception as exc:
    print("FIRST-ERROR:", type(exc).__name__, exc)
"""


def timed(args: list[str], env: dict[str, str]) -> tuple[float, str]:
    started = time.perf_counter()
    result = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, env=env)
    return time.perf_counter() - started, result.stdout + result.stderr


def median_of(args: list[str], env: dict[str, str], repeat: int) -> tuple[float, str]:
    times, output = [], ""
    for _ in range(repeat):
        seconds, output = timed(args, env)
        times.append(seconds)
    return statistics.median(times), output


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--out", type=Path, default=ROOT / "docs/performance.md")
    args = parser.parse_args()
    cache = tempfile.mkdtemp(prefix="robospec-bench-")
    env = {**os.environ, "ROBOSPEC_CACHE_DIR": cache}
    bad_spec = "tests/specs/negative/misspelled_joint.yaml"

    validate, validate_out = median_of(
        [PYTHON, "-m", "robospec.cli", "validate", bad_spec], env, args.repeat
    )
    hand, hand_out = median_of([PYTHON, "-c", HAND_WRITTEN_MISTAKE], env, args.repeat)
    validate_ok, _ = median_of(
        [PYTHON, "-m", "robospec.cli", "validate", "specs/maniskill/panda.yaml"], env, args.repeat
    )

    register = "import mani_skill.envs, robospec; robospec.register('specs/')"
    timed([PYTHON, "-c", register], env)  # prime the cache (cold)
    baseline, _ = median_of([PYTHON, "-c", "import mani_skill.envs"], env, args.repeat)
    warm, _ = median_of([PYTHON, "-c", register], env, args.repeat)
    overhead = (warm - baseline) / baseline

    first_error = next((line for line in validate_out.splitlines() if "error[" in line), "")
    hand_error = next(
        (
            line.split(":", 1)[1].strip()
            for line in hand_out.splitlines()
            if line.startswith("FIRST-ERROR:")
        ),
        "(no error raised)",
    )
    text = f"""# Performance

Measured by `benchmarks/run.py` in one run (each figure the median wall time of {args.repeat}
fresh processes, on this project's 2-core machine). Regenerate with:

    .venv/bin/python benchmarks/run.py

## Time to the first error for a misspelled joint

| way | seconds | what it says |
| --- | ---: | --- |
| `robospec validate {bad_spec}` | {validate:.2f} | `{first_error}` |
| hand-written agent + `gym.make` | {hand:.2f} | `{hand_error[:120]}` |

robospec is **{hand / validate:.1f}×** faster to the first error, and its error has a location.
Validating the (correct) panda spec takes {validate_ok:.2f} s and imports neither torch, SAPIEN
nor ManiSkill.

## Import-time registration (warm cache)

| what | seconds |
| --- | ---: |
| `import mani_skill.envs` | {baseline:.2f} |
| `import mani_skill.envs` + `robospec.register('specs/')` | {warm:.2f} |

Registering every example spec from a warm cache adds **{overhead * 100:.1f}%** (target: < 10%).
"""
    args.out.write_text(text)
    print(text)
    return 0 if overhead < 0.10 and validate < 1.0 else 1


if __name__ == "__main__":
    sys.exit(main())
