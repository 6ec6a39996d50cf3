"""The TOML parser: the standard library's ``tomllib`` (Python 3.11 on), ``tomli`` before it
(the package tomllib was taken from, a dependency there: pyproject.toml)."""

from __future__ import annotations

import sys

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

__all__ = ["tomllib"]
