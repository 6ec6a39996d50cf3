"""robospec: declarative robot specs (YAML/TOML) compiled into registered ManiSkill agents.

``robospec.register("specs/")`` compiles and registers at import time; the ``robospec`` CLI
validates, builds packages and prints the JSON Schema. Importing this package is cheap: the
pipeline and ManiSkill load only when used.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from robospec.diagnostics import Diagnostic, SpecError
from robospec.version import __version__

if TYPE_CHECKING:
    from robospec.output.register import register, sim_config_for

__all__ = ["Diagnostic", "SpecError", "__version__", "register", "sim_config_for"]


def __getattr__(name: str) -> Any:
    # registration's imports (shutil, tempfile, hashlib, ...) are not needed by the CLI's
    # validate, which imports this package first
    if name in ("register", "sim_config_for"):
        import importlib

        return getattr(importlib.import_module("robospec.output.register"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
