"""What ManiSkill, SAPIEN and their libraries print while robospec loads and steps a robot, told
once per distinct message, with a count and what it means.

SAPIEN's C++ logger writes straight to the process's stderr (``[time] [SAPIEN] [warning] ...``),
ManiSkill logs through Python's ``logging``, Gymnasium and SAPIEN's Python code warn through
``warnings``; loading a Unitree G1 alone prints one SAPIEN warning per collision mesh.
:func:`captured_output` sends all of it, file descriptors included, to a file for the length of
a block, and :class:`UpstreamLog` reads that file back as :class:`UpstreamMessage` records:
timestamps dropped, file paths folded into ``<path>`` so that "File not found: A" and "File not
found: B" count as one message (with the first path as its example), and a meaning for the
messages robospec knows.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO

_HIDDEN_BY_DEFAULT = (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning)
# ``warnings`` output, as :func:`captured_output` writes it: one line per warning
_WARNING_PREFIX = "[python-warning] "
_ANSI = re.compile(r"\x1b\[[0-9;]*m")
# SAPIEN's spdlog lines: [2026-11-24 07:20:27.678] [SAPIEN] [warning] text
_SPDLOG = re.compile(r"^\[\d{4}-\d\d-\d\d [\d:.]+\] \[(?P<source>[^\]]+)\] \[(?P<level>\w+)\] ")
# ManiSkill's logger: 2026-11-24 07:20:27,678 - mani_skill  - WARNING - text
_LOGGING = re.compile(r"^\d{4}-\d\d-\d\d [\d:,.]+ - (?P<source>\S+)\s*- (?P<level>\w+) - ")
# an absolute path, or a relative one with a file extension, in a message
# (an absolute one starts a word: the "/O" of "I/O" is none)
_PATH = re.compile(r"(?:(?<![\w.])/[^\s'\"(),]+|\b[\w.-]+(?:/[\w.-]+)+\.\w+)")

# (pattern over the message's text, what it means for the robot being loaded)
MEANINGS: tuple[tuple[re.Pattern[str], str], ...] = (
    (
        re.compile(r"loading multiple convex collision meshes from STL file is unsupported"),
        "the robot loads collision meshes with load_multiple_collisions, which splits a mesh "
        "file into its convex parts; an STL file has no parts, so SAPIEN splits it into "
        "connected pieces and takes each piece's convex hull. Harmless for loading; a "
        "concave piece collides as its hull",
    ),
    (
        re.compile(r"^File not found: "),
        "a mesh file the description names does not exist: SAPIEN loads that shape as "
        "nothing, so a missing collision mesh leaves its link without collision there",
    ),
    (
        re.compile(r"Failed to find system libvulkan"),
        "SAPIEN looks for Vulkan, which it needs only to render; physics does not use it",
    ),
    (
        re.compile(r"Box (low|high)'s precision lowered by casting to float32"),
        "a controller's action bounds are float64 and Gymnasium keeps action spaces in "
        "float32: harmless",
    ),
    (
        re.compile(r"__array_wrap__ must accept context"),
        "a NumPy 2 deprecation met inside torch: harmless",
    ),
    (
        re.compile(r"is not in the task's list of supported robots"),
        "the task places the robots it lists by their uid; another robot is loaded where the "
        "task loads any robot, at its default pose: it runs, its poses are not tuned for it",
    ),
    (
        re.compile(r"failed to find a rendering device"),
        "SAPIEN found no GPU to render with; robots still load without visuals for physics",
    ),
)


@dataclass(frozen=True)
class UpstreamMessage:
    """One distinct message, as often as it was said."""

    source: str  # SAPIEN, mani_skill, Python (a warning), or "output"
    level: str  # warning, error, critical, info, a warning's category ("" when none is said)
    text: str  # with paths folded into <path>
    count: int
    example: str | None  # the first path folded away, if any
    meaning: str | None  # what it means, when robospec knows

    def describe(self) -> str:
        """One line: ``SAPIEN warning (48x): text (e.g. path) -- meaning``."""
        head = " ".join(part for part in (self.source, self.level) if part)
        text = f"{head} ({self.count}x): {self.text}"
        if self.example:
            text += f" (e.g. {self.example})"
        if self.meaning:
            text += f" -- {self.meaning}"
        return text

    def to_json(self) -> dict[str, object]:
        return {
            "source": self.source,
            "level": self.level,
            "text": self.text,
            "count": self.count,
            "example": self.example,
            "meaning": self.meaning,
        }


def parse_line(line: str) -> tuple[str, str, str] | None:
    """``(source, level, text)`` of one line of output, or None for a blank line."""
    line = _ANSI.sub("", line).rstrip()
    if not line.strip():
        return None
    if line.startswith(_WARNING_PREFIX):
        category, _, text = line[len(_WARNING_PREFIX) :].partition(": ")
        return "Python", category, text
    for pattern in (_SPDLOG, _LOGGING):
        match = pattern.match(line)
        if match:
            return match["source"].strip(), match["level"].lower(), line[match.end() :]
    return "output", "", line.strip()


def meaning_of(text: str) -> str | None:
    return next((meaning for pattern, meaning in MEANINGS if pattern.search(text)), None)


@dataclass
class _Seen:
    count: int
    example: str | None


class UpstreamLog:
    """Lines of output, folded into distinct messages in the order first said."""

    def __init__(self) -> None:
        self._seen: dict[tuple[str, str, str], _Seen] = {}

    def feed(self, text: str) -> None:
        for line in text.splitlines():
            parsed = parse_line(line)
            if parsed is None:
                continue
            source, level, said = parsed
            paths = _PATH.findall(said)
            key = (source, level, _PATH.sub("<path>", said))
            self._seen.setdefault(key, _Seen(0, paths[0] if paths else None)).count += 1

    def messages(self) -> list[UpstreamMessage]:
        return [
            UpstreamMessage(source, level, text, seen.count, seen.example, meaning_of(text))
            for (source, level, text), seen in self._seen.items()
        ]

    def lines(self, *levels: str) -> list[UpstreamMessage]:
        """The messages said at one of ``levels`` (all when none are named)."""
        return [m for m in self.messages() if not levels or m.level in levels]


class CapturedOutput:
    """The output of a :func:`captured_output` block, read once the block is over."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.log = UpstreamLog()

    def messages(self) -> list[UpstreamMessage]:
        return self.log.messages()


def _show_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: object = None,
    line: str | None = None,
) -> None:
    text = str(message).replace("\n", " ")
    sys.stderr.write(f"{_WARNING_PREFIX}{category.__name__}: {text}\n")


class _CurrentStderr:
    """Whatever ``sys.stderr`` is when written to: the stream a logging handler keeps when
    it was made inside a captured block."""

    def write(self, text: str) -> int:
        return sys.stderr.write(text)

    def flush(self) -> None:
        sys.stderr.flush()


def _rebind_handlers(stream: TextIO) -> None:
    """Point every logging handler that took ``stream`` (the block's sys.stderr) at
    sys.stderr as it will be. A logger whose StreamHandler was made inside the block
    (ManiSkill makes its own when ``mani_skill`` is first imported) keeps the sys.stderr of
    that moment; the block closes that stream, and every later message would end in "---
    Logging error ---" and a traceback instead of being said (and gathered by the next block)."""
    import logging

    loggers = [logging.getLogger(), *logging.Logger.manager.loggerDict.values()]
    for logger in loggers:
        for handler in getattr(logger, "handlers", ()):
            if isinstance(handler, logging.StreamHandler) and handler.stream is stream:
                handler.setStream(_CurrentStderr())


@contextmanager
def captured_output(path: Path | None = None) -> Iterator[CapturedOutput]:
    """Within the block, whatever is written to file descriptors 1 and 2 (SAPIEN's C++ logger,
    ``print``, logging) and every Python warning goes to ``path`` (a temporary file when None)
    instead of the terminal; afterwards ``.messages()`` tells each distinct message once. The
    file stays for a caller that named it (a crashed process's last words are read from it)."""
    own = path is None
    if path is None:
        handle, name = tempfile.mkstemp(prefix="robospec-upstream-", suffix=".log")
        os.close(handle)
        path = Path(name)
    captured = CapturedOutput(path)
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    streams = sys.stdout, sys.stderr
    target = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
    # Python's own writes go there too, whatever sys.stdout was (a test's capture, a notebook)
    stream = open(target, "w", encoding="utf-8", errors="replace", buffering=1, closefd=False)
    try:
        os.dup2(target, 1)
        os.dup2(target, 2)
        sys.stdout = sys.stderr = stream
        with warnings.catch_warnings():
            # every warning each time it is said (to count it), but none that Python hides
            # unless asked (DeprecationWarning and the like): they are not for users
            warnings.simplefilter("always")
            for category in _HIDDEN_BY_DEFAULT:
                warnings.filterwarnings("ignore", category=category)
            warnings.showwarning = _show_warning
            yield captured
    finally:
        stream.flush()
        sys.stdout, sys.stderr = streams
        _rebind_handlers(stream)
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        stream.close()
        for fd in (*saved, target):
            os.close(fd)
        captured.log.feed(path.read_text(encoding="utf-8", errors="replace"))
        if own:
            path.unlink(missing_ok=True)
