"""`robospec build` writes the same agents that `robospec.register` compiles at import time.

For the specs under specs/maniskill the built modules are byte for byte the cache entries'
modules: the same text run by the same interpreter, so the same classes (that they behave as
ManiSkill's hand-written agents is tests/test_equivalence.py's). The built package is also
imported under a name of its own after ``register``: its ``@register_agent()`` calls must leave
the registered classes in place (ManiSkill answers a taken uid with "already registered, skip").
What ``import``ing a build registers on its own is tests/test_build.py's.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import uuid
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest

pytestmark = pytest.mark.maniskill
pytest.importorskip("mani_skill")

from conftest import ROOT  # noqa: E402
from maniskill_compare import (  # noqa: E402
    MANISKILL_SPECS,
    TWINS,
    registered_maniskill_specs,
    shared_cache_dir,
)

UIDS = sorted(TWINS.values())


@pytest.fixture(scope="session")
def robospec_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One cache for the session: the specs compile once."""
    return shared_cache_dir(tmp_path_factory)


@pytest.fixture(scope="module")
def registration(robospec_cache: Path) -> Iterator[tuple[Path, dict[str, type]]]:
    """The cache folder and the classes ``robospec.register`` returned, registered for this
    module's tests only."""
    with registered_maniskill_specs(robospec_cache) as agents:
        yield robospec_cache, agents


@pytest.fixture(scope="module")
def built_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("build") / "rs_built"
    # the same spec argument as register_maniskill_specs: the docstrings name it
    result = subprocess.run(
        [sys.executable, "-m", "robospec.cli", "build", str(MANISKILL_SPECS), "-o", str(out)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    return out


@pytest.fixture(scope="module")
def built_package(
    built_dir: Path, registration: tuple[Path, dict[str, type]]
) -> Iterator[ModuleType]:
    """The built package, imported as ``rs_built_<random>`` after ``register`` ran (so its
    ``@register_agent()`` calls are the ones ManiSkill skips)."""
    name = f"rs_built_{uuid.uuid4().hex}"
    spec = importlib.util.spec_from_file_location(
        name, built_dir / "__init__.py", submodule_search_locations=[str(built_dir)]
    )
    assert spec is not None and spec.loader is not None
    package = importlib.util.module_from_spec(spec)
    sys.modules[name] = package
    try:
        spec.loader.exec_module(package)
        yield package
    finally:
        for module in [m for m in sys.modules if m == name or m.startswith(name + ".")]:
            del sys.modules[module]


def _cache_modules(cache_dir: Path) -> dict[str, Path]:
    """``{uid: module file}`` of the entries ``register`` wrote under ``cache_dir``."""
    modules: dict[str, Path] = {}
    for manifest_file in sorted(cache_dir.glob("*/manifest.json")):
        manifest = json.loads(manifest_file.read_text(encoding="utf-8"))
        modules[manifest["uid"]] = manifest_file.parent / manifest["module_file"]
    return modules


def test_built_modules_are_byte_identical_to_the_registered_cache_entries(
    built_dir: Path, registration: tuple[Path, dict[str, type]]
) -> None:
    cache_dir, _ = registration
    cached = _cache_modules(cache_dir)
    assert sorted(cached) == UIDS
    for uid, cache_file in cached.items():
        built_file = built_dir / cache_file.name
        assert built_file.is_file(), f"{uid}: the build has no {cache_file.name}"
        assert built_file.read_bytes() == cache_file.read_bytes(), uid


def test_importing_the_built_package_keeps_the_registered_classes(
    built_package: ModuleType, registration: tuple[Path, dict[str, type]]
) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    _, registered = registration
    assert sorted(built_package.AGENTS) == UIDS
    for uid in UIDS:
        assert built_package.AGENTS[uid] is not registered[uid]  # the build's own class ran ...
        assert REGISTERED_AGENTS[uid].agent_cls is registered[uid]  # ... and replaced nothing
