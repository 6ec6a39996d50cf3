"""robospec solve: episodes per minute for the Panda (specs/maniskill/panda.yaml), ManiSkill's
own solutions planned by robospec's planner and recorded with RecordEpisode, in one process on
the CPU (``--num-procs`` multiplies it by the cores there are).

    python benchmarks/solve.py [--episodes N]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from measure import ROOT
from section import Section

TITLE = "Demonstrations (robospec solve)"
TASKS = ("PickCube-v1", "PushCube-v1", "StackCube-v1")
PANDA = ROOT / "specs" / "maniskill" / "panda.yaml"


def measure(episodes: int = 20, tasks: tuple[str, ...] = TASKS) -> Section:
    from robospec.solve.command import run_solve

    lines = [
        "| task | episodes | succeeded | seconds | episodes a minute |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    for task in tasks:
        with tempfile.TemporaryDirectory() as folder:
            started = time.perf_counter()
            report = run_solve(PANDA, task, episodes, Path(folder), 1, 0, progress=False)
            seconds = time.perf_counter() - started
        done = sum(e.success for e in report.episodes)
        rate = 60 * len(report.episodes) / seconds if seconds else 0.0
        lines.append(f"| {task} | {len(report.episodes)} | {done} | {seconds:.1f} | {rate:.0f} |")
    lines += [
        "",
        "`rs_panda`, one process, seeds from 0: compiling and registering the spec, the check "
        "before the first episode (a scene built and reset) and writing the .h5/.json included.",
    ]
    return Section(TITLE, "\n".join(lines))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--episodes", type=int, default=20)
    print(measure(parser.parse_args().episodes).markdown())


if __name__ == "__main__":
    main()
