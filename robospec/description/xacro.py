"""Expand xacro files in a child process with time and memory limits.

A xacro file is a program: ``${...}`` and ``$(eval ...)`` evaluate Python expressions, and
``${2**2**34}`` alone exhausts memory. So expansion never happens in the robospec process: a fresh
interpreter runs ``_xacro_child.py`` with ``RLIMIT_AS`` set before xacro is imported, in the xacro
file's folder, with no stdin, and is killed (with everything it started) after a wall-clock
timeout. xacro is never imported here.
"""

from __future__ import annotations

import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from robospec.diagnostics import Diagnostic, Location, error

_CHILD = Path(__file__).with_name("_xacro_child.py")

# Runs the child script without the working directory (the robot's folder, which could hold a
# ``xacro.py`` of its own) on sys.path, and without importing robospec in the child.
_BOOTSTRAP = (
    "import os, runpy, sys\n"
    "if sys.path and sys.path[0] in ('', os.getcwd()):\n"
    "    del sys.path[0]\n"
    "sys.argv = sys.argv[1:]\n"
    "runpy.run_path(sys.argv[0], run_name='__main__')\n"
)

# How much of the child's stderr to keep when it dies without an answer.
_STDERR_TAIL = 2000

_TIME_HINT = "expanding a xacro file runs it: look for runaway recursion or expressions"
_MEMORY_HINT = "expanding a xacro file runs it: look for huge numbers, strings or repetitions"


def expand_xacro(
    path: str,
    args: Mapping[str, str],
    *,
    timeout_s: float = 20.0,
    memory_bytes: int = 1 << 30,
) -> tuple[str | None, list[Diagnostic]]:
    """Expand the xacro file at ``path`` with ``args`` (``xacro:arg`` values).

    Returns the expanded URDF text and no diagnostics, or ``None`` and diagnostics located at the
    xacro file (RS053: xacro reported an error; RS054: the expansion hit ``timeout_s`` or
    ``memory_bytes``). Never raises on bad input.
    """
    where = Location(path)
    abs_path = os.path.abspath(path)
    if not os.path.isfile(abs_path):
        return None, [error(where, "RS053", f"xacro expansion failed: no such file '{path}'")]
    try:
        mappings = {str(k): str(v) for k, v in args.items()}
        result, stderr, killed = _run_child(abs_path, mappings, timeout_s, memory_bytes)
    except OSError as e:  # e.g. the interpreter cannot be started
        return None, [error(where, "RS053", f"xacro expansion failed: cannot start it ({e})")]

    if killed:
        return None, [
            error(
                where,
                "RS054",
                f"xacro expansion exceeded the time limit of {_seconds(timeout_s)} and was stopped",
                _TIME_HINT,
            )
        ]
    if result is None:
        return None, [_no_answer(where, stderr, memory_bytes)]
    if result.get("ok") is True and isinstance(result.get("urdf"), str):
        return result["urdf"], []
    if result.get("kind") == "memory":
        return None, [_memory_error(where, memory_bytes)]
    return None, [_xacro_error(path, abs_path, result)]


def _run_child(
    abs_path: str, mappings: dict[str, str], timeout_s: float, memory_bytes: int
) -> tuple[dict[str, Any] | None, str, bool]:
    """Run the child; return (its JSON answer or None, its stderr tail, killed by the timeout)."""
    # A CPU-time limit backs up the wall-clock one in case this process dies and cannot kill.
    cpu_seconds = max(1, math.ceil(timeout_s) + 5)
    cmd = [
        sys.executable,
        "-c",
        _BOOTSTRAP,
        str(_CHILD),
        # The child runs in the file's folder; the bare name keeps xacro's output banner ("generated
        # from twolink.urdf.xacro") free of this machine's paths, so builds stay reproducible.
        os.path.basename(abs_path),
        str(int(memory_bytes)),
        str(cpu_seconds),
        json.dumps(mappings),
    ]
    # stderr goes to a file: a xacro file printing without end must not fill our memory.
    with tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(
            cmd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=err,
            cwd=os.path.dirname(abs_path),
            start_new_session=True,  # its own process group, so the kill reaches any children
        )
        killed = False
        try:
            out, _ = proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            killed = True
            _kill(proc)
            out, _ = proc.communicate()
        if not killed and _died_of_cpu_limit(proc.returncode):
            killed = True
        err.seek(0, os.SEEK_END)
        size = err.tell()
        err.seek(max(0, size - _STDERR_TAIL))
        stderr = err.read().decode("utf-8", "replace")
    if killed:
        return None, stderr, True
    try:
        answer = json.loads(out.decode("ascii"))
    except (UnicodeDecodeError, ValueError):
        return None, stderr, False
    return (answer if isinstance(answer, dict) else None), stderr, False


def _kill(proc: subprocess.Popen[bytes]) -> None:
    try:
        if hasattr(os, "killpg"):
            os.killpg(proc.pid, signal.SIGKILL)
        else:
            proc.kill()
    except (ProcessLookupError, PermissionError):
        pass  # it ended between the timeout and the kill


def _died_of_cpu_limit(returncode: int | None) -> bool:
    sigxcpu = getattr(signal, "SIGXCPU", None)
    return returncode is not None and sigxcpu is not None and returncode == -sigxcpu


def _seconds(timeout_s: float) -> str:
    return f"{timeout_s:g} s"


def _bytes(n: int) -> str:
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= size:
            return f"{n / size:g} {unit}"
    return f"{n} bytes"


def _memory_error(where: Location, memory_bytes: int) -> Diagnostic:
    return error(
        where,
        "RS054",
        f"xacro expansion exceeded the memory limit of {_bytes(memory_bytes)} and was stopped",
        _MEMORY_HINT,
    )


def _no_answer(where: Location, stderr: str, memory_bytes: int) -> Diagnostic:
    # The child died without writing its answer. Under RLIMIT_AS that is usually an allocation
    # failing somewhere Python cannot turn into MemoryError.
    lowered = stderr.lower()
    if any(s in lowered for s in ("memoryerror", "cannot allocate memory", "out of memory")):
        return _memory_error(where, memory_bytes)
    last = stderr.strip().splitlines()[-1] if stderr.strip() else "no output"
    return error(where, "RS053", f"xacro expansion failed: the xacro process crashed ({last})")


# xacro appends one "when evaluating expression '...'" line per nesting level, innermost first.
_EXPRESSION = re.compile(r"when evaluating expression '(.*)'\s*$", re.MULTILINE)
_UNDEFINED_ARG = re.compile(r"Undefined substitution argument (\S+)")
# xacro words some errors as "<class '...'>: text text" (its message and the wrapped exception).
_CLASS_PREFIX = re.compile(r"^<class '[\w.]+'>: ")


def _xacro_error(path: str, abs_path: str, result: Mapping[str, Any]) -> Diagnostic:
    message = str(result.get("message") or "unknown error").strip()
    # xacro names files relative to the child's working directory, the top file's folder.
    file = os.path.join(os.path.dirname(abs_path), str(result.get("file") or abs_path))
    shown = _display_path(path, abs_path, file)
    line = result.get("line")
    column = result.get("column")
    if not isinstance(line, int):
        line, column = _find_expression(file, message)
    hint = None
    files = [f for f in result.get("files") or [] if isinstance(f, str)]
    if len(files) > 1:
        chain = " <- ".join(_display_path(path, abs_path, f) for f in reversed(files))
        hint = f"included as {chain}"
    return error(
        Location(shown, max(1, line or 1), max(1, column if isinstance(column, int) else 1)),
        "RS053",
        f"xacro expansion failed: {_tidy(message)}",
        hint,
    )


def _tidy(message: str) -> str:
    # Keep diagnostics one line: xacro's message has one line per nesting level.
    text = "; ".join(part.strip() for part in message.splitlines() if part.strip())
    text = _CLASS_PREFIX.sub("", text)
    errno_at = text.find(" [Errno ")
    if errno_at > 0:
        text = text[:errno_at]  # "No such file or directory: X [Errno 2] ...: 'X'" says it twice
    half = len(text) // 2
    if len(text) % 2 == 1 and text[half] == " " and text[:half] == text[half + 1 :]:
        text = text[:half]  # "msg msg": xacro repeats a wrapped exception's own message
    return text


def _display_path(path: str, abs_path: str, file: str) -> str:
    """Name the top file as the caller did; an included file relative to it where possible."""
    file_abs = os.path.abspath(os.path.join(os.path.dirname(abs_path), file))
    if file_abs == abs_path:
        return path
    rel = os.path.relpath(file_abs, os.path.dirname(abs_path))
    return os.path.join(os.path.dirname(path), rel) if not rel.startswith("..") else file_abs


def _find_expression(file: str, message: str) -> tuple[int | None, int | None]:
    """Find where an expression named in xacro's message is written, innermost first.

    xacro's errors carry no line numbers (its DOM has none), but they quote the expression that
    failed, which is usually written once in the file.
    """
    try:
        text = Path(file).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None, None
    # ${expr} with any spacing inside the braces: xacro quotes the expression stripped.
    patterns = [r"\$\{\s*" + re.escape(e.strip()) + r"\s*\}" for e in _EXPRESSION.findall(message)]
    patterns += [r"\$\(arg\s+" + re.escape(a) + r"\s*\)" for a in _UNDEFINED_ARG.findall(message)]
    for pattern in patterns:
        match = re.search(pattern, text)
        if match:
            line = text.count("\n", 0, match.start()) + 1
            column = match.start() - (text.rfind("\n", 0, match.start()) + 1) + 1
            return line, column
    return None, None
