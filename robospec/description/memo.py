"""Parsed descriptions remembered for a long-lived process (the language server), reused until
their file changes.

A one-shot ``robospec validate`` parses each description once anyway; a language server compiles
the same spec on every keystroke, and a large description (a humanoid, an expanded xacro) would
be parsed again each time. Inside :func:`remembering`, :func:`robospec.description.load_description`
asks the memo first. A remembered parse is reused only while the inputs that made it are the same:
the file's content (a hash of its bytes, so an edit within the same second of mtime is still seen),
the SRDF beside a URDF (its mtime and size), the packages and, for an expanded xacro, the text.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic

if TYPE_CHECKING:
    from robospec.description.facts import RobotDescription

Loaded = tuple["RobotDescription | None", list[Diagnostic]]
Key = tuple[object, ...]

_ACTIVE: ContextVar[DescriptionMemo | None] = ContextVar("robospec_description_memo", default=None)


def _digest(data: bytes) -> str:
    # hashlib (and the OpenSSL it loads) only where a memo is active: `validate` has none
    import hashlib

    return hashlib.blake2b(data, digest_size=16).hexdigest()


def _stat(path: str) -> tuple[int, int] | None:
    try:
        status = os.stat(path)
    except (OSError, ValueError):
        return None
    return status.st_mtime_ns, status.st_size


class DescriptionMemo:
    """Descriptions by path; each entry keeps the key it was parsed under (one per path, so a
    file edited many times holds one parse, not one per version)."""

    def __init__(self) -> None:
        self._entries: dict[tuple[str, str], tuple[Key, Loaded]] = {}
        self.parses = 0  # how many times a description was really parsed (tests and benchmarks)

    def key(
        self,
        path: str,
        text: str | bytes | None,
        packages: Mapping[str, str] | None,
        beside_file: bool | None = None,
    ) -> Key | None:
        """What a parse of ``path`` depends on; None when the file cannot be read (the loader
        then reports that, uncached)."""
        if text is None:
            try:
                with open(path, "rb") as handle:
                    content = _digest(handle.read())
            except (OSError, ValueError):
                return None
        else:
            content = _digest(text.encode() if isinstance(text, str) else text)
        reads_srdf = text is None if beside_file is None else beside_file
        srdf = _stat(path[:-4] + "srdf") if reads_srdf else None
        return (content, srdf, tuple(sorted((packages or {}).items())))

    def load(
        self,
        path: str,
        kind: str,
        text: str | bytes | None,
        packages: Mapping[str, str] | None,
        parse: Callable[[], Loaded],
        beside_file: bool | None = None,
    ) -> Loaded:
        key = self.key(path, text, packages, beside_file)
        if key is None:
            return parse()
        known = self._entries.get((path, kind))
        if known is not None and known[0] == key:
            description, diagnostics = known[1]
            return description, list(diagnostics)
        self.parses += 1
        description, diagnostics = parse()
        self._entries[(path, kind)] = (key, (description, list(diagnostics)))
        return description, diagnostics

    def paths(self) -> list[str]:
        """The description files remembered (a server watches them)."""
        return sorted({path for path, _ in self._entries})


def active_memo() -> DescriptionMemo | None:
    return _ACTIVE.get()


@contextmanager
def remembering(memo: DescriptionMemo) -> Iterator[DescriptionMemo]:
    """Within the block, descriptions are loaded through ``memo``."""
    token = _ACTIVE.set(memo)
    try:
        yield memo
    finally:
        _ACTIVE.reset(token)
