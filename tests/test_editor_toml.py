"""taplo (the TOML engine behind VS Code's Even Better TOML and `taplo lint` in CI) checking
TOML specs against schemas/robospec.schema.json: errors at the right line and column, and the
repo's TOML spec clean through its own `#:schema` directive.

taplo runs offline: `--no-auto-config` ignores any taplo config around, and the online schema
catalogs stay off (they are opt-in with `--default-schema-catalogs`). Positions are taplo's:
1-based lines and columns.
"""

from __future__ import annotations

import os
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest
from conftest import SCHEMA, TWOLINK_SPEC
from editor_engines import narrowed_schema, taplo_executable

# one reported problem: "error: MESSAGE" then, a line later, "┌─ PATH:LINE:COLUMN"
PROBLEM = re.compile(
    r"^error: (?P<message>.*)\n\s*┌─ (?P<path>.*):(?P<line>\d+):(?P<column>\d+)$", re.M
)


@dataclass(frozen=True)
class Lint:
    returncode: int
    output: str
    # each problem's (line, column) -> its message; taplo repeats an object-level problem at
    # every key and value of that object, so one message can sit at many positions
    problems: dict[tuple[int, int], str]


def taplo_lint(spec: Path, *options: str) -> Lint:
    result = subprocess.run(
        [taplo_executable(), "lint", "--no-auto-config", "--colors", "never", *options, str(spec)],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=spec.parent,
    )
    output = result.stdout + result.stderr
    problems = {(int(m["line"]), int(m["column"])): m["message"] for m in PROBLEM.finditer(output)}
    return Lint(result.returncode, output, problems)


def write_spec(path: Path, body: str) -> Path:
    """A TOML spec whose `#:schema` directive points at the repo's schema; ``body`` starts on
    line 2."""
    path.write_text(f"#:schema {SCHEMA.as_uri()}\n{body}")
    return path


def test_unknown_key_is_reported_at_the_key(tmp_path: Path) -> None:
    spec = write_spec(
        tmp_path / "unknown_key.toml",
        'robospec = 1\nuid = "demo"\n\n[loader]\nfix_root_lnk = true\n',
    )
    lint = taplo_lint(spec)
    assert lint.returncode == 1, lint.output
    assert "fix_root_lnk" in lint.problems.get((6, 1), ""), lint.output


def test_wrong_type_is_reported_at_the_value_only(tmp_path: Path) -> None:
    spec = write_spec(tmp_path / "wrong_type.toml", "robospec = 1\nuid = 3\n\n[loader]\n")
    lint = taplo_lint(spec)
    assert lint.returncode == 1, lint.output
    assert lint.problems == {(3, 7): '3 is not of type "string"'}, lint.output


def test_wrong_version_type_is_reported_at_the_value(tmp_path: Path) -> None:
    spec = write_spec(tmp_path / "wrong_version.toml", 'robospec = "x"\nuid = "demo"\n')
    lint = taplo_lint(spec)
    assert lint.returncode == 1, lint.output
    assert (2, 12) in lint.problems, lint.output
    assert '"x"' in lint.problems[(2, 12)]


def test_wrong_type_in_a_controller_is_reported_at_the_value_only(tmp_path: Path) -> None:
    spec = write_spec(
        tmp_path / "controller_wrong_type.toml",
        'robospec = 1\nuid = "demo"\n\n[controllers.arm]\ntype = "pd_joint_pos"\n'
        'joints = "arm"\nlower = -1\nupper = 1\nstiffness = "hard"\ndamping = 10\n',
    )
    lint = taplo_lint(spec)
    assert lint.returncode == 1, lint.output
    assert set(lint.problems) == {(10, 13)}, lint.output


def test_schema_option_applies_the_schema_without_a_directive(tmp_path: Path) -> None:
    spec = tmp_path / "no_directive.toml"
    spec.write_text("robospec = 1\nuid = 3\n")
    lint = taplo_lint(spec, "--schema", SCHEMA.as_uri())
    assert lint.problems == {(2, 7): '3 is not of type "string"'}, lint.output


def test_twolink_spec_lints_clean_through_its_own_directive() -> None:
    lint = taplo_lint(TWOLINK_SPEC)
    assert lint.returncode == 0, lint.output


def test_relative_schema_directive_resolves_against_the_spec_file(tmp_path: Path) -> None:
    # the twolink text with one unknown key, its directive rewritten relative to where the copy
    # lives: proves a relative directive like the committed one reaches the schema
    relative = Path(os.path.relpath(SCHEMA, tmp_path)).as_posix()
    body = TWOLINK_SPEC.read_text().split("\n", 1)[1]
    spec = tmp_path / "twolink_edited.toml"
    spec.write_text(f"#:schema {relative}\nuid_typo = 1\n{body}")
    lint = taplo_lint(spec)
    assert "uid_typo" in lint.problems.get((2, 1), ""), lint.output


@pytest.fixture(scope="module")
def twolink_schema(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The schema narrowed to the twolink robot by `robospec schema --for`."""
    return narrowed_schema(
        TWOLINK_SPEC, tmp_path_factory.mktemp("narrowed") / "twolink.schema.json"
    )


def test_narrowed_schema_accepts_the_twolink_spec(twolink_schema: Path) -> None:
    lint = taplo_lint(TWOLINK_SPEC, "--schema", twolink_schema.as_uri())
    assert lint.returncode == 0, lint.output


def test_narrowed_schema_flags_a_misspelled_joint_name(
    twolink_schema: Path, tmp_path: Path
) -> None:
    text = TWOLINK_SPEC.read_text().split("\n", 1)[1]
    typo = 'twolink_joint2 = "-pi/4"'
    assert text.count(typo) == 1
    spec = tmp_path / "twolink_typo.toml"
    spec.write_text(text.replace(typo, 'twolink_jointX = "-pi/4"'))
    line_number, line = next(
        (n, line) for n, line in enumerate(spec.read_text().splitlines(), 1) if "jointX" in line
    )
    lint = taplo_lint(spec, "--schema", twolink_schema.as_uri())
    assert lint.returncode == 1, lint.output
    # taplo reports a failed anyOf at every key and value of the table: the name is among them,
    # and nothing outside that line is blamed
    assert (line_number, line.index("twolink_jointX") + 1) in lint.problems, lint.output
    assert {line for line, _ in lint.problems} == {line_number}, lint.output
