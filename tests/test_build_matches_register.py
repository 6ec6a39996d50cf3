"""`robospec build` writes the same agents that `robospec.register` compiles at import time.

Both go through one function (robospec.output.modules.robot_files), so for the specs under
specs/maniskill the modules are byte for byte the same. The classes are compared too, attribute
by attribute, importing the built package under a name of its own: importing it runs
``@register_agent()`` again, which ManiSkill answers with "already registered, skip", so the
built classes are taken from the package itself, never from ManiSkill's registry.
"""

from __future__ import annotations

import importlib.util
import inspect
import json
import subprocess
import sys
import uuid
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

pytestmark = pytest.mark.maniskill
pytest.importorskip("mani_skill")

from conftest import ROOT  # noqa: E402
from maniskill_compare import (  # noqa: E402
    LOADER_FLAGS,
    MANISKILL_SPECS,
    TWINS,
    assert_same_controller_configs,
    assert_same_keyframes,
    assert_same_sensor_configs,
    assert_same_value,
    description_file,
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


def test_built_package_lists_exactly_the_registered_agents(
    built_package: ModuleType, registration: tuple[Path, dict[str, type]]
) -> None:
    _, registered = registration
    assert sorted(built_package.AGENTS) == UIDS
    for uid, cls in built_package.AGENTS.items():
        assert cls is not registered[uid]  # two classes, compiled apart ...
        assert cls.__name__ == registered[uid].__name__  # ... of the same name
        assert cls.uid == uid


def test_importing_the_built_package_keeps_the_registered_classes(
    built_package: ModuleType, registration: tuple[Path, dict[str, type]]
) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    _, registered = registration
    for uid in UIDS:
        assert REGISTERED_AGENTS[uid].agent_cls is registered[uid]


def _bare(cls: type) -> Any:
    """An instance that never ran ``__init__``: enough to read the config properties, which
    in generated classes use class attributes only (no simulation, no robot)."""
    return cls.__new__(cls)


@pytest.mark.parametrize("uid", UIDS)
def test_built_class_equals_registered_class_attribute_by_attribute(
    uid: str, built_package: ModuleType, registration: tuple[Path, dict[str, type]]
) -> None:
    built, registered = built_package.AGENTS[uid], registration[1][uid]
    assert built.__mro__[1:] == registered.__mro__[1:]  # the same ManiSkill base classes
    assert sorted(vars(built)) == sorted(vars(registered))

    assert built.uid == registered.uid == uid
    assert_same_value(built.urdf_path, registered.urdf_path, "urdf_path")
    assert_same_value(built.mjcf_path, registered.mjcf_path, "mjcf_path")
    assert description_file(built) == description_file(registered)
    assert Path(description_file(built)).is_file()
    for flag in LOADER_FLAGS:
        assert_same_value(getattr(built, flag), getattr(registered, flag), flag)
    assert_same_value(built.urdf_config, registered.urdf_config, "urdf_config")
    assert_same_keyframes(built.keyframes, registered.keyframes)

    assert_same_controller_configs(
        _bare(built)._controller_configs, _bare(registered)._controller_configs
    )
    assert_same_sensor_configs(_bare(built)._sensor_configs, _bare(registered)._sensor_configs)

    # every other class attribute: joint-name lists, tcp and the like, and the same methods
    for name, value in vars(registered).items():
        if name.startswith("__") or name in ("_controller_configs", "_sensor_configs"):
            continue
        other = vars(built)[name]
        if isinstance(value, property):
            assert inspect.getsource(other.fget) == inspect.getsource(value.fget), name
        elif inspect.isfunction(value):
            assert inspect.getsource(other) == inspect.getsource(value), name
        else:
            assert_same_value(other, value, name)
