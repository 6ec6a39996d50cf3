"""Check each robot in a worker process, so that a robot which kills the process (a segmentation
fault or an abort in SAPIEN's native code) costs only its own results.

One worker (``python -m robospec.physics.worker``) imports ManiSkill once (about 4.5 s) and
checks robots one after another, so ``robospec check`` of many specs costs what it cost in one
process. A worker that dies is replaced for the next robot; the robot it was checking gets an
RS515 diagnostic that says what the check was doing, the last ManiSkill/SAPIEN frame
(``faulthandler``'s traceback) and what SAPIEN printed before it died. Python exceptions never
kill a worker: they become diagnostics inside it (``robospec.physics.batch.check_loaded``).

The two processes talk over two pipes of their own (pickled messages), never over stdout: the
worker's stdout and stderr (SAPIEN's C++ logger writes there) go to one log file per robot,
which the worker folds into messages (``robospec.maniskill.upstream_output``) or, when it
died, the parent reads.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path
from types import TracebackType

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import ROBOT_NOT_LOADABLE
from robospec.maniskill.crash import from_fault_log
from robospec.maniskill.upstream_output import UpstreamLog
from robospec.physics.crash_diagnostics import process_died
from robospec.physics.findings import Finding, Status
from robospec.physics.one_shot import child_environment, read_text
from robospec.physics.results import LOAD, Options, RobotProgress, RobotReport
from robospec.pipeline import CompiledSpec

WORKER_MODULE = "robospec.physics.worker"
FAULT_LOG = "fault.log"  # faulthandler's traceback of a worker that died
STARTUP_LOG = "startup.log"  # what a worker printed outside any job
STOP_TIMEOUT = 10.0  # seconds a worker gets to exit once told to


@dataclass(frozen=True)
class Job:
    """One robot for a worker: the spec (the worker compiles it again: cheap, and nothing but
    plain data crosses the pipe) and where its output goes."""

    index: int
    path: Path
    display: str
    options: Options
    log: Path


def job_log(folder: Path, index: int) -> Path:
    return folder / f"job-{index}.log"


class WorkerDied(Exception):
    """The worker process ended while it checked a robot (or before it was ready)."""


class Worker:
    """One worker process and the pipes to it."""

    def __init__(self) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="robospec-check-"))
        jobs_read, jobs_write = os.pipe()
        results_read, results_write = os.pipe()
        with open(self.folder / STARTUP_LOG, "wb") as startup:
            self.process = subprocess.Popen(
                [
                    sys.executable,
                    "-m",
                    WORKER_MODULE,
                    str(jobs_read),
                    str(results_write),
                    str(self.folder),
                ],
                pass_fds=(jobs_read, results_write),
                stdin=subprocess.DEVNULL,
                stdout=startup,
                stderr=startup,
                env=child_environment(),
            )
        os.close(jobs_read)
        os.close(results_write)
        self.jobs = Connection(jobs_write, readable=False)
        self.results = Connection(results_read, writable=False)
        self.ready = False
        self.phase = "starting"

    def wait_ready(self) -> None:
        while not self.ready:
            self._receive()

    def run(self, job: Job, progress: RobotProgress | None) -> RobotReport:
        self.wait_ready()
        self.phase = "registering the agent"
        self.jobs.send(job)
        while True:
            message = self._receive()
            kind = message[0]
            if kind == "progress" and progress is not None:
                index, label = message[1:]
                progress(int(str(index)), str(label))
            elif kind == "result":
                report = message[1]
                assert isinstance(report, RobotReport)
                return report

    def _receive(self) -> tuple[object, ...]:
        try:
            message: tuple[object, ...] = self.results.recv()
        except (EOFError, OSError) as exc:
            raise WorkerDied(self.phase) from exc
        if message[0] == "ready":
            self.ready = True
        elif message[0] == "phase":
            self.phase = str(message[1])
        return message

    def returncode(self) -> int:
        try:
            return self.process.wait(timeout=STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            self.process.kill()
            return self.process.wait()

    def fault_log(self) -> str:
        return read_text(self.folder / FAULT_LOG)

    def startup_output(self) -> str:
        return read_text(self.folder / STARTUP_LOG)

    def close(self) -> None:
        try:
            self.jobs.send(None)  # stop
        except OSError:
            pass
        self.returncode()
        self.jobs.close()
        self.results.close()
        shutil.rmtree(self.folder, ignore_errors=True)


class WorkerPool:
    """Robots checked one at a time by a worker, started on the first robot and replaced when
    it dies. A worker that cannot even start (ManiSkill fails to import) is not started again:
    every robot gets the same RS510 diagnostic."""

    def __init__(self) -> None:
        self._worker: Worker | None = None
        self._cannot_start: str | None = None
        self._jobs = 0

    def __enter__(self) -> WorkerPool:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()

    def close(self) -> None:
        if self._worker is not None:
            if self._worker.process.poll() is None and not self._worker.ready:
                self._worker.process.kill()
            self._worker.close()
            self._worker = None

    def check(
        self, item: CompiledSpec, options: Options, progress: RobotProgress | None = None
    ) -> RobotReport:
        assert item.robot is not None
        if self._cannot_start is not None:
            return self._not_started(item, self._cannot_start)
        worker = self._worker or Worker()
        self._worker = worker
        self._jobs += 1
        job = Job(self._jobs, item.path, item.display, options, job_log(worker.folder, self._jobs))
        try:
            report = worker.run(job, progress)
        except WorkerDied:
            self._worker = None
            returncode = worker.returncode()
            if not worker.ready:  # it died importing ManiSkill, not checking this robot
                self._cannot_start = _last_line(worker.startup_output()) or (
                    f"exit status {returncode}"
                )
                worker.close()
                return self._not_started(item, self._cannot_start)
            report = self._died(item, worker, job, returncode)
            worker.close()
            return report
        # the compile diagnostics are this process's (the worker compiled the same spec)
        report.diagnostics = [*item.diagnostics, *report.diagnostics]
        return report

    def _died(self, item: CompiledSpec, worker: Worker, job: Job, returncode: int) -> RobotReport:
        assert item.robot is not None and item.context is not None
        crash = from_fault_log(worker.fault_log(), returncode)
        said = UpstreamLog()
        said.feed(read_text(job.log))
        diagnostic = process_died(
            item.context, item.robot.uid, crash, worker.phase, said.messages()
        )
        finding = Finding(
            LOAD if worker.phase.startswith(("loading", "registering")) else "process",
            None,
            "-",
            Status.FAIL,
            f"the check process died: {crash.what}",
            {},
            (diagnostic,),
        )
        return RobotReport(
            item.display, item.robot.uid, [finding], list(item.diagnostics), said.messages()
        )

    def _not_started(self, item: CompiledSpec, why: str) -> RobotReport:
        assert item.robot is not None
        diagnostic: Diagnostic = error(
            Location(item.display),
            ROBOT_NOT_LOADABLE,
            f"'{item.robot.uid}' cannot be checked: the check process did not start ({why})",
            "it imports ManiSkill: install the maniskill extra (pip install -e "
            "'.[maniskill]'), then run robospec check again",
        )
        return RobotReport(item.display, item.robot.uid, [], [*item.diagnostics, diagnostic])


def _last_line(text: str) -> str:
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else ""
