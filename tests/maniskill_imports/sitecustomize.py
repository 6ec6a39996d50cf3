"""The audit behind CI's nightly selection (.ci/run: -m maniskill; docs/development.md, "CI"):
with this folder on PYTHONPATH, every Python process a test starts (robospec in a child
process, a script) writes a line to ``$ROBOSPEC_MANISKILL_IMPORT_LOG`` at exit when it imported
mani_skill, sapien or torch, naming the test (``PYTEST_CURRENT_TEST``, which pytest sets and the
child inherits). A test named there and not marked ``maniskill`` must be marked: it proves
something on ManiSkill's nightly. Run over the unmarked tests:

    PYTHONPATH=$PWD:$PWD/tests/maniskill_imports ROBOSPEC_MANISKILL_IMPORT_LOG=out/imports.log \\
        .venv/bin/python -m pytest -p no:xdist -m "not maniskill" --ignore=tests/test_corpus.py

(The run itself fails an unmarked test that imports them in its own process: tests/conftest.py.)
"""

import atexit
import os
import sys

_MODULES = ("mani_skill", "sapien", "torch")


def _record() -> None:
    log, test = (
        os.environ.get("ROBOSPEC_MANISKILL_IMPORT_LOG"),
        os.environ.get("PYTEST_CURRENT_TEST"),
    )
    found = [name for name in _MODULES if name in sys.modules]
    if log and test and found:
        with open(log, "a", encoding="utf-8") as handle:
            handle.write(f"{test}\t{','.join(found)}\t{' '.join(sys.argv)}\n")


atexit.register(_record)
