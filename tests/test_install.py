"""The test environment is complete: what the full suite needs is installed, so a missing extra
fails here by name instead of skipping hundreds of tests in silence."""

from __future__ import annotations

import importlib.util

import pytest
from conftest import INSTALL_MANISKILL, MANISKILL_MODULES


@pytest.mark.parametrize("module", MANISKILL_MODULES)
def test_the_maniskill_extra_is_installed(module: str) -> None:
    # found, not imported: the fast loop runs this too, and importing mani_skill costs seconds
    assert importlib.util.find_spec(module) is not None, INSTALL_MANISKILL
