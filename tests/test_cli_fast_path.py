"""A plain `robospec validate` skips the typer app (robospec.cli.fast_validate) and answers exactly
as the typer command does: same stdout, stderr and exit status, for every format and colour
choice; every other command line (help, usage errors, completion) goes to typer."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT, fast_first

from robospec.cli import fast_validate
from robospec.model.frozen import frozen_code
from robospec.model.frozen_cache import entry_path

TYPER_PATH = "import sys; from robospec.cli.commands import app; app(prog_name='robospec')"
BAD = "docs/examples/codes/RS201/fail.yaml"
GOOD = "specs/maniskill/panda.yaml"


def _run(prefix: list[str], args: list[str], env: dict[str, str]) -> tuple[str, str, int]:
    result = subprocess.run(
        [sys.executable, *prefix, *args], cwd=ROOT, capture_output=True, text=True, env=env
    )
    return result.stdout, result.stderr, result.returncode


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@pytest.mark.parametrize(
    "args",
    fast_first(
        [
            ["validate", BAD],
            ["validate", GOOD],
            ["validate", GOOD, BAD, "--format", "json"],
            ["validate", "-f", "github", BAD],
            ["validate", "--format=sarif", BAD],
            ["validate", "--color", "always", BAD],
            ["validate", "--color=never", "docs/examples/codes/RS202"],
            ["validate", "no/such/spec.yaml"],
            ["validate", "specs/maniskill", "--format", "json", "--color", "auto"],
        ],
        count=3,  # two processes each case
    ),
)
def test_plain_validate_prints_and_exits_as_the_typer_command(args: list[str]) -> None:
    assert fast_validate.parse(args, {}) is not None
    env = {**os.environ, "NO_COLOR": ""}
    fast = _run(["-m", "robospec.cli"], args, env)
    typer_path = _run(["-c", TYPER_PATH], args, env)
    assert fast == typer_path
    assert fast[2] in (0, 1) and fast[0]


@pytest.mark.parametrize(
    "args",
    [
        ["validate"],
        ["validate", "--help"],
        ["validate", BAD, "--format", "yaml"],
        ["validate", BAD, "--colour", "always"],
        ["validate", BAD, "-f"],
        ["validate", "-fjson", BAD],
        ["validate", "--", BAD],
        ["build", BAD, "-o", "out"],
        [],
    ],
)
def test_other_command_lines_are_left_to_typer(args: list[str]) -> None:
    assert fast_validate.parse(args, {}) is None


def test_completion_is_left_to_typer() -> None:
    assert fast_validate.parse(["validate", BAD], {"_ROBOSPEC_COMPLETE": "complete_bash"}) is None


def test_usage_errors_still_come_from_typer_with_exit_2() -> None:
    _, stderr, code = _run(
        ["-m", "robospec.cli"], ["validate", BAD, "--format", "yaml"], {**os.environ}
    )
    assert code == 2 and "Invalid value" in stderr


MISSPELLED_KEY = "docs/examples/codes/RS101/fail.yaml"
# what no plain URDF spec needs: the typer app and what only build writes, the other
# description format, a xacro's expansion, the mends (derive), parts (compose), the pydantic
# models (pydantic-core alone validates), the kinematics; the explanations of a syntax error,
# Python references and the catalogue of codes, for a spec that has none of them to explain,
# name or silence; and hashlib, which only the language server's description memo needs
NOT_FOR_A_PLAIN_URDF_SPEC = (
    "robospec.cli.commands",
    "robospec.emit",
    "robospec.output",
    "robospec.description.mjcf",
    "robospec.description.xacro",
    "xacro",
    "robospec.derive",
    "robospec.compose",
    "robospec.resolve.parts",
    "robospec.resolve.part_renaming",
    "robospec.resolve.part_types",
    "pydantic",
    "robospec.kinematics",
    "robospec.load.syntax_hints",
    "robospec.resolve.python_refs",
    "hashlib",
    # nor the simulator: validate reads the uids ManiSkill registers from its source, unimported
    "mani_skill",
    "sapien",
    "torch",
    "gymnasium",
    # nor TOML's reader for a YAML spec (ruamel, for a TOML spec: below)
    "tomllib",
    "robospec.load.toml_parser",
    "robospec.load.toml_positions",
)
# a spec whose first error is in its model (a misspelled key) is never resolved: neither its
# description (nor lxml) is read, nor a check run
NOT_BEFORE_RESOLVE = (
    *NOT_FOR_A_PLAIN_URDF_SPEC,
    "robospec.resolve",
    "robospec.description",
    "lxml",
    "robospec.checks",
)


def _validate_loads(spec: str) -> tuple[int, set[str]]:
    """The exit status of `robospec validate SPEC` (the plain command line) and the modules it
    has imported by then, with the spec model cached (as in every run after the first: a cold
    cache makes it with pydantic)."""
    frozen_code(entry_path())
    probe = (
        "import sys\n"
        f"sys.argv = ['robospec', 'validate', {spec!r}]\n"
        "from robospec.cli import main\n"
        "try:\n    main()\nexcept SystemExit as exit:\n    code = exit.code\n"
        "print('EXIT', code, 'LOADED', *sorted(sys.modules))\n"
    )
    stdout, stderr, _ = _run(["-c", probe], [], dict(os.environ))
    said = stdout.rsplit("EXIT ", 1)[-1].split()
    assert len(said) > 2 and said[1] == "LOADED", stdout + stderr
    return int(said[0]), set(said[2:])


@pytest.mark.parametrize(
    ("spec", "code", "not_loaded"),
    [
        (BAD, 1, NOT_FOR_A_PLAIN_URDF_SPEC),
        (GOOD, 0, NOT_FOR_A_PLAIN_URDF_SPEC),
        (MISSPELLED_KEY, 1, NOT_BEFORE_RESOLVE),
    ],
)
def test_validate_imports_only_what_the_spec_in_hand_needs(
    spec: str, code: int, not_loaded: tuple[str, ...]
) -> None:
    exit_code, loaded = _validate_loads(spec)
    assert exit_code == code
    assert "robospec.model.frozen" in loaded  # the probe saw validate run
    unneeded = sorted(
        module
        for module in loaded
        if any(module == name or module.startswith(f"{name}.") for name in not_loaded)
    )
    assert unneeded == []


def test_a_toml_spec_is_validated_without_yaml_s_reader(tmp_path: Path) -> None:
    # the misspelled joint of BAD, written in TOML: the same error, and no YAML library loaded
    spec = tmp_path / "fail.toml"
    spec.write_text(
        'robospec = 1\nuid = "my_panda"\n'
        'description = {urdf = "{maniskill_assets}/robots/panda/panda_v2.urdf"}\n'
        '[groups]\narm = ["panda_joint1", "panda_joint77"]\n'
        '[controllers]\narm = {type = "pd_joint_pos", joints = "arm", lower = -1, upper = 1, '
        "stiffness = 1e3, damping = 1e2}\n"
        '[control_modes]\npd_joint_pos = {arm = "arm"}\n',
        encoding="utf-8",
    )
    exit_code, loaded = _validate_loads(str(spec))
    assert exit_code == 1
    assert {"robospec.load.toml_parser", "robospec.resolve"} <= loaded  # read, then resolved
    assert sorted(m for m in loaded if m.split(".")[0] == "ruamel") == []


def test_plain_validate_imports_no_typer_click_or_rich() -> None:
    probe = (
        "import sys\n"
        f"sys.argv = ['robospec', 'validate', {BAD!r}]\n"
        "from robospec.cli import main\n"
        "try:\n    main()\nexcept SystemExit as exit:\n    code = exit.code\n"
        "loaded = sorted(m for m in sys.modules if m.split('.')[0] in ('typer', 'click', 'rich'))\n"
        "print('EXIT', code, 'LOADED', loaded)\n"
    )
    stdout, _, _ = _run(["-c", probe], [], dict(os.environ))
    assert stdout.strip().endswith("EXIT 1 LOADED []")


def test_plain_validate_imports_no_forward_kinematics_numpy_or_meshes() -> None:
    # a URDF and an MJCF robot: the libraries that place links (yourdfpy, MuJoCo) and what they
    # bring are for the tools that place them, never validate's path
    probe = (
        "import sys\n"
        f"sys.argv = ['robospec', 'validate', {GOOD!r}, 'specs/maniskill/humanoid.yaml']\n"
        "from robospec.cli import main\n"
        "try:\n    main()\nexcept SystemExit as exit:\n    code = exit.code\n"
        "heavy = ('numpy', 'yourdfpy', 'trimesh', 'mujoco', 'scipy')\n"
        "loaded = sorted(m for m in sys.modules if m.split('.')[0] in heavy)\n"
        "print('EXIT', code, 'LOADED', loaded)\n"
    )
    stdout, _, _ = _run(["-c", probe], [], dict(os.environ))
    assert stdout.strip().endswith("EXIT 0 LOADED []")
