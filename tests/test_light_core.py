"""Every command on the light core (`pip install -e .`, no extra): it works, or it says which
extra it needs, naming the command, with exit status 2 or a coded diagnostic: never a
traceback, never an internal error (RS900).

The light core is simulated faithfully and cheaply: the commands run in a child process whose
import system refuses every module that the core's own dependencies (pyproject's
``dependencies``, and theirs) do not bring, as an uninstalled one would be refused
(tests/lightcore/sitecustomize.py)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from functools import cache
from importlib import metadata
from pathlib import Path

import pytest
import tomllib
from conftest import ROOT, fast_first
from packaging.requirements import Requirement

from robospec.cli.extras import EXTRA_MODULES
from robospec.docgen.cli_page import command_names

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
EXTRAS = set(PYPROJECT["project"]["optional-dependencies"])
SPEC = "specs/twolink.toml"  # a robot of our own (xacro): no ManiSkill asset needed
URDF = "tests/data/tree.urdf"


def _normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


@cache
def _core_distributions() -> frozenset[str]:
    """The distributions the core needs: pyproject's dependencies and theirs."""
    return _closure(tuple(PYPROJECT["project"]["dependencies"]))


def _closure(requirements: tuple[str, ...]) -> frozenset[str]:
    """The distributions ``requirements`` install, with their own requirements (and those of
    the extras they ask for: yourdfpy asks for ``trimesh[easy]``)."""
    core: set[str] = set()
    seen: set[tuple[str, frozenset[str]]] = set()
    # each requirement with the extras its dependent asked for (which its marker may name)
    todo = [(Requirement(text), frozenset[str]()) for text in requirements]
    while todo:
        requirement, asked = todo.pop()
        marker = requirement.marker
        if marker and not any(marker.evaluate({"extra": e}) for e in ("", *sorted(asked))):
            continue  # a dependency of one of its extras only
        name = _normalized(requirement.name)
        extras = frozenset(requirement.extras)
        if (name, extras) in seen:
            continue
        seen.add((name, extras))
        core.add(name)
        try:
            todo += [(Requirement(t), extras) for t in metadata.requires(requirement.name) or []]
        except metadata.PackageNotFoundError:
            continue
    return frozenset(core)


@cache
def blocked_modules() -> str:
    """The top-level modules installed here that the core's dependencies do not bring."""
    core = _core_distributions()
    modules = metadata.packages_distributions()
    blocked = {
        module
        for module, distributions in modules.items()
        if module.isidentifier()
        and module != "robospec"
        and not any(_normalized(d) in core for d in distributions)
    }
    # the extras' heavy modules must be among them, or this test proves nothing
    assert {"mani_skill", "sapien", "torch", "matplotlib", "pygls"} <= blocked
    return ",".join(sorted(blocked))


def blocked_distributions() -> str:
    core = _core_distributions()
    names = {_normalized(d.metadata["Name"]) for d in metadata.distributions()}
    return ",".join(sorted(names - core - {"robospec"}))


def light_env(pythonpath: str) -> dict[str, str]:
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT / "tests" / "lightcore"), pythonpath]),
        "ROBOSPEC_TEST_BLOCKED": blocked_modules(),
        "ROBOSPEC_TEST_BLOCKED_DISTS": blocked_distributions(),
    }


def run_light(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    env = light_env(str(ROOT))
    return subprocess.run(
        [sys.executable, "-m", "robospec.cli", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
        stdin=subprocess.DEVNULL,
    )


def _command_lines(out: Path) -> dict[str, list[str]]:
    return {
        "validate": ["validate", SPEC],
        "build": ["build", SPEC, "-o", str(out / "pkg")],
        "schema": ["schema", "--for", SPEC],
        "import": ["import", "mani_skill.agents.robots.panda.panda:Panda"],
        "check": ["check", SPEC, "--steps", "2"],
        "demo": ["demo", SPEC],
        "inspect": ["inspect", URDF],
        "new": ["new", URDF, "-o", str(out / "new.yaml")],
        "optimize": ["optimize", SPEC, "-o", str(out / "fast.yaml")],
        "tune": ["tune", SPEC],
        "solve": ["solve", SPEC, "-n", "1"],
        "doc": ["doc", SPEC, "-o", str(out / "card.md")],
        "lsp": ["lsp"],
    }


def test_the_blocker_refuses_what_the_core_does_not_install() -> None:
    code = (
        "import importlib.util, importlib.metadata as m\n"
        "assert importlib.util.find_spec('mani_skill') is None\n"
        "try:\n    m.version('torch')\nexcept m.PackageNotFoundError:\n    print('no torch')\n"
        "import pydantic, typer, lxml, numpy, yourdfpy, mujoco\n"
        "import matplotlib\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=light_env(str(ROOT))
    )
    assert result.stdout == "no torch\n", result.stderr
    assert "ModuleNotFoundError: No module named 'matplotlib'" in result.stderr


def test_every_command_is_run_here() -> None:
    assert set(_command_lines(Path("out"))) == set(command_names())


# each case starts a robospec process: the fast loop runs a command that needs an extra and one
# that does not, the full suite every command
@pytest.mark.parametrize(
    "name",
    fast_first(
        ["check", "validate", *sorted(set(_command_lines(Path("out"))) - {"check", "validate"})],
        count=2,
    ),
)
def test_every_command_works_on_the_light_core_or_names_the_extra_it_needs(
    name: str, tmp_path: Path
) -> None:
    result = run_light(*_command_lines(tmp_path)[name])
    said = result.stdout + result.stderr
    assert "Traceback" not in said, said
    assert "RS900" not in said and "internal error" not in said, said
    assert result.returncode in (0, 1, 2), said
    if result.returncode == 0:
        return
    extras = set(re.findall(r"robospec\[(\w+)\]", said))
    assert extras and extras <= EXTRAS, said
    if result.returncode == 1:
        assert re.search(r"error\[RS\d{3}\]", said), said  # a coded diagnostic
    else:
        assert f"robospec {name}: " in said, said  # located at the command


@pytest.mark.parametrize("extra", sorted(EXTRA_MODULES))
def test_the_modules_robospec_says_an_extra_brings_are_brought_by_it(extra: str) -> None:
    extras = PYPROJECT["project"]["optional-dependencies"]
    # ManiSkill's nightly stands in for the maniskill extra (never both: scripts/setup)
    alternatives = ("maniskill-nightly",) if extra == "maniskill" else ()
    installs = _closure(tuple(r for name in (extra, *alternatives) for r in extras[name]))
    provided = metadata.packages_distributions()
    for module in EXTRA_MODULES[extra]:
        assert any(_normalized(d) in installs for d in provided.get(module, ())), module
