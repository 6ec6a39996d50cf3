"""robospec's own files: the user cache folder, and how a file is written so that a reader sees
the old text or the new, never a part.

Shared by stages that must not import each other — the model (its frozen form,
robospec.model.frozen_cache), output (the register cache) and the authoring commands — and
light: the register cache's warm path and the model's load nothing else from here.
"""

from __future__ import annotations

import os
from pathlib import Path


def cache_root() -> Path:
    """``$ROBOSPEC_CACHE_DIR``, else ``$XDG_CACHE_HOME/robospec``, else ``~/.cache/robospec``."""
    configured = os.environ.get("ROBOSPEC_CACHE_DIR")
    if configured:
        return Path(configured)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "robospec"


def write_atomically(path: Path, text: str | bytes, mode: int | None = None) -> None:
    """Write ``text`` (or bytes) to ``path`` through a temporary file renamed over it, with
    permissions ``mode`` when given (else the temporary file's: private)."""
    import tempfile  # only writers pay for it: reading a warm cache does not

    path.parent.mkdir(parents=True, exist_ok=True)
    handle, staging = tempfile.mkstemp(prefix=".robospec-", suffix=".tmp", dir=path.parent)
    try:
        data = text.encode("utf-8") if isinstance(text, str) else text
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        if mode is not None:
            os.chmod(staging, mode)
        os.replace(staging, path)
    except BaseException:
        Path(staging).unlink(missing_ok=True)
        raise
