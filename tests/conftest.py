"""What every test module shares: the repository's paths, the robospec command line (in this
process, or in a child process where the process boundary is what a test proves), and the rule
that marks the tests needing ManiSkill.

ManiSkill tests and the fast loop (``scripts/test --fast``, i.e. ``pytest -m "not maniskill and
not slow"``):

- a test needs ManiSkill (imports mani_skill, sapien or torch, registers or simulates a robot)
  when it asks for the ``maniskill`` fixture, directly or through another fixture: it is then
  marked ``maniskill`` here, by that rule. A module whose every test needs it says so once,
  ``pytestmark = pytest.mark.maniskill``; when the run deselects that marker such a module is
  not even imported (its imports of ManiSkill cost seconds).
- in a run that deselects ``maniskill``, a test that imports mani_skill, sapien or torch anyway
  (an import statement it runs, or a module it loads) fails and says to mark it: the fast loop
  cannot quietly grow slow.
- a missing ManiSkill is a failure, never a skip: the ``maniskill`` fixture fails, and so does
  a ``pytest.importorskip`` of mani_skill, sapien or torch (tests/test_install.py names the
  extra to install).
"""

from __future__ import annotations

import ast
import atexit
import builtins
import importlib.util
import os
import random
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Container, Iterable, Iterator, Mapping
from functools import cache
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import pytest

from robospec.maniskill.installed import installed

if TYPE_CHECKING:
    from click.testing import Result

# every run writes where its time went, per test file (tests/durations.py)
pytest_plugins = ["durations"]

ROOT = Path(__file__).resolve().parent.parent
# property tests draw ROBOSPEC_FUZZ_SCALE times their examples (scripts/test --fast: a fifth)
FUZZ_SCALE = max(float(os.environ.get("ROBOSPEC_FUZZ_SCALE", "1")), 0.01)
SPECS = ROOT / "specs"
MANISKILL_SPECS = SPECS / "maniskill"
PANDA_SPEC = MANISKILL_SPECS / "panda.yaml"
TWOLINK_SPEC = SPECS / "twolink.toml"
TWOLINK_XACRO = SPECS / "robots" / "twolink" / "twolink.urdf.xacro"
SCHEMA = ROOT / "schemas" / "robospec.schema.json"
DOCS = ROOT / "docs"
# the catalogue of failing and passing examples, one folder per diagnostic code; the docs pages
# are generated from it (robospec.docgen.code_examples) and tests/test_spec_examples.py runs it
CODE_EXAMPLES = DOCS / "examples" / "codes"
# the Panda with panda_joint77 in its arm group: one error, RS201 at 6:51 (did you mean ...)
MISSPELLED_JOINT_SPEC = CODE_EXAMPLES / "RS201" / "fail.yaml"
# specs that must validate cleanly and that no shipped robot covers (hooks, helpers, ...)
POSITIVE_SPECS = ROOT / "tests" / "specs" / "positive"

# what the maniskill extra brings that a test may import
MANISKILL_MODULES = ("mani_skill", "sapien", "torch")

# Which ManiSkill the suite runs on (scripts/test: 3.0.1; scripts/test --nightly: the nightly):
# tests that assert an upstream bug assert it where this ManiSkill has it, and the fix where not
_INSTALLED = installed()
MANISKILL_VERSION = None if _INSTALLED is None else "nightly" if _INSTALLED.is_nightly else "3.0.1"
# Tests whose outcome cannot depend on ManiSkill's version — they neither import ManiSkill nor
# read what it installs (the layout of generated code, build's file safety, coacd's hulls) — are
# judged on 3.0.1 only: the nightly's run in CI spends its minutes on what the nightly can change.
SAME_ON_EVERY_MANISKILL = pytest.mark.skipif(
    MANISKILL_VERSION == "nightly",
    reason="the same on every ManiSkill version: judged on 3.0.1",
)


def sample_on_nightly(values: Iterable[Any], sample: Container[Any], why: str) -> list[Any]:
    """A sweep over every shipped robot whose mechanism ``sample`` proves on ManiSkill's
    nightly: the others are judged on 3.0.1 only (``why``: what the sample covers). CI's
    nightly run exists to find what the nightly breaks, and a change there that breaks one
    robot of such a sweep breaks the mechanism the sample takes too."""
    skip = pytest.mark.skipif(MANISKILL_VERSION == "nightly", reason=f"sampled there: {why}")
    return [pytest.param(value, marks=[] if value in sample else [skip]) for value in values]


# The control modes this ManiSkill cannot build, ManiSkill's agent and the spec's alike
# (docs/zoo.md, "ManiSkill versions"): the nightly's PDEEPosController reads root_link before
# setting it whenever root_link_name is set, as Fetch's end-effector controllers set it
FETCH_EE_MODES = frozenset(
    {"pd_ee_delta_pos", "pd_ee_delta_pose", "pd_ee_target_delta_pos", "pd_ee_target_delta_pose"}
)
CRASHING_MODES: dict[str, frozenset[str]] = (
    {"fetch": FETCH_EE_MODES} if MANISKILL_VERSION == "nightly" else {}
)
MANISKILL_MARK = "maniskill"
INSTALL_MANISKILL = (
    "the maniskill extra is not installed: run scripts/setup (pip install -e '.[maniskill]')"
)


def maniskill_assets() -> Path:
    """ManiSkill's bundled assets, ``mani_skill/assets`` (the robots ``{maniskill_assets}``
    names), found here by the tests themselves (``find_spec`` imports nothing), not by
    robospec's ``maniskill_assets_dir``, the code under test: a lookup that breaks fails the
    tests that read the assets instead of skipping them. Without ManiSkill, a failure naming
    the extra (the maniskill extra installs them, and CI has it)."""
    spec = importlib.util.find_spec("mani_skill")
    if spec is None or not spec.submodule_search_locations:
        pytest.fail(INSTALL_MANISKILL, pytrace=False)
    return Path(next(iter(spec.submodule_search_locations))) / "assets"


# -- the robospec command line


def run_robospec(
    *args: str,
    cwd: Path = ROOT,
    env: Mapping[str, str] | None = None,
    timeout: float = 120,
) -> subprocess.CompletedProcess[str]:
    """``robospec ARGS`` in a child process, as a user's shell runs it: for what only a process
    shows (exit status, what reaches stdout and stderr, imports, signals, the fast path)."""
    return subprocess.run(
        [sys.executable, "-m", "robospec.cli", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
        env=None if env is None else dict(env),
    )


def invoke_robospec(*args: str, env: Mapping[str, str | None] | None = None) -> Result:
    """``robospec ARGS`` through the typer app in this process (no interpreter start-up, and
    modules already imported stay imported): for what the command does, not how a process ends.
    Exceptions are caught and left on the result (``result.exception``); ``env`` maps a
    variable to None to unset it."""
    from typer.testing import CliRunner

    from robospec.cli import app

    return CliRunner().invoke(app, list(args), env=None if env is None else dict(env))


# -- ManiSkill


@pytest.fixture(scope="session")
def maniskill() -> ModuleType:
    """ManiSkill with its environments registered. A test that asks for it is marked
    ``maniskill`` (the rule below); without the extra it fails, naming what to install."""
    try:
        import mani_skill.envs  # noqa: F401  (registers the environments)
    except ImportError as error:
        pytest.fail(f"{INSTALL_MANISKILL} ({error})", pytrace=False)
    return sys.modules["mani_skill"]


def spec_params(paths: Iterable[Path], root: Path | None = None) -> list[Any]:
    """``paths`` as parameters named by their path (relative to ``root``, else by name); a spec
    whose ``extends`` names a Python class is marked ``maniskill``, since compiling it imports
    that class and checks it against ManiSkill's BaseAgent (a parameter cannot ask for the
    fixture)."""
    return [
        pytest.param(
            path,
            id=str(path.relative_to(root)) if root else path.name,
            marks=[pytest.mark.maniskill] if extends_python(path) else [],
        )
        for path in paths
    ]


def sample_fast(params: list[Any], sample: Container[Path]) -> list[Any]:
    """A sweep's parameters (from :func:`spec_params`) with all but ``sample`` marked ``slow``:
    the fast loop runs the sample, the full suite every one."""
    return [param if param.values[0] in sample else _slow(param) for param in params]


def fast_first(values: Iterable[Any], count: int = 1) -> list[Any]:
    """A sweep's parameters whose cases each start processes: the fast loop runs the first
    ``count``, the full suite every one (a tuple is one case of several arguments)."""
    params = [pytest.param(*(v if isinstance(v, tuple) else (v,))) for v in values]
    return [param if index < count else _slow(param) for index, param in enumerate(params)]


def _slow(param: Any) -> Any:
    """``param`` (a ``pytest.param``) also marked ``slow``: for the full suite only."""
    return pytest.param(*param.values, id=param.id, marks=[*param.marks, pytest.mark.slow])


def extends_python(spec: Path) -> bool:
    """Whether the spec's ``extends`` names a Python class (compiling it imports ManiSkill)."""
    return any(
        line.startswith("extends:") for line in spec.read_text(encoding="utf-8").splitlines()
    )


def _deselects(config: pytest.Config, marks: set[str]) -> bool:
    """Whether ``-m`` leaves out every test carrying ``marks``, whatever else it carries."""
    expression = config.getoption("markexpr", "")
    if not expression:
        return False
    from _pytest.mark.expression import Expression

    compiled = Expression.compile(expression)
    # an expression like "not maniskill and not slow": false for the marks, whatever the rest
    return not any(
        compiled.evaluate(lambda name, /, rest=rest, **_: name in marks or rest)
        for rest in (False, True)
    )


def _fast_run(config: pytest.Config) -> bool:
    return _deselects(config, {MANISKILL_MARK})


@cache
def _marked_whole_module(path: Path) -> bool:
    """The module says ``pytestmark = pytest.mark.maniskill`` (alone or in a list)."""
    try:
        tree = ast.parse(path.read_bytes(), filename=str(path))
    except (OSError, SyntaxError):
        return False  # let pytest import it and report the problem
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(target, ast.Name) and target.id == "pytestmark" for target in node.targets
        ):
            return any(
                isinstance(part, ast.Attribute)
                and part.attr == MANISKILL_MARK
                and isinstance(part.value, ast.Attribute)
                and part.value.attr == "mark"
                for part in ast.walk(node.value)
            )
    return False


def pytest_ignore_collect(collection_path: Path, config: pytest.Config) -> bool | None:
    # every test of such a module would be deselected: do not pay for importing ManiSkill
    if collection_path.suffix == ".py" and collection_path.name.startswith("test_"):
        if _fast_run(config) and _marked_whole_module(collection_path):
            return True
    return None


@pytest.hookimpl(tryfirst=True)  # before -m deselects by marker
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if MANISKILL_MARK in getattr(item, "fixturenames", ()):
            item.add_marker(MANISKILL_MARK)
    # the modules of minutes first (a stable sort: each module's tests keep their order):
    # xdist hands out whole modules in this order (--dist loadfile; _keep_module_order), and
    # one of them started last would keep one worker busy alone at the end
    items.sort(key=lambda item: item.get_closest_marker("minutes") is None)


def _keep_module_order(config: pytest.Config) -> None:
    """pytest-xdist's --dist loadfile hands out the modules with the most tests first unless
    told not to (--no-loadscope-reorder): a module of two tests and eleven minutes then
    started last, alone, while the other worker sat idle. The order is the collection's."""
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item: pytest.Item) -> Any:
    if not _fast_run(item.config):
        return (yield)
    # an import statement runs __import__ each time, even for a module imported long ago: so a
    # test is caught even when an earlier one brought ManiSkill in (sys.modules would not say)
    wanted: set[str] = set()
    real_import = builtins.__import__

    def watching_import(name: str, *args: Any, **kwargs: Any) -> Any:
        if name.partition(".")[0] in MANISKILL_MODULES:
            wanted.add(name.partition(".")[0])
        return real_import(name, *args, **kwargs)

    imported_before = set(_imported_maniskill())
    builtins.__import__ = watching_import
    try:
        result = yield
    finally:
        builtins.__import__ = real_import
    wanted |= set(_imported_maniskill()) - imported_before
    if wanted:
        pytest.fail(
            f"{item.nodeid} imported {', '.join(sorted(wanted))} but is not marked "
            f"'{MANISKILL_MARK}': ask for the maniskill fixture (or mark the module) so that "
            "the fast loop leaves it out",
            pytrace=False,
        )
    return result


def _imported_maniskill() -> list[str]:
    return [name for name in MANISKILL_MODULES if name in sys.modules]


def contact_offsets(entities: Iterable[Any]) -> list[float]:
    """The contact offset of every collision shape of ManiSkill's ``entities`` (links or actors:
    their ``_bodies`` in each sub-scene)."""
    return [
        shape.contact_offset
        for entity in entities
        for body in entity._bodies
        for shape in body.get_collision_shapes()
    ]


def _skipped_for_maniskill(report: pytest.TestReport | pytest.CollectReport) -> bool:
    if not report.skipped or not isinstance(report.longrepr, tuple):
        return False
    reason = str(report.longrepr[2])
    return any(f"could not import '{name}'" in reason for name in MANISKILL_MODULES)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Any:
    report = yield
    if _skipped_for_maniskill(report):
        report.outcome = "failed"
        report.longrepr = f"{INSTALL_MANISKILL} ({report.longrepr[2]})"
    return report


@pytest.hookimpl(wrapper=True)
def pytest_make_collect_report(collector: pytest.Collector) -> Any:
    report = yield
    if _skipped_for_maniskill(report):
        report.outcome = "failed"
        report.longrepr = f"{INSTALL_MANISKILL} ({report.longrepr[2]})"
    return report


# -- property tests: new examples each run, and the seed to draw them again


HYPOTHESIS_SEED_ENV = "ROBOSPEC_HYPOTHESIS_SEED"


@pytest.hookimpl(tryfirst=True)  # before Hypothesis's plugin reads --hypothesis-seed
def pytest_configure(config: pytest.Config) -> None:
    _keep_module_order(config)
    if config.getoption("hypothesis_seed", None) is None:
        seed = os.environ.get(HYPOTHESIS_SEED_ENV) or str(random.SystemRandom().randrange(2**32))
        config.option.hypothesis_seed = seed
        # pytest-xdist's workers (scripts/test --fast) start later, from this environment
        os.environ[HYPOTHESIS_SEED_ENV] = seed


def _seed_line(config: pytest.Config) -> str:
    seed = config.getoption("hypothesis_seed")
    return (
        f"hypothesis seed: {seed} (property tests draw new examples each run; "
        f"{HYPOTHESIS_SEED_ENV}={seed} or --hypothesis-seed={seed} draws these again)"
    )


def pytest_report_header(config: pytest.Config) -> str:
    return _seed_line(config)


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    terminalreporter.write_line(_seed_line(config))  # also under -q, which has no header


# -- isolation

# Collecting the test modules imports robospec.model.frozen, which makes and caches the frozen
# spec model, before any fixture runs: robospec's cache is a folder of this run's own from the
# start (removed at exit), never the user's ~/.cache; the fixture below then gives every test
# the session's folder.
_COLLECTION_CACHE = tempfile.mkdtemp(prefix="robospec-tests-cache-")
atexit.register(shutil.rmtree, _COLLECTION_CACHE, ignore_errors=True)
os.environ["ROBOSPEC_CACHE_DIR"] = _COLLECTION_CACHE


@pytest.fixture(autouse=True)
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    # never touch the user's ~/.cache from tests
    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "cache"))


def _maniskill_registry() -> dict[str, Any] | None:
    """ManiSkill's registry of agents, where ManiSkill has been imported (never imported here)."""
    registration = sys.modules.get("mani_skill.agents.registration")
    return None if registration is None else registration.REGISTERED_AGENTS


@pytest.fixture(scope="module", autouse=True)
def _maniskill_registry_as_found() -> Iterator[None]:
    """Each test module leaves ManiSkill's registry of agents as it found it: a uid a module
    registered (robospec.register in a test, run_solve, a picture's truth) would otherwise
    refuse the same uid in a later module of the same xdist worker (RS306), so that a
    module's outcome depended on which modules ran before it in its worker."""
    registry = _maniskill_registry()
    before = dict(registry) if registry is not None else None
    yield
    registry = _maniskill_registry()
    if registry is None:
        return
    if before is None:  # imported by this module: ManiSkill's own agents are what stays
        before = {
            uid: entry
            for uid, entry in registry.items()
            if entry.agent_cls.__module__.startswith("mani_skill.")
        }
    registry.clear()
    registry.update(before)


__all__ = [
    "CODE_EXAMPLES",
    "DOCS",
    "MANISKILL_SPECS",
    "MISSPELLED_JOINT_SPEC",
    "PANDA_SPEC",
    "POSITIVE_SPECS",
    "ROOT",
    "SCHEMA",
    "SPECS",
    "TWOLINK_SPEC",
    "TWOLINK_XACRO",
    "extends_python",
    "invoke_robospec",
    "maniskill_assets",
    "run_robospec",
    "sample_fast",
    "spec_params",
]
