"""Where the editor engines the tests drive live, and how they are started.

yaml-language-server is installed by ``npm ci`` into tools/editors/node_modules and taplo by pip
(the dev extra), both from scripts/setup. A missing engine fails the test with a message naming
scripts/setup instead of skipping it: CI installs them, so a skip would hide a broken setup.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT

YAML_LANGUAGE_SERVER = (
    ROOT / "tools" / "editors" / "node_modules" / "yaml-language-server" / "bin"
) / "yaml-language-server"


def yaml_language_server_argv() -> list[str]:
    """The command line that runs yaml-language-server over stdio."""
    node = shutil.which("node")
    if node is None:
        pytest.fail("node is not on PATH: install node >= 20, then run scripts/setup")
    if not YAML_LANGUAGE_SERVER.is_file():
        pytest.fail(f"{YAML_LANGUAGE_SERVER.relative_to(ROOT)} is missing: run scripts/setup")
    return [node, str(YAML_LANGUAGE_SERVER), "--stdio"]


def taplo_executable() -> str:
    """The taplo command: the one next to this Python (the venv's), else one on PATH."""
    beside_python = Path(sys.executable).parent / "taplo"
    if beside_python.is_file():
        return str(beside_python)
    on_path = shutil.which("taplo")
    if on_path is None:
        pytest.fail("taplo is missing (the dev extra's taplo wheel): run scripts/setup")
    return on_path


def narrowed_schema(spec: Path, out: Path) -> Path:
    """Write the schema narrowed to ``spec``'s robot by `robospec schema --for` to ``out``."""
    result = subprocess.run(
        [sys.executable, "-m", "robospec.cli", "schema", "--for", str(spec), "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=ROOT,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    return out
