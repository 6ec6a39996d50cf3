"""Every benchmark, side by side, measured in one run and written to docs/performance.md.

    .venv/bin/python benchmarks/run.py            # the full run (about 10 minutes)
    .venv/bin/python benchmarks/run.py --quick    # every part on a tiny budget (a smoke test)

1. Time to the first error for a misspelled joint: `robospec validate` against the hand-written
   way (benchmarks/first_error.py).
2. Import-time registration of every example spec, cold and warm cache, against
   `import mani_skill.envs` alone (benchmarks/registration.py).
3. `env.step` throughput of each generated agent against ManiSkill's own class
   (benchmarks/step_throughput.py).
4. Validate time and peak memory on synthetic robots of 100 to 10,000 links
   (benchmarks/scaling.py).

Exit status 1 when a target is missed (speed-up, warm overhead, linear growth).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

import first_error
import registration
import scaling
import step_throughput
from measure import ROOT
from section import Section

COMMAND = ".venv/bin/python benchmarks/run.py"
SECTION_TITLES = (first_error.TITLE, registration.TITLE, step_throughput.TITLE, scaling.TITLE)


def measure_all(quick: bool, repeat: int) -> list[Section]:
    if quick:
        return [
            first_error.measure(1),
            registration.measure(1),
            step_throughput.measure(steps=10, rounds=1, only=["panda"]),
            scaling.measure([100], 1),
        ]
    return [
        first_error.measure(repeat),
        registration.measure(repeat),
        step_throughput.measure(steps=200, rounds=5),
        scaling.measure([100, 1_000, 10_000], repeat),
    ]


def document(sections: list[Section], repeat: int, seconds: float) -> str:
    header = f"""# Performance

Measured by `benchmarks/run.py`, every table in one run (this one took {seconds:.0f} s on
{_machine()}). Regenerate with:

    {COMMAND}

Each time is the wall time of a fresh process, as a user starts it: the median of {repeat}
runs after one unmeasured warm-up run, with the spread (fastest–slowest). Children run with
Python's bytecode cache on, as after `pip install` (which compiles every module once); the
warm-up run writes that cache and warms the OS file cache. No robospec cache is involved in
`robospec validate`: it compiles the spec from scratch every time.
"""
    return "\n".join([header, *(section.markdown() for section in sections)])


def _machine() -> str:
    return f"{os.cpu_count()} CPU core(s), Python {platform.python_version()}, {sys.platform}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="measured runs per figure")
    parser.add_argument("--quick", action="store_true", help="tiny budget: repeat 1, 100 links")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "performance.md")
    args = parser.parse_args()
    repeat = 1 if args.quick else args.repeat
    started = time.perf_counter()
    sections = measure_all(args.quick, repeat)
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
