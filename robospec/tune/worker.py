"""The worker process of ``robospec tune`` (``robospec.tune.command`` starts it, one per spec):

    python -m robospec.tune.worker FOLDER

It reads ``FOLDER/request.pickle`` (a :class:`Request`), registers the spec's agent, tunes the
controllers in ManiSkill and writes ``FOLDER/result.pickle`` (a
:class:`~robospec.tune.results.TuneReport`). What ManiSkill and SAPIEN print goes to
``FOLDER/job.log``; before each step that could kill it the worker writes what it is doing to
``FOLDER/phase``, and ``faulthandler`` writes the traceback of a fatal signal to
``FOLDER/fault.log``: a robot that kills the process is a located diagnostic in the parent
(RS515), as in ``robospec check``.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from robospec.physics.one_shot import serve


@dataclass(frozen=True)
class Request:
    path: Path
    display: str
    controllers: tuple[str, ...]  # only these (empty: every controller)
    traces: bool = True  # send the step traces back (for plots)


def main(argv: Sequence[str]) -> int:
    return serve(argv, tune_spec)


def tune_spec(request: Request, phase: object) -> object:
    """Compile, register and tune in this process: the worker's job."""
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    from robospec.pipeline import compile_spec
    from robospec.tune.session import tune_compiled

    item = compile_spec(request.path, request.display)
    return tune_compiled(item, request.controllers, phase, request.traces)  # type: ignore[arg-type]


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
