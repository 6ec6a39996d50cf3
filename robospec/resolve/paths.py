"""Where spec paths point: relative to the spec file, or into ManiSkill's asset folders.

``{maniskill_assets}`` is the asset folder inside the mani_skill package (PACKAGE_ASSET_DIR);
``{maniskill_data}`` is where ManiSkill downloads robots to (ASSET_DIR: ``$MS_ASSET_DIR/data``,
default ``~/.maniskill/data``). Both are found without importing ManiSkill (it costs seconds).
"""

from __future__ import annotations

import importlib.util
import os
from functools import cache
from pathlib import Path
from typing import Literal

ASSETS_PLACEHOLDER = "{maniskill_assets}"
DATA_PLACEHOLDER = "{maniskill_data}"


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


def maniskill_data_dir() -> Path:
    """ManiSkill's ``ASSET_DIR``, computed as mani_skill/__init__.py does."""
    root = os.getenv("MS_ASSET_DIR", os.path.join(os.path.expanduser("~"), ".maniskill"))
    return Path(root) / "data"


def split_data(text: str) -> str | None:
    """The part after ``{maniskill_data}/``, or None when the path is not in ManiSkill's data."""
    if not text.startswith(DATA_PLACEHOLDER):
        return None
    return text[len(DATA_PLACEHOLDER) :].lstrip("/")


FolderKind = Literal["maniskill_assets", "maniskill_data"]


def in_maniskill(text: str) -> tuple[FolderKind, str, Path | None] | None:
    """The ManiSkill folder a path starts with: its kind, the path below it and where that is
    on this machine (None: the assets, and ManiSkill is not installed); None for a path that
    names no ManiSkill folder."""
    in_data = split_data(text)
    if in_data is not None:
        return "maniskill_data", in_data, maniskill_data_dir() / in_data
    in_assets = split_assets(text)
    if in_assets is not None:
        assets = maniskill_assets_dir()
        return "maniskill_assets", in_assets, assets / in_assets if assets is not None else None
    return None
