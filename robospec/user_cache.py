"""robospec's user cache folder, shared by the stages that keep something there: the model (its
frozen form, robospec.model.frozen_cache) and output (the register cache, robospec.output.register).

It lives apart from both so that neither imports the other, and so that the register cache's warm
path loads nothing of the model.
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
