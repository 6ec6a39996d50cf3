"""Time to the first error for a misspelled joint: `robospec validate` against the hand-written
way (subclass ManiSkill's Panda with the same misspelling, then `gym.make` until it fails)."""

from __future__ import annotations

import sys
from collections import Counter

from measure import PYTHON, child_env, interleaved, run
from section import Section

TITLE = "Time to the first error for a misspelled joint"
BAD_SPEC = "tests/specs/negative/misspelled_joint.yaml"
GOOD_SPEC = "specs/maniskill/panda.yaml"
TARGET_SPEEDUP = 20.0

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


def measure(repeat: int) -> Section:
    env = child_env()
    samples = interleaved(
        {
            "validate": lambda: ([PYTHON, "-m", "robospec.cli", "validate", BAD_SPEC], env),
            "hand": lambda: ([PYTHON, "-c", HAND_WRITTEN_MISTAKE], env),
            "validate_ok": lambda: ([PYTHON, "-m", "robospec.cli", "validate", GOOD_SPEC], env),
        },
        repeat,
    )
    validate, hand, validate_ok = samples["validate"], samples["hand"], samples["validate_ok"]
    first_error = next((line for line in validate.output.splitlines() if "error[" in line), "")
    hand_error = next(
        (
            line.split(":", 1)[1].strip()
            for line in hand.output.splitlines()
            if line.startswith("FIRST-ERROR:")
        ),
        "(no error raised)",
    )
    speedup = hand.median / validate.median
    body = f"""
| way | median s | spread s | what it says |
| --- | ---: | ---: | --- |
| `robospec validate {BAD_SPEC}` | {validate.median:.3f} | {validate.spread} | `{first_error}` |
| hand-written agent + `gym.make` | {hand.median:.2f} | {hand.spread} | `{hand_error[:120]}` |

robospec is **{speedup:.1f}×** faster to the first error (target: ≥ {TARGET_SPEEDUP:.0f}×), and
its error has a location. Validating the (correct) panda spec takes {validate_ok.median:.3f} s
(peak memory {validate_ok.peak_rss_kib / 1024:.0f} MiB) and {_heavy_imports(GOOD_SPEC)}.
"""
    return Section(TITLE, body + _import_breakdown(), speedup >= TARGET_SPEEDUP)


HEAVY = {"torch": "torch", "sapien": "SAPIEN", "mani_skill": "ManiSkill", "pydantic": "pydantic"}
LOADED = """
import sys
from robospec.cli import main
sys.argv = ["robospec", "validate", sys.argv[1]]
try:
    main()
except SystemExit:
    pass
print("LOADED:", " ".join(sorted({m.split(".")[0] for m in sys.modules})))
"""


def _heavy_imports(spec: str) -> str:
    """Which heavy packages validating ``spec`` loads, measured in a child (pydantic's models
    are frozen ahead of time: robospec/model/freeze.py; pydantic-core alone runs them)."""
    output = run([PYTHON, "-c", LOADED, spec], child_env()).output
    line = next((ln for ln in output.splitlines() if ln.startswith("LOADED:")), "LOADED:")
    loaded = set(line.removeprefix("LOADED:").split())
    names = [label for module, label in HEAVY.items() if module in loaded]
    if names:
        return "imports " + ", ".join(names)
    return "imports none of " + ", ".join(HEAVY.values()) + " (pydantic-core alone validates)"


def _import_breakdown() -> str:
    """Where `robospec validate`'s start-up goes: ``-X importtime`` self times, summed by top
    package (one run; importtime's own bookkeeping inflates them a little)."""
    args = [PYTHON, "-X", "importtime", "-m", "robospec.cli", "validate", BAD_SPEC]
    output = run(args, child_env()).output
    by_package: Counter[str] = Counter()
    for line in output.splitlines():
        if not line.startswith("import time:") or "|" not in line:
            continue
        fields = line.removeprefix("import time:").split("|")
        if not fields[0].strip().isdigit():
            continue  # the header line
        module = fields[2].strip()
        top = module.split(".")[0]
        if top == "robospec" and "." in module:
            top = ".".join(module.split(".")[:2])
        elif top.lstrip("_") in sys.stdlib_module_names or top.startswith("_"):
            top = "(standard library)"
        by_package[top] += int(fields[0])
    total = sum(by_package.values())
    rows = [f"| {name} | {micros / 1000:.0f} |" for name, micros in by_package.most_common(12)]
    rest = total - sum(micros for _, micros in by_package.most_common(12))
    return "\n".join(
        [
            "",
            "Where the start-up of that `robospec validate` goes (`-X importtime` self times",
            f"summed by package, one run; {total / 1000:.0f} ms of imports in all):",
            "",
            "| package | ms |",
            "| --- | ---: |",
            *rows,
            f"| everything else | {rest / 1000:.0f} |",
            "",
        ]
    )
