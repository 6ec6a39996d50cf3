"""One job in a process of its own: how ``robospec tune`` and ``tune --reference`` run ManiSkill.

The parent pickles a request into a fresh folder and runs ``python -m MODULE FOLDER``; the
worker module's ``main`` is :func:`serve`, which reads the request, runs the job and pickles its
result back. What ManiSkill and SAPIEN print goes to ``FOLDER/job.log``, what the job is doing to
``FOLDER/phase`` (before each step that could kill the process), and ``faulthandler`` writes the
traceback of a fatal signal to ``FOLDER/fault.log``: a robot that kills the process is a
:class:`Death` the command turns into a located diagnostic, never a lost run. (``robospec check``
keeps one worker for many robots instead: :mod:`robospec.physics.isolation`.)

Nothing here imports ManiSkill: the worker's job does, in the worker.
"""

from __future__ import annotations

import faulthandler
import os
import pickle
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

REQUEST = "request.pickle"
RESULT = "result.pickle"
PHASE = "phase"
LOG = "job.log"
FAULT_LOG = "fault.log"
FIRST_PHASE = "importing ManiSkill"

Phase = Callable[[str], None]


@dataclass(frozen=True)
class Death:
    """A worker that ended without a result: its exit status, what it printed, what it was
    doing and faulthandler's traceback."""

    returncode: int
    log: str
    doing: str
    fault_log: str

    @property
    def at_start(self) -> bool:
        """It could not import what it needs (ManiSkill not installed, say)."""
        return self.doing == FIRST_PHASE and self.returncode > 0

    def last_line(self) -> str:
        lines = [line.strip() for line in self.log.splitlines() if line.strip()]
        return lines[-1] if lines else f"exit status {self.returncode}"


def run_once(module: str, request: object, prefix: str) -> Any:
    """The result ``python -m module`` made of ``request``, or its :class:`Death`."""
    folder = Path(tempfile.mkdtemp(prefix=prefix))
    try:
        (folder / REQUEST).write_bytes(pickle.dumps(request))
        with open(folder / LOG, "ab") as log:
            process = subprocess.run(
                [sys.executable, "-m", module, str(folder)],
                stdin=subprocess.DEVNULL,
                stdout=log,
                stderr=log,
                env=child_environment(),
                check=False,
            )
        result = folder / RESULT
        if process.returncode == 0 and result.is_file():
            return pickle.loads(result.read_bytes())
        return Death(
            process.returncode,
            read_text(folder / LOG),
            read_text(folder / PHASE) or "starting",
            read_text(folder / FAULT_LOG),
        )
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def serve(argv: Sequence[str], job: Callable[[Any, Phase], Any]) -> int:
    """The worker's side: ``job(request, phase)``'s result, with the messages ManiSkill printed
    meanwhile set as its ``messages``, written back for :func:`run_once`."""
    folder = Path(argv[0])
    fault_log = open(folder / FAULT_LOG, "w")  # open while the process lives
    faulthandler.enable(fault_log)
    request = pickle.loads((folder / REQUEST).read_bytes())
    from robospec.maniskill.upstream_output import captured_output

    def phase(doing: str) -> None:
        (folder / PHASE).write_text(doing, encoding="utf-8")

    phase(FIRST_PHASE)
    with captured_output(folder / LOG) as output:
        result = job(request, phase)
    result.messages = list(output.messages())
    (folder / RESULT).write_bytes(pickle.dumps(result))
    return 0


def child_environment() -> dict[str, str]:
    """This process's environment, with its module search path: the worker imports robospec,
    the generated agents' hook modules and whatever else this process can."""
    env = dict(os.environ)
    paths = [p for p in sys.path if p and os.path.isdir(p)]
    env["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths))
    return env


def read_text(path: Path) -> str:
    """The file's text, or "" when there is none."""
    try:
        return path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return ""
