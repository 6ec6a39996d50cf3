"""Where a test run's time goes, written down by every run (a pytest plugin that
tests/conftest.py loads): ``out/test-durations-<ManiSkill>.json`` (``out/`` is ignored by git;
one file per ManiSkill, so CI's nightly run does not overwrite its 3.0.1 figures) holds each test
file's seconds (setup, call and teardown of its tests), its count of tests, the xdist workers that
ran them, and when on the run's clock it started and ended; the end of the run's summary prints the
busiest files and each worker's busy time, so that CI's log says it too. ``docs/development.md``
("CI") reads these figures; the next change to CI starts from them, not from guesses.
"""

from __future__ import annotations

import json
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

import pytest

OUT = Path(__file__).resolve().parent.parent / "out"
SHOWN = 12  # files printed at the end of the run


class _Durations:
    def __init__(self) -> None:
        self.started = time.time()
        self.files: dict[str, dict[str, Any]] = defaultdict(
            lambda: {"seconds": 0.0, "tests": 0, "workers": [], "start": None, "end": None}
        )
        # each worker's busy seconds, and when it ended its last test: a worker that ends long
        # before the run does sat idle while one long file kept the other busy
        self.workers: dict[str, dict[str, float]] = defaultdict(
            lambda: {"seconds": 0.0, "end": 0.0}
        )

    def add(self, report: pytest.TestReport) -> None:
        row = self.files[report.nodeid.split("::")[0]]
        row["seconds"] += report.duration
        if report.when == "call" or (report.when == "setup" and report.outcome != "passed"):
            row["tests"] += 1
        node = getattr(report, "node", None)  # pytest-xdist's controller: the worker's
        name = node.gateway.id if node is not None else "main"
        if name not in row["workers"]:  # --dist load spreads a file's tests over workers
            row["workers"].append(name)
        start = getattr(report, "start", 0) - self.started
        stop = getattr(report, "stop", 0) - self.started
        worker = self.workers[name]
        worker["seconds"] += report.duration
        worker["end"] = max(worker["end"], stop)
        row["start"] = start if row["start"] is None else min(row["start"], start)
        row["end"] = stop if row["end"] is None else max(row["end"], stop)

    def document(self, config: pytest.Config, label: str) -> dict[str, Any]:
        files = dict(sorted(self.files.items(), key=lambda item: -item[1]["seconds"]))
        return {
            "maniskill": label,
            "arguments": list(config.invocation_params.args),
            "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(self.started)),
            "wall_seconds": round(time.time() - self.started, 1),
            "workers": {
                name: {key: round(value, 1) for key, value in worker.items()}
                for name, worker in sorted(self.workers.items())
            },
            "files": {
                name: {
                    key: round(value, 2) if isinstance(value, float) else value
                    for key, value in row.items()
                }
                for name, row in files.items()
            },
        }


# the run's record, on the controller only (pytest-xdist's workers report to it)
_current: dict[str, _Durations] = {}


def pytest_configure(config: pytest.Config) -> None:
    if not hasattr(config, "workerinput"):
        _current["durations"] = _Durations()


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    durations = _current.get("durations")
    if durations is not None:
        durations.add(report)


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    durations = _current.pop("durations", None)
    if durations is None or not durations.files:
        return
    conftest = sys.modules.get("conftest")
    label = getattr(conftest, "MANISKILL_VERSION", None) or "none"
    document = durations.document(config, label)
    try:
        OUT.mkdir(exist_ok=True)
        path = OUT / f"test-durations-{label}.json"
        path.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    except OSError as error:  # a read-only checkout still runs its tests
        terminalreporter.write_line(f"test durations not written: {error}")
        return
    workers = ", ".join(
        f"{name} {worker['seconds']:.0f} s (its last test ended at {worker['end']:.0f} s)"
        for name, worker in document["workers"].items()
    )
    terminalreporter.write_line(
        f"test durations ({path.relative_to(OUT.parent)}): wall {document['wall_seconds']:.0f} s;"
        f" busy {workers}"
    )
    for name, row in list(document["files"].items())[:SHOWN]:
        terminalreporter.write_line(
            f"  {row['seconds']:7.1f} s  {row['tests']:4d} tests  {','.join(row['workers']):>7}  "
            f"{row['start']:6.0f}-{row['end']:6.0f} s  {name}"
        )
