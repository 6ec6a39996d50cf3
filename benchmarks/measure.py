"""Timing fresh processes: wall time, peak memory, medians and spreads.

Every benchmark measures what a user gets from a fresh process. Children run with bytecode
caching on (``PYTHONDONTWRITEBYTECODE`` removed), as after ``pip install``, which compiles
every module once: a benchmark that recompiled robospec's sources in every run would measure
this machine's environment, not robospec. One unmeasured warm-up run per command writes those
caches (and warms the OS file cache) before the measured runs.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PYTHON = sys.executable


def child_env(**extra: str) -> dict[str, str]:
    """The environment of a measured child: this one, bytecode caching on, plus ``extra``."""
    env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    env.update(extra)
    return env


@dataclass(frozen=True)
class Run:
    """One finished child process."""

    seconds: float
    peak_rss_kib: int  # ru_maxrss of the child alone (KiB on Linux)
    returncode: int
    output: str  # stdout and stderr, interleaved
    # user + system CPU time of the child alone: what other work on a shared machine inflates
    # least (wall time also waits for the CPU)
    cpu_seconds: float = 0.0


def run(args: list[str], env: dict[str, str], cwd: Path = ROOT) -> Run:
    """Run ``args`` to completion: its wall time, exit status, output and its own peak RSS
    (from ``wait4``, so no other child's peak counts).

    Output goes to a file, not a pipe, so the child cannot block on a full pipe while this
    process waits for it.
    """
    with tempfile.TemporaryFile(mode="w+") as out:
        started = time.perf_counter()
        child = subprocess.Popen(args, cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(child.pid, 0)
        seconds = time.perf_counter() - started
        child.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        cpu = usage.ru_utime + usage.ru_stime
        return Run(seconds, usage.ru_maxrss, child.returncode, out.read(), cpu)


@dataclass(frozen=True)
class Sample:
    """Repeated runs of one command: median and spread of wall time, the last output."""

    times: tuple[float, ...]
    peak_rss_kib: int
    returncode: int
    output: str
    cpu_times: tuple[float, ...] = ()

    @property
    def median(self) -> float:
        return statistics.median(self.times)

    @property
    def cpu_median(self) -> float:
        return statistics.median(self.cpu_times)

    @property
    def spread(self) -> str:
        return f"{min(self.times):.2f}–{max(self.times):.2f}"


Command = Callable[[], tuple[list[str], dict[str, str]]]
"""Makes the arguments and environment of one run (a cold-cache run needs a new folder each
time)."""


def sample(args: list[str], env: dict[str, str], repeat: int, warm_up: bool = True) -> Sample:
    """Run ``args`` ``repeat`` times (after one unmeasured warm-up run unless told not to)."""
    return interleaved({"only": lambda: (args, env)}, repeat, warm_up)["only"]


def interleaved(
    commands: dict[str, Command], repeat: int, warm_up: bool = True
) -> dict[str, Sample]:
    """Run the commands in turn, ``repeat`` rounds (after one unmeasured warm-up round unless
    told not to), so that a change in the machine's load during the benchmark hits every
    command alike instead of whichever ran in that stretch."""
    runs: dict[str, list[Run]] = {name: [] for name in commands}
    for round_ in range(repeat + 1 if warm_up else repeat):
        for name, command in commands.items():
            result = run(*command())
            if round_ > 0 or not warm_up:
                runs[name].append(result)
    return {
        name: Sample(
            tuple(result.seconds for result in done),
            max(result.peak_rss_kib for result in done),
            done[-1].returncode,
            done[-1].output,
            tuple(result.cpu_seconds for result in done),
        )
        for name, done in runs.items()
    }
