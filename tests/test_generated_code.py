"""Generated modules read like a careful hand-written ManiSkill agent, and ruff agrees.

robospec lays its code out itself (:mod:`robospec.emit.layout`: the core install has no ruff).
These tests run the real ruff, the one installed beside this Python (the dev extra), never one
found on ``PATH``, with ``--isolated`` so that no ``pyproject.toml`` decides the result, at line
length 100, over the package built from every spec in ``specs/`` and over property-generated
robots whose every name is hostile text. For each module they check:

- ``ruff format --check``, twice: as ruff formats by default, and ignoring trailing commas. A
  trailing comma makes ruff keep a bracket broken even where its content would fit on one line,
  so only the second run proves that every layout choice is ruff's own, not one it tolerates;
- ``ruff check --select E,F,W,I``: line lengths, unused and unsorted imports, unused variables.

The golden modules (``tests/golden/``, written by ``tests/golden_modules.py``) show what the
generated code looks like; a test fails while they are out of date.
"""

from __future__ import annotations

import ast
import io
import json
import os
import subprocess
import sys
import tempfile
import tokenize
from pathlib import Path

import pytest
from conftest import FUZZ_SCALE, PANDA_SPEC, POSITIVE_SPECS, SPECS
from golden_modules import GOLDEN, generated_modules
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from test_injection import hostile_robots, spec_text, toml_spec_text, write_urdf

from robospec.emit.generate import emit_module
from robospec.output.package import plan_package
from robospec.pipeline import compile_spec

LINE_LENGTH = 100
RUFF = Path(sys.executable).parent / ("ruff.exe" if os.name == "nt" else "ruff")
FORMAT = ["format", "--isolated", "--line-length", str(LINE_LENGTH), "--check", "--diff"]
CANONICAL = ["--config", "format.skip-magic-trailing-comma = true"]
CHECK = ["check", "--isolated", "--line-length", str(LINE_LENGTH), "--select", "E,F,W,I"]


def ruff(arguments: list[str], source: str) -> subprocess.CompletedProcess[str]:
    assert RUFF.is_file(), f"ruff is not installed beside {sys.executable}: pip install -e '.[dev]'"
    return subprocess.run(
        [str(RUFF), *arguments, "--stdin-filename", "generated.py", "-"],
        input=source,
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def ruff_findings(source: str) -> list[dict[str, object]]:
    """``ruff check``'s findings, each with its ``code`` and ``location``."""
    result = ruff([*CHECK, "--output-format", "json"], source)
    assert result.returncode in (0, 1), result.stderr
    return json.loads(result.stdout)


def assert_formatted(source: str) -> None:
    for arguments in (FORMAT, [*FORMAT, *CANONICAL]):
        result = ruff(arguments, source)
        assert result.returncode == 0, (
            f"ruff {' '.join(arguments)}:\n{result.stdout}{result.stderr}"
        )


def assert_ruff_clean(source: str) -> None:
    assert_formatted(source)
    findings = ruff_findings(source)
    assert not findings, [(f["code"], f["location"], f["message"]) for f in findings]


def unavoidable(finding: dict[str, object], long_lines: set[int], chosen: set[str]) -> bool:
    """A finding no emitter could avoid: a line too long for a name no layout can break, or a
    name ``chosen`` verbatim by the spec (the class name, a member) that pycodestyle calls
    ambiguous (``I``, ``O``, ``l``: E741-E743)."""
    if finding["code"] == "E501":
        return finding["location"]["row"] in long_lines  # type: ignore[index]
    if finding["code"] in ("E741", "E742", "E743"):
        return any(f"`{name}`" in str(finding["message"]) for name in chosen)
    return False


def unbreakable_long_lines(source: str) -> set[int]:
    """Lines too long only because of one string literal: no layout can break a name.
    (ruff itself does not count a line that is one word without spaces as too long.)"""
    lines = source.splitlines()
    longest: dict[int, int] = {}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type == tokenize.STRING and token.start[0] == token.end[0]:
            row = token.start[0]
            longest[row] = max(longest.get(row, 0), len(token.string))
    return {
        row
        for row, length in longest.items()
        if len(lines[row - 1]) - length + len('""') <= LINE_LENGTH
    }


@pytest.fixture(scope="module")
def example_package(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """The package ``robospec build specs/`` writes: ``{file name: text}``."""
    from robospec.load.discovery import discover

    paths, problems = discover([SPECS])
    assert paths and not problems
    compiled = [compile_spec(path) for path in paths]
    for item in compiled:
        assert item.robot is not None, [d.format_text() for d in item.diagnostics]
    files = plan_package(compiled, tmp_path_factory.mktemp("out") / "robospec_agents")
    return {name: text for name, text in files.items() if name.endswith(".py")}


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_every_example_spec_gives_a_module_ruff_leaves_as_it_is(
    example_package: dict[str, str],
) -> None:
    for name, source in sorted(example_package.items()):
        try:
            assert_ruff_clean(source)
        except AssertionError as failure:
            raise AssertionError(f"{name}: {failure}") from None


@settings(
    max_examples=max(int(60 * FUZZ_SCALE), 10),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(hostile_robots(), st.sampled_from(["yaml", "toml"]))
def test_modules_of_robots_with_hostile_names_are_ruff_clean(
    robot: dict[str, object], spec_format: str
) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / str(robot["folder"])
        folder.mkdir()
        write_urdf(
            folder / "robot.urdf", str(robot["base"]), str(robot["link"]), str(robot["joint"])
        )
        spec_path = Path(tmp) / f"{robot['spec_file']}.{spec_format}"
        text = spec_text(robot) if spec_format == "yaml" else toml_spec_text(robot)
        spec_path.write_text(text, encoding="utf-8")
        result = compile_spec(spec_path)
        if result.robot is None:
            event("refused by the compiler")
            return
        try:
            source = emit_module(result.robot, Path(tmp) / "out")
        except ValueError:
            event("refused by the emitter")
            return
    assert_formatted(source)
    long_lines = unbreakable_long_lines(source)
    chosen = {result.robot.class_name, str(robot["member"])}
    findings = [f for f in ruff_findings(source) if not unavoidable(f, long_lines, chosen)]
    event("a name longer than a line" if long_lines else "every line fits")
    assert not findings, [(f["code"], f["location"], f["message"]) for f in findings]


def test_golden_modules_are_what_the_emitter_writes() -> None:
    for name, source in generated_modules().items():
        golden = GOLDEN / name
        assert golden.is_file(), (
            f"{golden} is missing: run .venv/bin/python tests/golden_modules.py --write"
        )
        assert golden.read_text(encoding="utf-8") == source, (
            f"{golden} is out of date: run .venv/bin/python tests/golden_modules.py --write "
            "and review git diff tests/golden"
        )


def test_golden_modules_are_ruff_clean() -> None:
    for golden in sorted(GOLDEN.glob("*.py")):
        assert_ruff_clean(golden.read_text(encoding="utf-8"))


def test_the_ruff_checks_fail_on_a_module_ruff_would_change() -> None:
    # proves the checks can fail: each catches what it is there to catch
    with pytest.raises(AssertionError, match="format"):
        assert_formatted("x = [\n    1,\n    2\n]\n")
    with pytest.raises(AssertionError, match="format"):
        assert_formatted("x = [\n    1,\n    2,\n]\n")  # fits on one line: not ruff's own layout
    with pytest.raises(AssertionError, match="F401"):
        assert_ruff_clean("import os\n")
    with pytest.raises(AssertionError, match="I001"):
        assert_ruff_clean("import sys\nimport os\n\nprint(os, sys)\n")


def test_panda_names_shared_gains_once_like_maniskills_panda() -> None:
    source = generated_modules()["rs_panda.py"]
    tree = ast.parse(source)
    (agent,) = [node for node in tree.body if isinstance(node, ast.ClassDef)]
    gains = {
        node.targets[0].id: ast.literal_eval(node.value)
        for node in agent.body
        if isinstance(node, ast.Assign)
        and isinstance(node.targets[0], ast.Name)
        and node.targets[0].id.endswith(("_stiffness", "_damping", "_force_limit", "_friction"))
    }
    # the gripper's one controller keeps its own values: a name is for what several share
    assert gains == {"arm_stiffness": 1000.0, "arm_damping": 100.0, "arm_force_limit": 100.0}
    assert "stiffness=self.arm_stiffness" in source
    assert source.count("stiffness=") == source.count("self.arm_stiffness") + 1  # the gripper's own


def test_default_poses_are_sapien_pose_without_arguments() -> None:
    source = generated_modules()["rs_panda.py"]
    assert "pose=sapien.Pose()," in source
    assert "sapien.Pose(p=" not in source


def test_a_module_imports_only_what_it_uses() -> None:
    for name, source in generated_modules().items():
        tree = ast.parse(source)
        bound = {
            (alias.asname or alias.name).split(".")[0]
            for node in tree.body
            if isinstance(node, (ast.Import, ast.ImportFrom))
            for alias in node.names
        }
        used = {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}
        assert bound <= used, (name, bound - used)


@pytest.mark.maniskill  # compiling a spec that extends a Python class imports it
def test_an_extends_base_class_is_imported_plainly(tmp_path: Path) -> None:
    result = compile_spec(POSITIVE_SPECS / "hooks_extends.yaml")
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    source = emit_module(result.robot, tmp_path)
    assert "from mani_skill.agents.robots.panda.panda import Panda\n" in source
    assert "class RsTestExtends(Panda):" in source
    assert_ruff_clean(source)


@pytest.mark.maniskill
def test_an_extends_base_class_named_like_the_agent_is_imported_renamed(tmp_path: Path) -> None:
    spec = tmp_path / "child.yaml"
    spec.write_text(
        "robospec: 1\nuid: rs_child\nclass_name: Panda\n"
        'extends: "mani_skill.agents.robots.panda.panda:Panda"\n'
        "keyframes: {ready: {qpos: [0, 0, 0, -2, 0, 2, 0.8, 0.04, 0.04]}}\n"
    )
    result = compile_spec(spec)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    source = emit_module(result.robot, tmp_path)
    assert "from mani_skill.agents.robots.panda.panda import Panda as PandaBase\n" in source
    assert "class Panda(PandaBase):" in source
    assert_ruff_clean(source)


HOOKS_SPEC = """robospec: 1
uid: rs_hooked
class_name: panda_hooks
description: {urdf: "{maniskill_assets}/robots/panda/panda_v2.urdf"}
controllers:
  arm: {type: pd_joint_pos, joints: "*", lower: null, upper: null, stiffness: 1e3, damping: 1e2}
control_modes: {pd_joint_pos: {all: arm}}
hooks:
  after_init: "hookmods.panda_hooks:after_init"
  methods: {gripper_opening: "hookmods.panda_hooks:gripper_opening"}
"""


def test_hooks_are_imported_with_their_module_renamed_when_its_name_is_taken(
    tmp_path: Path,
) -> None:
    spec = tmp_path / "hooked.yaml"
    spec.write_text(HOOKS_SPEC)
    result = compile_spec(spec)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    source = emit_module(result.robot, tmp_path)
    # the class is called panda_hooks: the module takes another name
    assert "from hookmods import panda_hooks as panda_hooks_module\n" in source
    assert "        panda_hooks_module.after_init(self)\n" in source
    assert "    gripper_opening = panda_hooks_module.gripper_opening\n" in source
    assert "importlib" not in source and "getattr" not in source
    assert_ruff_clean(source)


def test_the_panda_module_is_the_same_from_any_build_folder(tmp_path: Path) -> None:
    robot = compile_spec(PANDA_SPEC).robot
    assert robot is not None
    assert emit_module(robot, tmp_path / "a") == emit_module(robot, tmp_path / "b" / "c")
