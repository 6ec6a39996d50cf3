"""A crash is told by where it happened and whose code that is, never by a path of the machine
(robospec.maniskill.crash). The ManiSkill and SAPIEN crashes themselves are
tests/test_check_isolation.py's; here, a real process dying of a signal, and a real exception."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from robospec.maniskill.crash import USER, from_exception, from_fault_log, signal_name

CRASHER = """import faulthandler
import os


def deep_inside():
    os.abort()


faulthandler.enable()
deep_inside()
"""


def test_a_process_killed_by_a_signal_is_told_by_its_signal_and_its_last_python_frame(
    tmp_path: Path,
) -> None:
    script = tmp_path / "crasher.py"
    script.write_text(CRASHER)
    result = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=60, check=False
    )
    assert result.returncode < 0
    crash = from_fault_log(result.stderr, result.returncode)
    assert crash.what == "SIGABRT (aborted)"
    assert crash.frame is not None
    assert (crash.frame.line, crash.frame.function) == (6, "deep_inside")
    assert crash.frame.path == "crasher.py" and str(tmp_path) not in crash.frame.path
    assert crash.frame.owner == USER and not crash.upstream


def test_exit_statuses_and_signals_have_names() -> None:
    assert signal_name(-11) == "SIGSEGV (segmentation fault)"
    assert signal_name(3) == "exit status 3"


def _wrapped() -> None:
    try:
        int("reduction")
    except ValueError as error:  # as Gymnasium re-raises what an environment's creator raised
        raise ValueError(f"{error} was raised from the environment creator") from error


def test_an_exception_is_told_by_the_error_first_raised_not_its_re_raise() -> None:
    try:
        _wrapped()
    except ValueError as error:
        crash = from_exception(error)
    assert crash.what == "ValueError: invalid literal for int() with base 10: 'reduction'"
    assert crash.frame is not None and crash.frame.function == "_wrapped"
    assert crash.frame.path.endswith("test_crash_records.py")
