"""The worker process of ``robospec check`` (``robospec.physics.isolation`` starts it):

    python -m robospec.physics.worker JOBS_FD RESULTS_FD FOLDER

It imports ManiSkill once, then checks the robots it is sent one after another: each job's
stdout and stderr go to the job's log file, and it answers with ``("phase", what)`` before each
step that could kill it, ``("progress", index, label)`` per check and ``("result", report)``.
``faulthandler`` writes the Python traceback of a fatal signal to ``FOLDER/fault.log``.
"""

from __future__ import annotations

import faulthandler
import gc
import importlib
import sys
from multiprocessing.connection import Connection
from pathlib import Path

from robospec.physics import upstream_findings
from robospec.physics.isolation import FAULT_LOG, Job
from robospec.physics.results import RobotReport


def prepare_process() -> None:
    """Import ManiSkill's environments, then move every object alive now out of the garbage
    collector's sight: ManiSkill calls ``gc.collect()`` each time it builds a scene, and with
    torch's and ManiSkill's objects in view that costs about 0.15 s — more than building the
    scene, which ``Sim.start`` does before every measurement."""
    for module in ("mani_skill.envs", "robospec.output.register", "robospec.physics.batch"):
        importlib.import_module(module)  # mani_skill.envs registers Empty-v1
    gc.collect()
    gc.freeze()


def run_job(job: Job, results: Connection) -> RobotReport:
    from robospec.maniskill.upstream_output import captured_output
    from robospec.physics.batch import check_compiled
    from robospec.pipeline import compile_spec

    def phase(doing: str) -> None:
        results.send(("phase", doing))

    def progress(index: int, label: str) -> None:
        results.send(("progress", index, label))

    with captured_output(job.log) as output:
        item = compile_spec(job.path, job.display)
        report = check_compiled(item, job.options, progress, phase)
    report.messages = output.messages()
    if item.context is not None:
        report.findings.extend(upstream_findings.findings(item.context, report.messages))
    report.diagnostics = report.diagnostics[len(item.diagnostics) :]  # the parent has those
    return report


def main(argv: list[str]) -> int:
    jobs = Connection(int(argv[0]), writable=False)
    results = Connection(int(argv[1]), readable=False)
    fault_log = open(Path(argv[2]) / FAULT_LOG, "w")  # open while the process lives
    faulthandler.enable(fault_log)
    prepare_process()
    results.send(("ready",))
    while True:
        try:
            job = jobs.recv()
        except EOFError:
            return 0
        if job is None:
            return 0
        results.send(("result", run_job(job, results)))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
