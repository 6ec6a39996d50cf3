"""The CLI contract: exit codes, located text lines, JSON shape, and a light import path."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MISSPELLED_JOINT_SPEC as MISSPELLED
from conftest import ROOT, invoke_robospec, run_robospec


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_validate_of_the_shipped_specs_exits_zero() -> None:
    result = run_robospec("validate", "specs/")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 error(s)" in result.stdout


def test_misspelled_joint_exits_one_with_the_exact_line_column_and_suggestion() -> None:
    result = run_robospec("validate", str(MISSPELLED.relative_to(ROOT)))
    assert result.returncode == 1
    first = result.stdout.splitlines()[0]
    assert first == (
        "docs/examples/codes/RS201/fail.yaml:6:51: error[RS201] unknown joint 'panda_joint77'"
    )
    assert "did you mean 'panda_joint7'?" in result.stdout
    line = MISSPELLED.read_text().splitlines()[5]
    assert line[50:].startswith("panda_joint77")


def test_json_format_follows_the_diagnostics_contract() -> None:
    result = run_robospec("validate", "--format", "json", str(MISSPELLED))
    assert result.returncode == 1
    report = json.loads(result.stdout)
    assert report["summary"] == {"errors": 1, "warnings": 0, "notes": 0, "files": 1}
    (diagnostic,) = report["diagnostics"]
    assert set(diagnostic) == {"file", "line", "column", "code", "severity", "message", "hint"}
    assert (diagnostic["line"], diagnostic["column"], diagnostic["code"]) == (6, 51, "RS201")


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_usage_errors_exit_two() -> None:
    assert run_robospec("validate").returncode == 2
    assert run_robospec("validate", "--format", "yaml", "specs/").returncode == 2
    assert run_robospec("frobnicate").returncode == 2


def test_a_missing_path_is_a_located_error_not_a_traceback() -> None:
    result = run_robospec("validate", "no/such/spec.yaml")
    assert result.returncode == 1
    assert "no/such/spec.yaml:1:1: error[RS001]" in result.stdout
    assert "Traceback" not in result.stderr


HEAVY = ("torch", "sapien", "mani_skill", "trimesh", "yourdfpy")


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@pytest.mark.parametrize(
    ("entry", "heavy"),
    [
        # the typer app (which itself imports pydantic)
        ("from robospec.cli import app; app(['validate', 'specs/'])", HEAVY),
        # the plain command, as typed: it validates with the frozen models
        # (tests/test_frozen_model.py), on pydantic-core, and never loads pydantic
        (
            "sys.argv = ['robospec', 'validate', 'specs/']; from robospec.cli import main; main()",
            (*HEAVY, "pydantic"),
        ),
    ],
    ids=["typer-app", "plain-validate"],
)
def test_validate_never_imports_the_heavy_packages(entry: str, heavy: tuple[str, ...]) -> None:
    probe = (
        "import sys\n"
        "try:\n"
        f"    {entry}\n"
        "except SystemExit as exit:\n"
        "    assert exit.code == 0, exit.code\n"
        f"print('HEAVY', sorted(m for m in {heavy!r} if m in sys.modules))\n"
    )
    # the frozen spec model is made with pydantic on the first run after a change, then read
    # from the cache without it (tests/test_frozen_model.py): probe a run that finds it cached
    subprocess.run([sys.executable, "-c", "import robospec.model.frozen"], cwd=ROOT, check=True)
    result = subprocess.run(
        [sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert "HEAVY []" in result.stdout, result.stdout + result.stderr


def test_schema_command_prints_the_committed_schema() -> None:
    result = run_robospec("schema")
    assert result.returncode == 0
    committed = (ROOT / "schemas/robospec.schema.json").read_text(encoding="utf-8")
    assert result.stdout == committed, "run: robospec schema -o schemas/robospec.schema.json"


def test_schema_with_out_says_what_it_wrote(tmp_path: Path) -> None:
    out = tmp_path / "robospec.schema.json"
    result = invoke_robospec("schema", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert out.is_file()
    assert result.stdout == f"wrote {out}\n"


def test_every_writing_command_says_what_it_wrote(tmp_path: Path) -> None:
    """build, new and doc name the files they wrote (schema: above; import, optimize, tune and
    check --plot in their own tests, which simulate)."""
    panda = str(ROOT / "specs" / "maniskill" / "panda.yaml")
    urdf = str(ROOT / "tests" / "data" / "tree.urdf")
    for args, written in [
        (("build", panda, "-o", str(tmp_path / "pkg")), "wrote"),
        (("new", urdf, "-o", str(tmp_path / "arm.yaml"), "--no-sim"), f"wrote {tmp_path}"),
        (("doc", panda, "-o", str(tmp_path / "card.md")), f"wrote {tmp_path / 'card.md'}"),
    ]:
        result = invoke_robospec(*args)
        assert result.exit_code == 0, result.output
        assert written in result.stdout, args


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_a_warning_is_silenced_by_the_spec_or_on_the_command_line(tmp_path: Path) -> None:
    """RS307 (the ground's collision bits) is meant on a mobile base: fetch.yaml silences it;
    without that line it warns, and --silence RS307 silences it for one run. Errors stay."""
    fetch = ROOT / "specs" / "maniskill" / "fetch.yaml"
    assert "warning[RS307]" not in run_robospec("validate", str(fetch)).stdout
    loud = tmp_path / "fetch.yaml"
    text = fetch.read_text(encoding="utf-8")
    kept = "\n".join(line for line in text.splitlines() if not line.startswith("silence:"))
    loud.write_text(kept.replace("{maniskill_assets}", "{maniskill_assets}") + "\n")
    assert run_robospec("validate", str(loud)).stdout.count("warning[RS307]") == 2
    quiet = run_robospec("validate", str(loud), "--silence", "RS307", "--silence", "RS319")
    assert quiet.returncode == 0 and "warning[" not in quiet.stdout, quiet.stdout
    assert "0 warning(s)" in quiet.stdout
    unknown = run_robospec("validate", str(loud), "--silence", "RS999")
    assert unknown.returncode == 2 and "RS999 is not a robospec code" in unknown.stderr
    # an error is reported whatever --silence says
    misspelled = run_robospec("validate", str(MISSPELLED), "--silence", "RS201")
    assert misspelled.returncode == 1 and "error[RS201]" in misspelled.stdout
