"""robospec: declarative robot specs (YAML/TOML) compiled into registered ManiSkill agents.

``robospec.register("specs/")`` compiles and registers at import time; the ``robospec`` CLI
validates, builds packages and prints the JSON Schema. Importing this package is cheap: the
pipeline and ManiSkill load only when used.
"""

from __future__ import annotations

from robospec.diagnostics import Diagnostic, SpecError
from robospec.registration import register

__version__ = "0.1.0"
__all__ = ["Diagnostic", "SpecError", "__version__", "register"]
