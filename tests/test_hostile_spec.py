"""Hostile spec files through every entry point: `robospec validate`, `robospec build -o DIR`
and `robospec.register(...)` each answer with a located, coded diagnostic and exit 1 (or
SpecError), never a traceback, a hang or a half-written output folder.

The parsers' own behaviour is tested beside them (tests/test_toml_positions.py,
docs/examples/codes/); this is the cross-entry-point matrix of issue 6. A few cases also run
in a real child process to prove nothing that looks like a traceback reaches stderr.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest
from conftest import fast_first, invoke_robospec, run_robospec

import robospec
from robospec.diagnostics import Diagnostic
from robospec.diagnostics.codes import CODES
from robospec.pipeline import compile_spec

GOOD_YAML = (
    "robospec: 1\n"
    "uid: rs_hostile\n"
    'description: {urdf: "{maniskill_assets}/robots/panda/panda_v2.urdf"}\n'
    "controllers:\n"
    '  arm: {type: pd_joint_pos, joints: "panda_joint[1-7]", lower: null, upper: null,'
    " stiffness: 1e3, damping: 1e2}\n"
    "  gripper: {type: pd_joint_pos, joints: [panda_finger_joint1, panda_finger_joint2],"
    " lower: 0, upper: 0.04, stiffness: 1e3, damping: 1e2}\n"
    "control_modes:\n"
    "  pd_joint_pos: {arm: arm, gripper: gripper}\n"
)
GOOD_TOML = (
    "robospec = 1\n"
    'uid = "rs_hostile"\n'
    'description = { urdf = "{maniskill_assets}/robots/panda/panda_v2.urdf" }\n'
    "[controllers.arm]\n"
    'type = "pd_joint_pos"\n'
    'joints = "panda_joint[1-7]"\n'
    "lower = -6.3\n"
    "upper = 6.3\n"
    "stiffness = 1e3\n"
    "damping = 1e2\n"
    "[controllers.gripper]\n"
    'type = "pd_joint_pos"\n'
    'joints = ["panda_finger_joint1", "panda_finger_joint2"]\n'
    "lower = 0\n"
    "upper = 0.04\n"
    "stiffness = 1e3\n"
    "damping = 1e2\n"
    "[control_modes]\n"
    'pd_joint_pos = { arm = "arm", gripper = "gripper" }\n'
)

_DEEP = 10_000
_BOMB = "a: &a [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 10)}]\n" for i in range(8)
)


@dataclass(frozen=True)
class Hostile:
    """A bad spec: its file name, how to make it, and the diagnostic it must give."""

    name: str
    make: Callable[[Path], None]  # writes (or creates) the spec at the given path
    code: str
    line: int
    column: int | None = None  # None: any column >= 1

    def param(self) -> object:
        return pytest.param(self, id=self.name.replace(".", "_"))


def _text(data: str | bytes) -> Callable[[Path], None]:
    raw = data.encode() if isinstance(data, str) else data

    def make(path: Path) -> None:
        path.write_bytes(raw)

    return make


def _huge(path: Path) -> None:
    with path.open("wb") as handle:  # 50 MB of plausible YAML, written in 1 MB pieces
        piece = b"# " + b"x" * 1021 + b"\n"
        for _ in range(50 * 1024):
            handle.write(piece)


def _folder(path: Path) -> None:
    path.mkdir()
    (path / "notes.txt").write_text("a folder named like a spec\n")


def _fifo(path: Path) -> None:
    os.mkfifo(path)


def _unreadable(path: Path) -> None:
    path.symlink_to(path.name)  # a link to itself: reading it fails (ELOOP) for every user


SPEC_CASES = [
    # a list and a string never closed: at the bracket and the quote (RS015)
    Hostile("malformed.yaml", _text("robospec: 1\nuid: [rs_a, rs_b\n"), "RS015", 2, 6),
    Hostile("malformed.toml", _text('robospec = 1\nuid = "rs_a\n'), "RS015", 2, 7),
    Hostile(
        "wrong_type.yaml",
        _text(GOOD_YAML.replace("stiffness: 1e3", "stiffness: [1]", 1)),
        "RS102",
        5,
    ),
    Hostile(
        "wrong_type.toml", _text(GOOD_TOML.replace('uid = "rs_hostile"', "uid = 5")), "RS102", 2, 7
    ),
    Hostile("unknown_key.yaml", _text(GOOD_YAML + "colour: red\n"), "RS101", 9, 1),
    Hostile("unknown_key.toml", _text('colour = "red"\n' + GOOD_TOML), "RS101", 1, 1),
    Hostile(
        "duplicate_key.yaml",
        _text(GOOD_YAML.replace("uid: rs_hostile\n", "uid: rs_hostile\nuid: rs_other\n")),
        "RS003",
        3,
    ),
    Hostile(
        "duplicate_key.toml",
        _text(GOOD_TOML.replace('uid = "rs_hostile"\n', 'uid = "rs_hostile"\nuid = "rs_other"\n')),
        "RS003",
        3,
    ),
    Hostile("empty.yaml", _text(""), "RS004", 1, 1),
    Hostile("empty.toml", _text(""), "RS004", 1, 1),
    Hostile("whitespace.yaml", _text(" \n\t\n   \n"), "RS004", 1, 1),
    Hostile("whitespace.toml", _text(" \n\t\n   \n"), "RS004", 1, 1),
    Hostile("huge.yaml", _huge, "RS006", 1, 1),
    Hostile("deep_list.yaml", _text("a: " + "[" * _DEEP + "]" * _DEEP + "\n"), "RS006", 1),
    Hostile("deep_map.yaml", _text("a: " + "{a: " * _DEEP + "1" + "}" * _DEEP + "\n"), "RS006", 1),
    Hostile(
        "deep_block.yaml",
        _text("".join(" " * i + "a:\n" for i in range(1500)) + " " * 1500 + "1\n"),
        "RS006",
        257,
    ),
    Hostile("deep_items.yaml", _text("a:\n" + "- " * _DEEP + "1\n"), "RS006", 2),
    Hostile("deep_list.toml", _text("a = " + "[" * _DEEP + "]" * _DEEP + "\n"), "RS006", 1),
    Hostile(
        "deep_table.toml", _text("a = " + "{a = " * _DEEP + "1" + "}" * _DEEP + "\n"), "RS006", 1
    ),
    Hostile("many_values.yaml", _text("a: [" + ", ".join(["1"] * 300_000) + "]\n"), "RS006", 1),
    Hostile("alias_bomb.yaml", _text(_BOMB), "RS006", 6, 1),
    Hostile("invalid_utf8.yaml", _text(b"robospec: 1\nuid: rs_\xff\xfe\n"), "RS001", 2, 9),
    Hostile("invalid_utf8.toml", _text(b'robospec = 1\nuid = "rs_\xc3"\n'), "RS001", 2, 11),
    Hostile("bom_unknown_key.yaml", _text("\ufeff" + GOOD_YAML + "colour: red\n"), "RS101", 9, 1),
    Hostile(
        "bom_unknown_key.toml", _text("\ufeff" + 'colour = "red"\n' + GOOD_TOML), "RS101", 1, 1
    ),
    Hostile("nul.yaml", _text(b"robospec: 1\nuid: rs\x00x\n"), "RS002", 2, 8),
    Hostile("nul.toml", _text(b'robospec = 1\nuid = "rs\x00x"\n'), "RS002", 2),
    Hostile("huge_integer.yaml", _text("robospec: " + "9" * 5000 + "\n"), "RS002", 1, 11),
    Hostile("huge_integer.toml", _text("robospec = " + "9" * 5000 + "\n"), "RS002", 1, 12),
    Hostile("merge_key.yaml", _text("base: &b {robospec: 1}\n<<: *b\nuid: 5\n"), "RS101", 1),
    Hostile("complex_key.yaml", _text("? [a, b]\n: 1\n"), "RS002", 1),
    # a tagged list has no item positions in ruamel: RS900 before (found by atheris)
    Hostile("tagged_list.yaml", _text("robospec: 1\nuid: !tag [x, y]\n"), "RS102", 2, 6),
    # a mapping key holding a list is unhashable: ruamel raised TypeError (found by atheris)
    Hostile("unhashable_key.yaml", _text("a: 1\nb:\n  {x: [1]}: 2\n"), "RS002", 3, 3),
    # a description path longer than the file system allows (found by atheris)
    Hostile(
        "long_description_path.yaml",
        _text(GOOD_YAML.replace("{maniskill_assets}/robots/panda/panda_v2.urdf", "x" * 300)),
        "RS050",
        3,
    ),
    # ruamel's round-trip parser raises NotImplementedError on this comment (found by atheris)
    Hostile("comment_overlap.yaml", _text("a:\n  b:  # c\n     y\n\n"), "RS002", 2, 7),
    Hostile("folder.yaml", _folder, "RS001", 1, 1),
    Hostile("fifo.yaml", _fifo, "RS001", 1, 1),
    Hostile(
        "missing_description.yaml",
        _text(GOOD_YAML.replace("{maniskill_assets}/robots/panda/panda_v2.urdf", "no.urdf")),
        "RS050",
        3,
    ),
    # a path that no one can read, root included (a chmod 000 file root would read anyway)
    Hostile("unreadable.yaml", _unreadable, "RS001", 1, 1),
]


def _make(case: Hostile, folder: Path) -> Path:
    path = folder / case.name
    case.make(path)
    return path


def _line_count(path: Path) -> int:
    if not path.is_file():
        return 1  # a folder or FIFO (opening a FIFO would wait for a writer)
    try:
        with path.open("rb") as handle:
            return max(sum(1 for _ in handle), 1)
    except OSError:
        return 1  # a folder, FIFO or unreadable file: only line 1 can be named


def _assert_located(case: Hostile, path: Path, found: list[tuple[str, str, int, int]]) -> None:
    """``found``: (file, code, line, column) of every error; one must be the case's."""
    assert found, f"{case.name}: no error"
    for file, code, line, column in found:
        assert code in CODES, code
        assert line >= 1 and column >= 1, (file, code, line, column)
        if Path(file).name == path.name:
            assert line <= _line_count(path), (file, code, line, column)
    matching = [f for f in found if f[1] == case.code]
    assert matching, f"{case.name}: expected {case.code}, got {found}"
    _, _, line, column = matching[0]
    assert line == case.line, (case.name, matching[0])
    if case.column is not None:
        assert column == case.column, (case.name, matching[0])


def _json_errors(output: str) -> list[tuple[str, str, int, int]]:
    report = json.loads(output)
    return [
        (d["file"], d["code"], d["line"], d["column"])
        for d in report["diagnostics"]
        if d["severity"] == "error"
    ]


def _errors(diagnostics: list[Diagnostic]) -> list[tuple[str, str, int, int]]:
    return [
        (d.location.file, d.code, d.location.line, d.location.column)
        for d in diagnostics
        if d.is_error
    ]


@pytest.mark.parametrize("case", [c.param() for c in SPEC_CASES])
def test_validate_gives_the_located_code_and_exit_1(case: Hostile, tmp_path: Path) -> None:
    path = _make(case, tmp_path)
    result = invoke_robospec("validate", str(path), "--format", "json")
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    _assert_located(case, path, _json_errors(result.stdout))


@pytest.mark.parametrize("case", [c.param() for c in SPEC_CASES])
def test_build_gives_the_located_code_and_writes_no_output_folder(
    case: Hostile, tmp_path: Path
) -> None:
    path = _make(case, tmp_path)
    out = tmp_path / "out_pkg"
    result = invoke_robospec("build", str(path), "-o", str(out), "--format", "json")
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    _assert_located(case, path, _json_errors(result.stdout))
    assert not out.exists()


def test_build_into_an_existing_folder_leaves_it_as_it_was(tmp_path: Path) -> None:
    spec = tmp_path / "bad.yaml"
    spec.write_text("a: " + "[" * _DEEP + "]" * _DEEP + "\n")
    out = tmp_path / "pkg"
    out.mkdir()
    (out / "mine.py").write_text("# not robospec's\n")
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    result = invoke_robospec("build", str(spec), "-o", str(out))
    assert result.exit_code == 1
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


@pytest.mark.usefixtures("maniskill")  # register() imports ManiSkill first
@pytest.mark.parametrize("case", [c.param() for c in SPEC_CASES])
def test_register_raises_spec_error_with_the_located_code_and_registers_nothing(
    case: Hostile, tmp_path: Path
) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    path = _make(case, tmp_path)
    before = dict(REGISTERED_AGENTS)
    with pytest.raises(robospec.SpecError) as caught:
        robospec.register(path, cache_dir=tmp_path / "cache")
    _assert_located(case, path, _errors(caught.value.diagnostics))
    assert dict(REGISTERED_AGENTS) == before


# The work each expensive input would cause, which its refusal must come before: parsing
# (ruamel.yaml's scanner is quadratic in flow nesting and slow per value, tomllib recurses per
# level: tens of seconds), or, for the alias bomb, which parses small, walking the 10^9 values
# it expands to into plain data.
EXPENSIVE_WORK = {
    "huge.yaml": "_load_yaml",
    "deep_list.yaml": "_load_yaml",
    "deep_map.yaml": "_load_yaml",
    "many_values.yaml": "_load_yaml",
    "deep_list.toml": "_load_toml",
    "alias_bomb.yaml": "_walk_yaml",
}


@pytest.mark.parametrize("case", [c.param() for c in SPEC_CASES if c.name in EXPENSIVE_WORK])
def test_expensive_inputs_are_refused_before_the_expensive_work(
    case: Hostile, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # RS006 says a limit was hit; the work it guards against fails here if it starts, so the
    # refusal came before it (no clock: how fast robospec refuses is benchmarks/' to measure)
    from robospec.load import reader

    work = EXPENSIVE_WORK[case.name]

    def started(*_: object) -> None:
        raise AssertionError(f"{case.name} reached {work}")

    monkeypatch.setattr(reader, work, started)
    result = compile_spec(_make(case, tmp_path))
    assert [d.code for d in result.diagnostics] == ["RS006"]


def test_the_good_specs_used_here_are_valid(tmp_path: Path) -> None:
    for name, text in (("good.yaml", GOOD_YAML), ("good.toml", GOOD_TOML)):
        path = tmp_path / name
        path.write_text(text)
        assert compile_spec(path).ok, _errors(compile_spec(path).diagnostics)
    bom = tmp_path / "bom.yaml"
    bom.write_bytes(b"\xef\xbb\xbf" + GOOD_YAML.encode())
    assert compile_spec(bom).ok


@pytest.mark.parametrize(
    "name",
    fast_first(["deep_list.yaml", "alias_bomb.yaml", "invalid_utf8.yaml", "fifo.yaml", "nul.toml"]),
)
def test_a_real_process_prints_no_traceback(name: str, tmp_path: Path) -> None:
    (case,) = [c for c in SPEC_CASES if c.name == name]
    path = _make(case, tmp_path)
    for command in (["validate", str(path)], ["build", str(path), "-o", str(tmp_path / "o")]):
        result = run_robospec(*command)
        assert result.returncode == 1, result.stderr
        assert "Traceback" not in result.stderr + result.stdout
        assert f"[{case.code}]" in result.stderr + result.stdout
        assert not (tmp_path / "o").exists()


def test_a_spec_path_longer_than_the_file_system_allows_is_rs001(tmp_path: Path) -> None:
    path = tmp_path / ("x" * 300 + ".yaml")
    result = invoke_robospec("validate", str(path), "--format", "json")
    assert result.exit_code == 1
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert [e[1:] for e in _json_errors(result.stdout)] == [("RS001", 1, 1)]


def test_an_anchor_defined_twice_prints_nothing_on_stderr(tmp_path: Path) -> None:
    # YAML lets a later anchor replace an earlier one; ruamel warned about it on stderr,
    # naming its own source file, around robospec's diagnostics
    path = tmp_path / "anchors.yaml"
    path.write_text(
        GOOD_YAML.replace("lower: 0,", "lower: &v 0,").replace("upper: 0.04", "upper: &v 0.04")
    )
    result = run_robospec("validate", str(path))
    assert result.returncode == 0, result.stdout
    assert result.stderr == ""
