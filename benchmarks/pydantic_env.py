"""A Python environment with an older pydantic, to measure robospec with it side by side.

The benchmarks' own Python has the project's virtual environment (the newest pydantic). This
makes, once, a second virtual environment in the temporary folder with ``pydantic==VERSION``
and robospec's other dependencies as pyproject.toml lists them; robospec itself is not
installed there: children run it from this checkout (``python -m robospec.cli`` in ROOT).
"""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
from pathlib import Path

import tomllib
from measure import ROOT

OLDER_PYDANTIC = "2.9.2"
"""The older pydantic measured beside the newest (pyproject.toml allows 2.7 and later)."""


def python_with_pydantic(version: str) -> tuple[Path | None, str]:
    """The interpreter of an environment with ``pydantic==version``, made on first use, and
    ``""``; or None and why it could not be made (offline, say)."""
    folder = Path(tempfile.gettempdir()) / f"robospec-bench-pydantic-{version}"
    python = folder / "bin" / "python"
    requirements = requirements_with(version)
    stamp = folder / "robospec-requirements.txt"
    if python.exists() and stamp.exists() and stamp.read_text() == "\n".join(requirements):
        return python, ""
    pip = [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    steps = [[sys.executable, "-m", "venv", "--clear", str(folder)], [*pip, *requirements]]
    for step in steps:
        try:
            done = subprocess.run(step, capture_output=True, text=True, timeout=900)
        except (OSError, subprocess.TimeoutExpired) as exc:
            return None, f"`{' '.join(step[1:4])}` failed: {exc}"
        if done.returncode != 0:
            last = (done.stderr.strip().splitlines() or ["(no message)"])[-1]
            return None, f"`{' '.join(step[1:4])}` failed: {last}"
    stamp.write_text("\n".join(requirements))
    return python, ""


def requirements_with(version: str) -> list[str]:
    """robospec's dependencies (pyproject.toml), with pydantic pinned to ``version``."""
    with (ROOT / "pyproject.toml").open("rb") as stream:
        dependencies = tomllib.load(stream)["project"]["dependencies"]
    others = [d for d in dependencies if _name(d) != "pydantic"]
    return [f"pydantic=={version}", *others]


def _name(requirement: str) -> str:
    return re.split(r"[\s<>=!~;\[]", requirement, maxsplit=1)[0].lower()


def pydantic_version(python: Path | str) -> str:
    """``pydantic X (pydantic-core Y)`` as ``python`` imports them."""
    code = "import pydantic, pydantic_core; print(pydantic.VERSION, pydantic_core.__version__)"
    done = subprocess.run([str(python), "-c", code], capture_output=True, text=True, check=True)
    pydantic, core = done.stdout.split()
    return f"pydantic {pydantic} (pydantic-core {core})"
