"""Diagnostic output formats of validate/build/import, driven through the real CLI on real bad
specs: text (source excerpt, caret under the key or value, colour rules), github workflow
annotations (escaping) and SARIF 2.1.0 (valid against the official schema, round-trips the
locations of the JSON report)."""

from __future__ import annotations

import json
import os
import pty
import re
import shutil
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
from conftest import CODE_EXAMPLES, DOCS, MISSPELLED_JOINT_SPEC, ROOT, fast_first, run_robospec
from jsonschema import Draft202012Validator, FormatChecker

from robospec.diagnostics import Location, error, sort_key
from robospec.diagnostics.codes import CODES
from robospec.docgen.code_examples import failing_example_paths
from robospec.pipeline import compile_all
from robospec.reporting import render
from robospec.reporting.excerpt import span_width
from robospec.reporting.github import annotation
from robospec.reporting.sarif import sarif_log

MISSPELLED = str(MISSPELLED_JOINT_SPEC.relative_to(ROOT))  # RS201 at 6:51
UNKNOWN_KEY = str((CODE_EXAMPLES / "RS101" / "fail.yaml").relative_to(ROOT))  # RS101 at 13:1
BAD_EXPRESSION = str((CODE_EXAMPLES / "RS010" / "fail_bad_expression.yaml").relative_to(ROOT))
FAILING = [str(path.relative_to(ROOT)) for path in failing_example_paths(DOCS)]
SARIF_SCHEMA = json.loads((ROOT / "tests/data/sarif/sarif-schema-2.1.0.json").read_text())
ANSI = re.compile(r"\x1b\[[0-9;]*m")
PANDA = "{maniskill_assets}/robots/panda/panda_v2.urdf"


def plain_env(**extra: str) -> dict[str, str]:
    """The test process's environment without the colour switches, plus ``extra``."""
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    env.update(extra)
    return env


def sarif_errors(document: object) -> list[str]:
    validator = Draft202012Validator(SARIF_SCHEMA, format_checker=FormatChecker())
    return [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(document)]


# -- text ---------------------------------------------------------------------------------------


def test_text_shows_the_source_line_and_underlines_the_misspelled_joint() -> None:
    result = run_robospec("validate", MISSPELLED, env=plain_env())
    assert result.returncode == 1
    header, source, carets, hint, summary = result.stdout.splitlines()
    assert header == (
        f"{MISSPELLED}:6:51: error[RS201] unknown joint 'panda_joint77'"
    )  # the first line is unchanged: tools grep it
    line6 = (ROOT / MISSPELLED).read_text().splitlines()[5]
    assert source == f"  6 | {line6}"
    gutter = len("  6 | ")
    assert carets.index("^") == gutter + 50  # column 51, 1-based
    assert carets.strip(" |") == "^" * len("panda_joint77")
    assert hint == "    hint: did you mean 'panda_joint7'?"
    assert summary == "1 file(s) checked: 1 error(s), 0 warning(s)"


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_text_first_lines_are_exactly_the_diagnostics_one_line_form() -> None:
    # the one-line form (Diagnostic.format_text, SpecError, other reports) and the excerpt
    # renderer must not drift apart: tools grep these lines
    compiled, diagnostics = compile_all([ROOT / path for path in FAILING])
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    text = render(diagnostics, len(compiled), "text")
    headers = [
        line for line in text.splitlines() if re.match(r"\S+:\d+:\d+: (error|warning|note)\[", line)
    ]
    assert headers == [d.format_text().splitlines()[0] for d in sorted(diagnostics, key=sort_key)]
    assert len(headers) > 30


def test_text_underlines_a_key_and_a_quoted_value() -> None:
    result = run_robospec("validate", UNKNOWN_KEY, BAD_EXPRESSION, env=plain_env())
    lines = result.stdout.splitlines()
    key = lines.index(f"{UNKNOWN_KEY}:13:1: error[RS101] unknown key 'keyframe'")
    assert lines[key + 1] == "  13 | keyframe:"
    assert lines[key + 2] == "     | ^^^^^^^^"
    value = next(i for i, line in enumerate(lines) if "error[RS010]" in line)
    source, carets = lines[value + 1], lines[value + 2]
    start = carets.index("^")
    assert source[start:].startswith("\"__import__('os')\"")
    assert carets[start:] == "^" * len("\"__import__('os')\"")


def test_text_excerpt_comes_from_the_robot_description_when_the_urdf_is_wrong(
    tmp_path: Path,
) -> None:
    shutil.copy(ROOT / "tests/data/urdf_invalid/bad_axis.urdf", tmp_path / "robot.urdf")
    (tmp_path / "spec.yaml").write_text(
        "robospec: 1\nuid: rs_fmt_axis\ndescription: {urdf: robot.urdf}\n"
        "controllers:\n  arm: {type: pd_joint_pos, joints: [j1], lower: -1, upper: 1,"
        " stiffness: 1e3, damping: 1e2}\ncontrol_modes:\n  pd: {arm: arm}\n"
    )
    result = run_robospec("validate", "spec.yaml", cwd=tmp_path, env=plain_env())
    lines = result.stdout.splitlines()
    # the caret under the element, not in the indentation before it
    assert lines[0].startswith("robot.urdf:7:5: error[RS052]"), result.stdout
    assert lines[1] == '  7 |     <axis xyz="0 1"/> <!-- expect RS052 -->'
    assert lines[2] == "    |     " + "^" * len('<axis xyz="0 1"/>')


def test_text_has_no_excerpt_when_the_file_cannot_be_read() -> None:
    result = run_robospec("validate", "no/such/spec.yaml", env=plain_env())
    assert result.stdout.splitlines()[0].startswith("no/such/spec.yaml:1:1: error[RS001]")
    assert not any(" | " in line for line in result.stdout.splitlines())


def test_text_shows_control_characters_in_the_source_as_replacement_characters(
    tmp_path: Path,
) -> None:
    # an escape sequence in a spec must not reach the terminal through the excerpt (YAML rejects
    # the file, RS002, and the excerpt shows the line with the character)
    (tmp_path / "spec.yaml").write_text("robospec: 1  # \x1b[2J\nuid: rs_x\n")
    result = run_robospec("validate", "spec.yaml", cwd=tmp_path, env=plain_env())
    assert "error[RS002]" in result.stdout
    assert "\x1b" not in result.stdout
    excerpt = [line for line in result.stdout.splitlines() if line.startswith("  1 |")]
    assert excerpt == ["  1 | robospec: 1  # \ufffd[2J"], result.stdout


def test_piped_text_has_no_colour() -> None:
    result = run_robospec("validate", MISSPELLED, env=plain_env())
    assert "\x1b[" not in result.stdout


@pytest.mark.parametrize(
    ("args", "env", "coloured"),
    fast_first(
        [
            (["--color", "always"], {}, True),
            ([], {"FORCE_COLOR": "1"}, True),
            ([], {"FORCE_COLOR": "0"}, False),
            ([], {"FORCE_COLOR": "1", "NO_COLOR": "1"}, False),  # NO_COLOR beats FORCE_COLOR
            ([], {"FORCE_COLOR": "1", "NO_COLOR": ""}, True),  # an empty NO_COLOR is unset
            (["--color", "always"], {"NO_COLOR": "1"}, True),  # the command line beats both
            (["--color", "never"], {"FORCE_COLOR": "1"}, False),
        ],
        count=2,
    ),
)
def test_colour_precedence(args: list[str], env: dict[str, str], coloured: bool) -> None:
    result = run_robospec("validate", *args, MISSPELLED, env=plain_env(**env))
    assert ("\x1b[" in result.stdout) is coloured
    plain = run_robospec("validate", MISSPELLED, env=plain_env()).stdout
    assert ANSI.sub("", result.stdout) == plain  # colour changes nothing else


def run_on_a_terminal(*args: str, env: dict[str, str]) -> str:
    """Run the CLI with stdout on a pseudo-terminal, as in an interactive shell."""
    leader, follower = pty.openpty()
    process = subprocess.Popen(
        [sys.executable, "-m", "robospec.cli", *args],
        cwd=ROOT,
        stdout=follower,
        stderr=subprocess.DEVNULL,
        env=env,
    )
    os.close(follower)
    chunks = []
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        chunks.append(chunk)
    process.wait(timeout=120)
    os.close(leader)
    return b"".join(chunks).decode().replace("\r\n", "\n")


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_a_terminal_gets_colour_unless_no_color_is_set() -> None:
    coloured = run_on_a_terminal("validate", MISSPELLED, env=plain_env(TERM="xterm"))
    assert "\x1b[1;31merror[RS201]\x1b[0m" in coloured
    assert "\x1b[1;31m^^^^^^^^^^^^^\x1b[0m" in coloured  # the caret in the severity's colour
    assert "\x1b[" not in run_on_a_terminal(
        "validate", MISSPELLED, env=plain_env(TERM="xterm", NO_COLOR="1")
    )
    assert "\x1b[" not in run_on_a_terminal("validate", MISSPELLED, env=plain_env(TERM="dumb"))


@pytest.mark.parametrize(
    ("line", "column", "width"),
    [
        ("keyframe: {rest: 1}", 1, 8),  # a key ends at ': '
        ("  uid: rs_x  # comment", 8, 4),  # a plain scalar ends at a space
        ("joints: [a, bb, c]", 13, 2),  # ... or at a flow separator
        ("joints: [a, bb, c]", 9, 10),  # a flow sequence up to its bracket
        ("arm: {a: [1, 2], b: '}'}", 6, 19),  # brackets inside quotes do not count
        ("x: 'it''s'", 4, 7),  # YAML's doubled single quote
        ('x: "a\\"b"', 4, 6),  # an escaped double quote
        ("x: {a: 1,", 4, 1),  # not closed on this line: the bracket alone
        ("url = 'http://x:1/y'", 7, 14),  # TOML literal string
        ("qpos = [0, 1]", 1, 4),  # a TOML key ends at ' ='
        ("    <axis/>", 5, 7),  # an XML element
        ("    <axis/>", 1, 1),  # whitespace: one caret
        ("short", 40, 1),  # past the end: one caret
    ],
)
def test_span_width(line: str, column: int, width: int) -> None:
    assert span_width(line, column) == width


# -- github -------------------------------------------------------------------------------------


def parse_annotation(line: str) -> tuple[str, dict[str, str], str]:
    """Split a workflow command the way the Actions runner does, undoing its escapes."""

    def unescape(text: str) -> str:
        return re.sub(r"%(25|0D|0A|3A|2C)", lambda m: chr(int(m.group(1), 16)), text)

    match = re.fullmatch(r"::(\w+) ([^:]*)::(.*)", line)
    assert match, line
    properties = dict(item.split("=", 1) for item in match.group(2).split(","))
    return match.group(1), {k: unescape(v) for k, v in properties.items()}, unescape(match[3])


def test_github_annotations_escape_percent_comma_and_colon(tmp_path: Path) -> None:
    folder = tmp_path / "odd, dir: 100%"
    folder.mkdir()
    (folder / "spec.yaml").write_text(
        f'robospec: 1\nuid: rs_fmt_odd\ndescription: {{urdf: "{PANDA}"}}\n'
        '"bad%key, really: yes": 1\n'
    )
    result = run_robospec("validate", "--format", "github", folder.name, cwd=tmp_path)
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert lines[-1] == "1 file(s) checked: 1 error(s), 0 warning(s)"
    (line,) = [line for line in lines if "RS101" in line]
    # raw form: no property separator survives unescaped inside a value
    assert line.startswith("::error file=odd%2C dir%3A 100%25/spec.yaml,line=4,col=1,title=RS101::")
    assert "bad%25key, really: yes" in line  # data: % escaped, comma and colon kept
    kind, props, message = parse_annotation(line)
    assert kind == "error"
    assert props == {"file": "odd, dir: 100%/spec.yaml", "line": "4", "col": "1", "title": "RS101"}
    assert message.startswith("unknown key 'bad%key, really: yes'")


def test_github_message_with_a_hint_keeps_it_on_a_second_line() -> None:
    result = run_robospec("validate", "--format", "github", MISSPELLED)
    line, _summary = result.stdout.splitlines()
    assert line == (
        f"::error file={MISSPELLED},line=6,col=51,title=RS201::unknown joint 'panda_joint77'"
        "%0Ahint: did you mean 'panda_joint7'?"
    )
    _, _, message = parse_annotation(line)
    assert message == "unknown joint 'panda_joint77'\nhint: did you mean 'panda_joint7'?"


def test_github_paths_are_relative_to_the_working_directory(tmp_path: Path) -> None:
    # GitHub matches annotations to files by their path in the repository
    result = run_robospec("validate", "--format", "github", str(ROOT / MISSPELLED))
    assert result.stdout.startswith(f"::error file={MISSPELLED},line=6,col=51,")


def test_github_escapes_carriage_returns() -> None:
    d = error(Location("a.yaml", 2, 3), "RS101", "one\r\ntwo")
    assert annotation(d) == "::error file=a.yaml,line=2,col=3,title=RS101::one%0D%0Atwo"


# -- sarif --------------------------------------------------------------------------------------


@pytest.mark.slow
def test_sarif_of_every_failing_example_is_valid_and_round_trips_the_json_locations() -> None:
    sarif = run_robospec("validate", "--format", "sarif", *FAILING)
    report = run_robospec("validate", "--format", "json", *FAILING)
    assert sarif.returncode == report.returncode == 1
    document = json.loads(sarif.stdout)
    assert sarif_errors(document) == []
    (run,) = document["runs"]
    driver = run["tool"]["driver"]
    assert driver["name"] == "robospec" and driver["version"]
    rules = driver["rules"]
    expected = json.loads(report.stdout)["diagnostics"]
    assert [r["id"] for r in rules] == sorted({d["code"] for d in expected})
    for entry in rules:
        assert entry["shortDescription"]["text"] == CODES[entry["id"]].title
    root = urlsplit(run["originalUriBaseIds"]["%SRCROOT%"]["uri"])
    assert Path(unquote(root.path)) == ROOT
    found = []
    for result in run["results"]:
        assert rules[result["ruleIndex"]]["id"] == result["ruleId"]
        physical = result["locations"][0]["physicalLocation"]
        artifact, region = physical["artifactLocation"], physical["region"]
        assert artifact["uriBaseId"] == "%SRCROOT%"
        assert "\\" not in artifact["uri"] and not urlsplit(artifact["uri"]).scheme
        found.append(
            (
                unquote(artifact["uri"]),
                region["startLine"],
                region["startColumn"],
                result["ruleId"],
                result["level"],
                result["message"]["text"].split("\nhint: ")[0],
            )
        )
    assert found == [
        (d["file"], d["line"], d["column"], d["code"], d["severity"], d["message"])
        for d in expected
    ]


def test_sarif_locates_a_file_outside_the_working_directory_by_absolute_uri(
    tmp_path: Path,
) -> None:
    spec = tmp_path / "spec file.yaml"
    spec.write_text((ROOT / UNKNOWN_KEY).read_text())
    result = run_robospec("validate", "--format", "sarif", str(spec))
    document = json.loads(result.stdout)
    assert sarif_errors(document) == []
    (finding,) = document["runs"][0]["results"]
    artifact = finding["locations"][0]["physicalLocation"]["artifactLocation"]
    assert artifact == {"uri": spec.as_uri()}
    assert "%20" in artifact["uri"]


def test_sarif_rules_link_to_their_docs_when_the_project_has_urls() -> None:
    diagnostics = [
        error(Location("specs/a.yaml", 3, 5), "RS201", "unknown joint 'x'", "did you mean 'y'?"),
        error(Location("specs/b.yaml", 1, 1), "RS101", "unknown key 'z'"),
    ]
    urls = {
        "homepage": "https://example.org/robospec",
        "documentation": "https://example.org/docs/",
    }
    document = sarif_log(diagnostics, ROOT, urls)
    assert sarif_errors(document) == []
    driver = document["runs"][0]["tool"]["driver"]
    assert driver["informationUri"] == "https://example.org/robospec"
    for rule in driver["rules"]:  # the pages the URIs name exist
        assert (ROOT / "docs/codes" / f"{rule['id']}.md").is_file()
    assert [r["helpUri"] for r in driver["rules"]] == [
        "https://example.org/docs/codes/RS101.md",
        "https://example.org/docs/codes/RS201.md",
    ]


def test_sarif_with_no_diagnostics_is_a_valid_empty_run() -> None:
    result = run_robospec("validate", "--format", "sarif", "specs/maniskill/panda.yaml")
    assert result.returncode == 0, result.stdout + result.stderr
    document = json.loads(result.stdout)
    assert sarif_errors(document) == []
    assert document["runs"][0]["results"] == []


# -- the option on build and import ---------------------------------------------------------------


def test_build_reports_in_sarif_and_github(tmp_path: Path) -> None:
    out = tmp_path / "pkg"
    sarif = run_robospec("build", UNKNOWN_KEY, "-o", str(out), "--format", "sarif")
    assert sarif.returncode == 1
    assert sarif_errors(json.loads(sarif.stdout)) == []
    github = run_robospec("build", UNKNOWN_KEY, "-o", str(out), "--format", "github")
    assert github.returncode == 1
    assert f"::error file={UNKNOWN_KEY},line=13,col=1,title=RS101::" in github.stdout
    assert not out.exists()


def test_import_reports_in_github_format_on_stderr() -> None:
    result = run_robospec("import", "not-a-target", "--format", "github")
    assert result.returncode == 1
    assert result.stderr.startswith("::error file=<module%3AClass>,line=1,col=1,title=RS400::")
    assert "Traceback" not in result.stderr


def test_an_unknown_format_or_colour_is_a_usage_error() -> None:
    assert run_robospec("validate", "--format", "xml", MISSPELLED).returncode == 2
    assert run_robospec("validate", "--color", "sometimes", MISSPELLED).returncode == 2


def test_text_excerpt_follows_a_spec_edited_in_the_same_process(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # one process (a notebook calling register) reports twice on a file edited in between, and
    # on a same-named file in another folder: each excerpt shows the line as it is now
    spec = tmp_path / "a" / "robot.yaml"
    spec.parent.mkdir()
    diagnostic = error(Location("robot.yaml", 2, 1), "RS101", "unknown key 'x'")
    monkeypatch.chdir(spec.parent)
    spec.write_text("robospec: 1\nfirst_version: 1\n")
    assert "first_version" in render([diagnostic], 1, "text")
    spec.write_text("robospec: 1\nsecond_version_of_it: 1\n")
    assert "second_version_of_it" in render([diagnostic], 1, "text")
    other = tmp_path / "b" / "robot.yaml"
    other.parent.mkdir()
    other.write_text("robospec: 1\nanother_folder: 1\n")
    monkeypatch.chdir(other.parent)
    assert "another_folder" in render([diagnostic], 1, "text")
