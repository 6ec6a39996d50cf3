"""`env.step` throughput of each generated agent against its hand-written twin.

For every spec in specs/maniskill/ (spec ``specs/maniskill/<uid>.yaml`` reproduces ManiSkill's
agent ``<uid>``), one worker process registers the spec, makes ``Empty-v1`` (physx_cpu, no
renderer, the agent's default control mode) once with the generated agent and once with
ManiSkill's own class, and steps both with the same uniformly random actions (fixed seed). The
two are timed in alternating rounds in the same process, so drift of the machine's load hits
both alike; the ratio of steps/s is reported per round as a median and a spread. A robot that
cannot be loaded here is listed with the reason.

    python benchmarks/step_throughput.py --worker --steps N --rounds R [SPEC...]

is the worker; it prints one JSON object per robot.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

from measure import PYTHON, ROOT, child_env, run
from section import Section

TITLE = "env.step throughput: generated agent against its hand-written twin"
SPECS = ROOT / "specs" / "maniskill"


def measure(steps: int, rounds: int, only: list[str] | None = None) -> Section:
    specs = [SPECS / f"{name}.yaml" for name in only] if only else sorted(SPECS.glob("*.yaml"))
    args = [PYTHON, str(Path(__file__)), "--worker", "--steps", str(steps)]
    args += ["--rounds", str(rounds), *map(str, specs)]
    result = run(args, child_env())
    rows = [json.loads(line) for line in result.output.splitlines() if line.startswith("{")]
    if result.returncode != 0 or len(rows) != len(specs):
        raise RuntimeError(f"step throughput worker failed:\n{result.output[-3000:]}")
    measured = [row for row in rows if "ratios" in row]
    lines = [
        "| robot (spec uid / ManiSkill uid) | control mode | generated steps/s | "
        "hand-written steps/s | ratio (median) | ratio spread |",
        "| --- | --- | ---: | ---: | ---: | ---: |",
    ]
    for row in measured:
        ratios = row["ratios"]
        lines.append(
            f"| `{row['spec_uid']}` / `{row['twin']}` | {row['control_mode']} | "
            f"{row['generated']:.0f} | {row['hand_written']:.0f} | "
            f"{statistics.median(ratios):.2f} | {min(ratios):.2f}–{max(ratios):.2f} |"
        )
    unloaded = [row for row in rows if "reason" in row]
    if unloaded:
        lines += ["", "Not measured (cannot be loaded here):", ""]
        lines += [f"- `{row['spec']}`: {row['reason']}" for row in unloaded]
    all_ratios = [statistics.median(row["ratios"]) for row in measured]
    overall = statistics.median(all_ratios) if all_ratios else float("nan")
    lines += [
        "",
        f"{len(measured)} robot(s), {rounds} alternating round(s) of {steps} steps each per "
        "agent after a short warm-up, same random actions (seed 0) for both. Median of the "
        f"per-robot ratios: **{overall:.2f}** (1.00 = the generated agent steps as fast as the "
        "hand-written one; the spread is this machine's noise between rounds).",
    ]
    return Section(TITLE, "\n".join(lines))


def _worker(specs: list[Path], steps: int, rounds: int) -> None:
    import gymnasium  # noqa: F401  (ManiSkill's environments need it imported first)
    import mani_skill.envs  # noqa: F401
    from stepping import alternating_rates, failure_reason, random_actions, ratios

    import robospec
    from robospec.maniskill.headless import make_empty_env

    cache = tempfile.mkdtemp(prefix="robospec-bench-steps-")
    for spec in specs:
        twin = spec.stem
        try:
            (spec_uid,) = robospec.register(str(spec), cache_dir=cache)
            envs = {"generated": make_empty_env(spec_uid), "hand_written": make_empty_env(twin)}
        except Exception as exc:  # a robot that cannot load here is listed, not fatal
            print(json.dumps({"spec": _shown(spec), "reason": failure_reason(exc)}))
            continue
        actions = random_actions(envs["hand_written"].action_space, steps)
        rates = alternating_rates(envs, actions, rounds)
        print(
            json.dumps(
                {
                    "spec": _shown(spec),
                    "spec_uid": spec_uid,
                    "twin": twin,
                    "control_mode": envs["generated"].unwrapped.control_mode,
                    "generated": statistics.median(rates["generated"]),
                    "hand_written": statistics.median(rates["hand_written"]),
                    "ratios": ratios(rates["generated"], rates["hand_written"]),
                }
            ),
            flush=True,
        )
        for env in envs.values():
            env.close()


def _shown(spec: Path) -> str:
    return spec.resolve().relative_to(ROOT).as_posix()


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--worker", action="store_true", required=True)
    parser.add_argument("--steps", type=int, required=True)
    parser.add_argument("--rounds", type=int, required=True)
    parser.add_argument("specs", type=Path, nargs="+")
    options = parser.parse_args()
    _worker(options.specs, options.steps, options.rounds)
    sys.exit(0)
