"""Expand xacro files in a child process with time and memory limits.

A xacro file is a program: ``${...}`` and ``$(eval ...)`` evaluate Python expressions (its
"sandbox" can be escaped to reach ``os``), and ``${2**2**34}`` alone exhausts memory. So expansion
never happens in the robospec process: a fresh interpreter runs ``_xacro_child.py`` in the xacro
file's folder, with no stdin, in a process group of its own, with limits set before xacro is
imported:

- wall clock: ``timeout_s`` (default 20 s, or ``ROBOSPEC_XACRO_TIMEOUT`` seconds); CPU time
  (``RLIMIT_CPU``) a little above it, in case this process dies and cannot kill;
- memory: ``memory_bytes`` of address space (``RLIMIT_AS``; default 1 GiB, or
  ``ROBOSPEC_XACRO_MEMORY_MB`` MiB);
- output: what it prints goes to a file capped by ``RLIMIT_FSIZE`` (64 MiB); its answer comes
  through a pipe only it holds, read up to ``memory_bytes``;
- include depth: 50 nested ``xacro:include``s (a file including itself stops there, at once);
- processes: when the child ends, for any reason, its whole process group is killed, so nothing
  the file started (``os.system("... &")``, a fork) outlives the expansion.

xacro is never imported here.
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
import threading
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from robospec.diagnostics import Diagnostic, Location, error, line_column
from robospec.diagnostics.codes import PACKAGE_NOT_FOUND, XACRO_FAILED, XACRO_OVER_LIMIT

_CHILD = Path(__file__).with_name("_xacro_child.py")
# The child answers $(find NAME) with this module, loaded by its path (it imports no robospec).
_PACKAGES = Path(__file__).with_name("packages.py")

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
# How many files of an include chain a hint names.
_MAX_CHAIN = 6

_TIME_HINT = "expanding a xacro file runs it: look for runaway recursion or expressions"
_MEMORY_HINT = "expanding a xacro file runs it: look for huge numbers, strings or repetitions"


DEFAULT_TIMEOUT_S = 20.0
DEFAULT_MEMORY_BYTES = 1 << 30
TIMEOUT_ENV = "ROBOSPEC_XACRO_TIMEOUT"
MEMORY_ENV = "ROBOSPEC_XACRO_MEMORY_MB"
OUTPUT_LIMIT_BYTES = 64 << 20
MAX_INCLUDE_DEPTH = 50


def configured_limits() -> tuple[float, int]:
    """(timeout in seconds, memory in bytes): the defaults, or what the environment sets.
    A value that is not a positive number is ignored (limits are never switched off)."""
    timeout_s = _positive_env(TIMEOUT_ENV)
    memory_mb = _positive_env(MEMORY_ENV)
    return (
        DEFAULT_TIMEOUT_S if timeout_s is None else timeout_s,
        DEFAULT_MEMORY_BYTES if memory_mb is None else int(memory_mb * (1 << 20)),
    )


def _positive_env(name: str) -> float | None:
    try:
        value = float(os.environ.get(name, ""))
    except ValueError:
        return None
    return value if math.isfinite(value) and value > 0 else None


def expand_xacro(
    path: str,
    args: Mapping[str, str],
    *,
    packages: Mapping[str, str] | None = None,
    timeout_s: float | None = None,
    memory_bytes: int | None = None,
) -> tuple[str | None, list[Diagnostic]]:
    """Expand the xacro file at ``path`` with ``args`` (``xacro:arg`` values).

    ``$(find NAME)`` is the folder of ROS package NAME: ``packages`` (name -> absolute folder)
    first, then as robospec.description.packages finds it from the file's folder up.

    Returns the expanded URDF text and no diagnostics, or ``None`` and diagnostics located at the
    xacro file (RS053: xacro reported an error; RS054: the expansion hit ``timeout_s``,
    ``memory_bytes`` or the output limit; RS058: ``$(find NAME)`` names a package found
    nowhere). Limits not given come from :func:`configured_limits`. Never raises on bad input.
    """
    default_timeout, default_memory = configured_limits()
    timeout_s = default_timeout if timeout_s is None else timeout_s
    memory_bytes = default_memory if memory_bytes is None else memory_bytes
    where = Location(path)
    abs_path = os.path.abspath(path)
    if not os.path.isfile(abs_path):
        return None, [error(where, XACRO_FAILED, f"xacro expansion failed: no such file '{path}'")]
    try:
        mappings = {str(k): str(v) for k, v in args.items()}
        folders = {str(k): str(v) for k, v in (packages or {}).items()}
        result, stderr, killed = _run_child(abs_path, mappings, folders, timeout_s, memory_bytes)
    except OSError as e:  # e.g. the interpreter cannot be started
        return None, [error(where, XACRO_FAILED, f"xacro expansion failed: cannot start it ({e})")]

    if killed:
        return None, [
            error(
                where,
                XACRO_OVER_LIMIT,
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
    if result.get("kind") == "package":
        return None, [_package_error(path, abs_path, result)]
    if result.get("kind") == "output":
        return None, [
            error(
                where,
                XACRO_OVER_LIMIT,
                f"xacro expansion printed more than {_bytes(OUTPUT_LIMIT_BYTES)} and was stopped",
                "expanding a xacro file runs it: look for messages printed in a loop",
            )
        ]
    return None, [_xacro_error(path, abs_path, result)]


def _run_child(
    abs_path: str,
    mappings: dict[str, str],
    packages: dict[str, str],
    timeout_s: float,
    memory_bytes: int,
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
        str(OUTPUT_LIMIT_BYTES),
        str(MAX_INCLUDE_DEPTH),
        json.dumps(packages),
        str(_PACKAGES),
    ]
    # Its prints go to a file (capped in the child by RLIMIT_FSIZE), never into our memory.
    with tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(
            cmd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=err,
            cwd=os.path.dirname(abs_path),
            start_new_session=True,  # its own process group, so the kill reaches any children
        )
        answer = _AnswerReader(proc, limit=max(1 << 20, memory_bytes))
        try:
            finished = _wait_unreaped(proc, timeout_s)
        finally:
            # Always, even after a clean exit: whatever the file started dies with the group.
            # The child is not reaped yet, so its pid (the group's id) cannot have been reused.
            _kill(proc)
            proc.wait()
            answer.join()
        killed = not finished or _died_of_signal(proc.returncode, "SIGXCPU")
        flooded = _died_of_signal(proc.returncode, "SIGXFSZ")
        err.seek(0, os.SEEK_END)
        size = err.tell()
        err.seek(max(0, size - _STDERR_TAIL))
        stderr = err.read().decode("utf-8", "replace")
    if killed:
        return None, stderr, True
    if flooded:
        return {"ok": False, "kind": "output"}, stderr, False
    if answer.overflowed:
        return {"ok": False, "kind": "memory"}, stderr, False
    try:
        parsed = json.loads(answer.data().decode("ascii"))
    except (UnicodeDecodeError, ValueError):
        return None, stderr, False
    return (parsed if isinstance(parsed, dict) else None), stderr, False


class _AnswerReader:
    """Drain the child's answer pipe in a thread, keeping at most ``limit`` bytes."""

    def __init__(self, proc: subprocess.Popen[bytes], limit: int) -> None:
        assert proc.stdout is not None
        self._pipe = proc.stdout
        self._limit = limit
        self._chunks: list[bytes] = []
        self._size = 0
        self.overflowed = False
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while chunk := self._pipe.read(1 << 16):
            if self._size + len(chunk) > self._limit:
                self.overflowed = True
                continue  # keep draining so the writer is not blocked; the kill ends it
            self._chunks.append(chunk)
            self._size += len(chunk)

    def join(self) -> None:
        self._thread.join()
        self._pipe.close()

    def data(self) -> bytes:
        return b"".join(self._chunks)


def _wait_unreaped(proc: subprocess.Popen[bytes], timeout_s: float) -> bool:
    """Wait until the child exits (True) or ``timeout_s`` passes (False), without reaping it."""
    waitid = getattr(os, "waitid", None)
    if waitid is None:  # e.g. macOS: reap it; the group kill right after is still best effort
        try:
            proc.wait(timeout=timeout_s)
            return True
        except subprocess.TimeoutExpired:
            return False
    deadline = time.monotonic() + timeout_s
    pause = 0.001
    while True:
        if waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None:
            return True
        left = deadline - time.monotonic()
        if left <= 0:
            return False
        time.sleep(min(pause, left))
        pause = min(pause * 2, 0.02)


def _kill(proc: subprocess.Popen[bytes]) -> None:
    try:
        if hasattr(os, "killpg"):
            os.killpg(proc.pid, signal.SIGKILL)
        else:
            proc.kill()
    except (ProcessLookupError, PermissionError):
        pass  # the group is already gone


def _died_of_signal(returncode: int | None, name: str) -> bool:
    number = getattr(signal, name, None)
    return returncode is not None and number is not None and returncode == -number


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
        XACRO_OVER_LIMIT,
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
    return error(where, XACRO_FAILED, f"xacro expansion failed: the xacro process crashed ({last})")


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
        shown_files = [_display_path(path, abs_path, f) for f in reversed(files)]
        if len(shown_files) > _MAX_CHAIN:  # a runaway include: the innermost and the top
            hidden = len(shown_files) - _MAX_CHAIN
            shown_files = [*shown_files[: _MAX_CHAIN - 1], f"({hidden} more)", shown_files[-1]]
        hint = f"included as {' <- '.join(shown_files)}"
    return error(
        Location(shown, max(1, line or 1), max(1, column if isinstance(column, int) else 1)),
        XACRO_FAILED,
        f"xacro expansion failed: {_tidy(message)}",
        hint,
    )


def _package_error(path: str, abs_path: str, result: Mapping[str, Any]) -> Diagnostic:
    """RS058 at the ``$(find NAME)`` that names a package found nowhere."""
    name = str(result.get("package") or "")
    file = os.path.join(os.path.dirname(abs_path), str(result.get("file") or abs_path))
    line, column = _find_text(file, r"\$\(\s*find\s+" + re.escape(name) + r"\s*\)")
    if line is None:
        line, column = _find_text(file, r"find\(\s*['\"]" + re.escape(name) + r"['\"]\s*\)")
    return error(
        Location(_display_path(path, abs_path, file), line or 1, column or 1),
        PACKAGE_NOT_FOUND,
        f"ROS package '{name}' not found for $(find {name})",
        f"say where it is in the spec: `description: {{packages: {{{name}: FOLDER}}}}` (no "
        f"package.xml names it, and no folder '{name}' is beside the xacro file's folder or "
        "above it)",
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
    # ${expr} with any spacing inside the braces: xacro quotes the expression stripped.
    patterns = [r"\$\{\s*" + re.escape(e.strip()) + r"\s*\}" for e in _EXPRESSION.findall(message)]
    patterns += [r"\$\(arg\s+" + re.escape(a) + r"\s*\)" for a in _UNDEFINED_ARG.findall(message)]
    for pattern in patterns:
        line, column = _find_text(file, pattern)
        if line is not None:
            return line, column
    return None, None


def _find_text(file: str, pattern: str) -> tuple[int | None, int | None]:
    """Line and column of the first match of ``pattern`` in ``file`` (None, None if none)."""
    try:
        text = Path(file).read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None, None
    match = re.search(pattern, text)
    return line_column(text, match.start()) if match else (None, None)
