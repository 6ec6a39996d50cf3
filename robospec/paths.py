"""Where spec paths point: relative to the spec file, or into ManiSkill's bundled assets.

``{maniskill_assets}`` is found without importing ManiSkill (importing it costs seconds).
"""

from __future__ import annotations

import importlib.util
from functools import cache
from pathlib import Path

ASSETS_PLACEHOLDER = "{maniskill_assets}"


@cache
def maniskill_assets_dir() -> Path | None:
    spec = importlib.util.find_spec("mani_skill")
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations))) / "assets"


def split_assets(text: str) -> str | None:
    """The part after ``{maniskill_assets}/``, or None when the path is not in the assets."""
    if not text.startswith(ASSETS_PLACEHOLDER):
        return None
    return text[len(ASSETS_PLACEHOLDER) :].lstrip("/")
