"""Where the frozen spec model is kept: one module per pydantic and model source, in the cache.

:mod:`robospec.model.freeze` writes the frozen module for the pydantic installed; that costs an
import of pydantic and a build of every model's schema (a few tenths of a second), so its text
is kept in robospec's user cache folder under a key of everything it is made from: the model
sources, pydantic-core's and pydantic's versions, and Python's. A change to any of them makes a
new key, so a stale module is never used, and nothing needs regenerating by hand. Files whose
key no longer matches stay behind unused; deleting the folder is always safe.

This module imports neither pydantic nor anything of the model: the warm path runs it.
"""

from __future__ import annotations

import importlib.util
import sys
import zlib
from pathlib import Path

import pydantic_core

from robospec.files import cache_root

MODEL_FOLDER = Path(__file__).parent
"""The model's sources (every module here: the models, their rules, the freezer, the records)."""

FORMAT = "1"
"""The layout of a cache entry; a change to how entries are read or named bumps it."""


def entry_path() -> Path:
    """The cached frozen module for the model sources and the pydantic here."""
    return cache_root() / "model" / f"frozen_{model_key()}.py"


def model_key() -> str:
    """A checksum of everything the frozen module's text depends on.

    CRC-32, not a cryptographic hash: it tells versions of one's own files apart (whoever can
    write the cache can write any entry anyway), and hashlib's import alone would cost `validate`
    more than all of this module."""
    python = f"{sys.implementation.name} {sys.version_info[0]}.{sys.version_info[1]}"
    checksum = 0
    for part in (FORMAT, pydantic_core.__version__, _pydantic_version(), python):
        checksum = zlib.crc32(part.encode() + b"\0", checksum)
    for path in sorted(MODEL_FOLDER.glob("*.py")):
        checksum = zlib.crc32(path.name.encode() + b"\0" + path.read_bytes() + b"\0", checksum)
    return f"{checksum:08x}"


def _pydantic_version() -> str:
    # pydantic pins one pydantic-core, but patch releases of pydantic share one and may make
    # different schemas; its version module is read, not imported (importing it loads pydantic)
    found = importlib.util.find_spec("pydantic")
    if found is None or found.origin is None:
        return "no pydantic"
    try:
        return Path(found.origin).with_name("version.py").read_text(encoding="utf-8")
    except OSError:
        return "unreadable"
