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


def test_pyproject_is_read_by_setuptools_without_a_deprecation() -> None:
    """`pip install -e .` prints no setuptools banner (e.g. about a license given as a TOML
    table): the same configuration reading, with every warning an error."""
    import warnings

    from conftest import ROOT
    from setuptools.config.pyprojecttoml import apply_configuration
    from setuptools.dist import Distribution

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        apply_configuration(Distribution(), ROOT / "pyproject.toml")
