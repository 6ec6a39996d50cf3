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


def test_setup_installs_without_setuptools_editable_install_box() -> None:
    """pip shows setuptools' "Editable installation" notice, a box of asterisks, whatever its
    --quiet says: scripts/setup's pip install filters that warning, and only that one. Proved
    on setuptools' own notice, raised in a process with the filter the script sets."""
    import os
    import re
    import subprocess
    import sys

    from conftest import ROOT

    script = (ROOT / "scripts" / "setup").read_text(encoding="utf-8")
    (install,) = [line for line in script.splitlines() if "pip install --quiet -e" in line]
    found = re.match(r'PYTHONWARNINGS="([^"]+)" ', install)
    assert found, install
    notice = (
        "from setuptools.warnings import InformationOnly\n"
        "InformationOnly.emit('Editable installation.', 'Please be careful with folders')\n"
        "import warnings; warnings.warn('another warning')\n"
    )
    for filters, shown in ((found.group(1), False), ("", True)):
        result = subprocess.run(
            [sys.executable, "-c", notice],
            capture_output=True,
            text=True,
            env={**os.environ, "PYTHONWARNINGS": filters},
            check=True,
        )
        assert ("Editable installation" in result.stderr) is shown, result.stderr
        assert "another warning" in result.stderr  # nothing else is silenced
