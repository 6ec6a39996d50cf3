"""Every benchmark, side by side, measured in one run and written to docs/performance.md.

    .venv/bin/python benchmarks/run.py            # the full run (about 10 minutes)
    .venv/bin/python benchmarks/run.py --quick    # every part on a tiny budget (a smoke test)
    .venv/bin/python benchmarks/run.py --only first_error   # one part; its section is replaced

1. Time to the first error for a misspelled joint: `robospec validate` against the hand-written
   way, and with the newest pydantic against an older one (benchmarks/first_error.py).
2. Import-time registration of every example spec, cold and warm cache, against
   `import mani_skill.envs` alone (benchmarks/registration.py).
3. `env.step` throughput of each generated agent against ManiSkill's own class
   (benchmarks/step_throughput.py).
4. Validate time and peak memory on synthetic robots of 100 to 10,000 links
   (benchmarks/scaling.py).
5. Time to sample a robot's collision matrix, optimize's and new's first stage
   (benchmarks/collision_matrix.py).
6. `env.step` throughput of robots optimized by `robospec optimize`, and by its fast profile,
   against the same robots as written (benchmarks/optimize_throughput.py).
7. What optimize and the fast profile change in behaviour: link-pose divergence, check's step
   responses and the Panda's motion-planning success (benchmarks/optimize_fidelity.py).
8. The same robots on physx_cuda at 1,024 and 4,096 environments, where a GPU is
   (benchmarks/optimize_gpu.py; skipped with a message elsewhere).
9. How soon `robospec lsp` publishes fresh diagnostics after an edit of the Panda spec
   (benchmarks/lsp_latency.py).
10. Time to draw a robot card's pictures (`robospec doc --images`) for the Panda and the G1
    on the CPU (benchmarks/pictures.py).
11. `robospec new`'s time per corpus robot, with and without the simulated refinement of its
    gains (benchmarks/scaffold.py).
12. The generated modules laid out by robospec's own layout against black and ruff: the same
    text or not, time per module and import, install size (benchmarks/formatter.py).
13. Demonstrations from ManiSkill's solutions (benchmarks/solve.py).
14. An MJCF compiled by MuJoCo and written as a URDF (`loader: mujoco`), per model, cold and
    cached (benchmarks/mjcf_compile.py).

Exit status 1 when a target is missed (speed-up, warm overhead, linear growth).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path

import collision_matrix
import first_error
import formatter
import lsp_latency
import mjcf_compile
import optimize_fidelity
import optimize_gpu
import optimize_throughput
import pictures
import registration
import scaffold
import scaling
import solve
import step_throughput
from measure import ROOT
from section import Section

COMMAND = ".venv/bin/python benchmarks/run.py"
SECTION_TITLES = (
    first_error.TITLE,
    registration.TITLE,
    step_throughput.TITLE,
    scaling.TITLE,
    collision_matrix.TITLE,
    optimize_throughput.TITLE,
    optimize_fidelity.TITLE,
    optimize_gpu.TITLE,
    lsp_latency.TITLE,
    pictures.TITLE,
    scaffold.TITLE,
    formatter.TITLE,
    solve.TITLE,
    mjcf_compile.TITLE,
)


PARTS = (
    "first_error",
    "registration",
    "step_throughput",
    "scaling",
    "collision_matrix",
    "optimize_throughput",
    "optimize_fidelity",
    "optimize_gpu",
    "lsp_latency",
    "pictures",
    "scaffold",
    "formatter",
    "solve",
    "mjcf_compile",
)
"""Each part's name (its module), in the order of SECTION_TITLES."""


def measurers(quick: bool, repeat: int) -> dict[str, Callable[[], Section]]:
    """Each part's measurement, by name, on the budget asked for."""
    if quick:
        return {
            "first_error": lambda: first_error.measure(1),
            "registration": lambda: registration.measure(1),
            "step_throughput": lambda: step_throughput.measure(steps=10, rounds=1, only=["panda"]),
            "scaling": lambda: scaling.measure([100], 1),
            "collision_matrix": lambda: collision_matrix.measure(
                1, cases=(collision_matrix.TARGET,)
            ),
            "optimize_throughput": lambda: optimize_throughput.measure(
                steps=10, rounds=1, only=["panda"], corpus=False, samples=20, every_spec=False
            ),
            "optimize_fidelity": lambda: optimize_fidelity.measure(
                seeds=1,
                steps=5,
                samples=20,
                robots=("panda",),
                check_robots=("panda",),
                tasks=("PickCube-v1",),
            ),
            "optimize_gpu": lambda: optimize_gpu.measure(
                envs=(16,), steps=5, samples=20, robots=("panda",)
            ),
            "lsp_latency": lambda: lsp_latency.measure(4),
            "pictures": lambda: pictures.measure(1, only=["panda"]),
            # the analytic gains only: the simulated refinement is new's own, tested there
            "scaffold": lambda: scaffold.measure(1, only=["erd_ur5"], refine=False),
            "formatter": lambda: formatter.measure(1, random_count=10),
            "solve": lambda: solve.measure(1, ("PickCube-v1",)),
            "mjcf_compile": lambda: mjcf_compile.measure(1, only=["dmc_jaco_arm"]),
        }
    return {
        "first_error": lambda: first_error.measure(repeat),
        "registration": lambda: registration.measure(repeat),
        "step_throughput": lambda: step_throughput.measure(steps=200, rounds=5),
        "scaling": lambda: scaling.measure([100, 1_000, 10_000], repeat),
        "collision_matrix": lambda: collision_matrix.measure(repeat),
        "optimize_throughput": lambda: optimize_throughput.measure(steps=200, rounds=5),
        "optimize_fidelity": lambda: optimize_fidelity.measure(seeds=50, steps=100),
        "optimize_gpu": lambda: optimize_gpu.measure(),
        "lsp_latency": lambda: lsp_latency.measure(40),
        "pictures": lambda: pictures.measure(repeat),
        "scaffold": lambda: scaffold.measure(repeat),
        "formatter": lambda: formatter.measure(repeat),
        "solve": lambda: solve.measure(),
        "mjcf_compile": lambda: mjcf_compile.measure(repeat),
    }


def replace_section(document: str, section: Section) -> str:
    """``document`` with the section titled as ``section`` replaced by it (up to the next
    ``## `` heading); a section the document lacks (a new part) goes where SECTION_TITLES
    puts it."""
    heading = f"## {section.title}\n"
    if heading not in document:
        return _insert_section(document, section)
    start = document.index(heading)
    end = document.find("\n## ", start + len(heading))
    rest = document[end + 1 :] if end != -1 else ""
    return document[:start] + section.markdown() + ("\n" + rest if rest else "")


def _insert_section(document: str, section: Section) -> str:
    later = SECTION_TITLES[SECTION_TITLES.index(section.title) + 1 :]
    starts = [document.find(f"\n## {title}\n") for title in later]
    start = min((found for found in starts if found != -1), default=len(document.rstrip()))
    rest = document[start:]  # the later sections, or the document's last newline
    head = document[:start].rstrip("\n") + "\n\n" + section.markdown()
    return head + (rest if rest.strip() else "")


def document(sections: list[Section], repeat: int, seconds: float) -> str:
    header = f"""# Performance

Measured by `benchmarks/run.py`, every table in one run (this one took {seconds:.0f} s on
{_machine()}). Regenerate with:

    {COMMAND}

Each time is the wall time of a fresh process, as a user starts it: the median of {repeat}
runs after one unmeasured warm-up run, with the spread (fastest–slowest). Children run with
Python's bytecode cache on, as after `pip install` (which compiles every module once); the
warm-up run writes that cache and warms the OS file cache. `robospec validate` compiles the
spec from scratch every time; only its spec model comes from robospec's cache, which the
warm-up run fills (a cold cache is measured on its own). A section can be measured again
alone (`--only NAME`): it then replaces its own section only.
"""
    return "\n".join([header, *(section.markdown() for section in sections)])


def _machine() -> str:
    return f"{os.cpu_count()} CPU core(s), Python {platform.python_version()}, {sys.platform}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="measured runs per figure")
    parser.add_argument("--quick", action="store_true", help="tiny budget: repeat 1, 100 links")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "performance.md")
    parser.add_argument(
        "--only", choices=PARTS, help="measure one part and replace its section in --out"
    )
    args = parser.parse_args()
    repeat = 1 if args.quick else args.repeat
    started = time.perf_counter()
    parts = measurers(args.quick, repeat)
    if args.only:
        sections = [parts[args.only]()]
        text = replace_section(args.out.read_text(encoding="utf-8"), sections[0])
    else:
        sections = [measure() for measure in parts.values()]
        assert tuple(section.title for section in sections) == SECTION_TITLES
        text = document(sections, repeat, time.perf_counter() - started)
    args.out.write_text(text, encoding="utf-8")
    print(text)
    missed = [section.title for section in sections if not section.meets_target]
    for title in missed:
        print(f"target missed: {title}", file=sys.stderr)
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
