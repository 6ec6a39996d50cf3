"""Broken robot descriptions (URDF, MJCF) through every entry point: `robospec validate`,
`robospec build -o DIR`, `robospec.register(...)` (a spec that names the file) and
`robospec inspect` (the file itself) each give an error located at the defect's line in the
description, with its code, and exit 1 (or SpecError) — never a traceback or a hang.

The parsers' defect catalogue is tested beside them (tests/test_description_urdf.py,
tests/test_description_mjcf.py); this is the cross-entry-point matrix of issue 6 item 1.
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
from robospec.diagnostics.codes import CODES
from robospec.pipeline import compile_spec

URDF = """<?xml version="1.0"?>
<robot name="hostile">
  <link name="base"/>
  <link name="upper"/>
  <link name="lower"/>
  <joint name="j1" type="revolute">
    <parent link="base"/>
    <child link="upper"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="upper"/>
    <child link="lower"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
</robot>
"""
MJCF = """<mujoco model="hostile">
  <default>
    <default class="arm"><joint axis="0 0 1" range="-1 1"/></default>
  </default>
  <worldbody>
    <body name="base">
      <body name="upper">
        <geom size=".05"/><joint name="j1" class="arm"/>
        <body name="lower">
          <geom size=".05"/><joint name="j2" axis="0 0 1" range="-1 1"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
SPEC = """robospec: 1
uid: rs_hostile_{kind}
description: {{{kind}: {file}}}
controllers:
  arm: {{type: pd_joint_pos, joints: [j1, j2], lower: -1, upper: 1, stiffness: 100, damping: 10}}
control_modes:
  pd_joint_pos: {{arm: arm}}
"""


@dataclass(frozen=True)
class Broken:
    """A broken description: how to make it in a folder, and the error it must give."""

    name: str
    kind: str  # "urdf" or "mjcf"
    make: Callable[[Path], None]  # writes the description (and what it includes) at the path
    code: str
    line: int
    words: str  # in the message
    file: str | None = None  # the file the error is in, when not the description itself
    # a file that is not there (or not a file) is the spec's mistake: validate, build and
    # register locate it at the spec's `description:` value, on this line; inspect at line 1
    spec_line: int | None = None

    def param(self) -> object:
        return pytest.param(self, id=self.name)


def _edit(text: str, old: str, new: str) -> Callable[[Path], None]:
    assert old in text, old
    edited = text.replace(old, new, 1)

    def make(path: Path) -> None:
        path.write_text(edited)

    return make


def _urdf(old: str, new: str) -> Callable[[Path], None]:
    return _edit(URDF, old, new)


def _mjcf(old: str, new: str) -> Callable[[Path], None]:
    return _edit(MJCF, old, new)


def _nothing(path: Path) -> None:
    pass


def _folder(path: Path) -> None:
    path.mkdir()


def _fifo(path: Path) -> None:
    os.mkfifo(path)


def _unreadable(path: Path) -> None:
    path.symlink_to(path.name)  # a link to itself: reading it fails (ELOOP) for every user


def _include_cycle(path: Path) -> None:
    path.write_text(MJCF.replace("  <default>", '  <include file="part.xml"/>\n  <default>', 1))
    (path.parent / "part.xml").write_text(f'<mujoco>\n  <include file="{path.name}"/>\n</mujoco>\n')


LIMIT = '<limit lower="-1" upper="1" effort="10" velocity="1"/>'
J2_LIMIT = '<child link="lower"/>\n    ' + LIMIT

CASES = [
    Broken(
        "urdf_bad_xml",
        "urdf",
        _urdf('<link name="lower"/>', '<link name="lower">'),
        "RS051",
        16,
        "not well-formed",
    ),
    Broken("urdf_empty", "urdf", _edit("", "", ""), "RS051", 1, "not well-formed"),
    Broken(
        "urdf_missing_parent",
        "urdf",
        _urdf('    <parent link="upper"/>\n', ""),
        "RS052",
        11,
        "no <parent",
    ),
    Broken(
        "urdf_unknown_parent",
        "urdf",
        _urdf('<parent link="upper"/>', '<parent link="uper"/>'),
        "RS052",
        12,
        "unknown parent link 'uper'",
    ),
    Broken(
        "urdf_duplicate_link",
        "urdf",
        _urdf('<link name="lower"/>', '<link name="upper"/>'),
        "RS052",
        5,
        "duplicate link name 'upper'",
    ),
    Broken(
        "urdf_duplicate_joint",
        "urdf",
        _urdf('<joint name="j2" type="revolute">', '<joint name="j1" type="revolute">'),
        "RS052",
        11,
        "duplicate joint name 'j1'",
    ),
    Broken(
        "urdf_cycle",
        "urdf",
        _urdf(
            "</robot>",
            '  <joint name="j3" type="fixed"><parent link="lower"/>'
            '<child link="base"/></joint>\n</robot>',
        ),
        "RS052",
        6,
        "cycle",
    ),
    Broken(
        "urdf_several_roots",
        "urdf",
        _urdf('<link name="base"/>', '<link name="base"/>\n  <link name="orphan"/>'),
        "RS052",
        4,
        "several root links",
    ),
    Broken(
        "urdf_unknown_mimic",
        "urdf",
        _urdf(J2_LIMIT, J2_LIMIT + '\n    <mimic joint="j9"/>'),
        "RS052",
        15,
        "mimics unknown joint 'j9'",
    ),
    Broken(
        "urdf_lower_abc",
        "urdf",
        _urdf(J2_LIMIT, J2_LIMIT.replace('"-1"', '"abc"')),
        "RS052",
        14,
        'lower="abc" is not a number',
    ),
    Broken(
        "urdf_lower_nan",
        "urdf",
        _urdf(J2_LIMIT, J2_LIMIT.replace('"-1"', '"nan"')),
        "RS052",
        14,
        'lower="nan" is not a number',
    ),
    Broken(
        "urdf_upper_inf",
        "urdf",
        _urdf(J2_LIMIT, J2_LIMIT.replace('upper="1"', 'upper="inf"')),
        "RS052",
        14,
        'upper="inf" is not a number',
    ),
    Broken(
        "urdf_effort_1e999",
        "urdf",
        _urdf(J2_LIMIT, J2_LIMIT.replace('effort="10"', 'effort="1e999"')),
        "RS052",
        14,
        'effort="1e999" is not a number',
    ),
    Broken("urdf_missing", "urdf", _nothing, "RS050", 1, "No such file", spec_line=3),
    Broken("urdf_folder", "urdf", _folder, "RS050", 1, "folder", spec_line=3),
    Broken("urdf_fifo", "urdf", _fifo, "RS050", 1, "not a regular file", spec_line=3),
    Broken(
        "mjcf_bad_xml", "mjcf", _mjcf("</worldbody>", "</worldbdy>"), "RS051", 14, "not well-formed"
    ),
    Broken(
        "mjcf_unknown_class",
        "mjcf",
        _mjcf('<joint name="j1" class="arm"/>', '<joint name="j1" class="amr"/>'),
        "RS052",
        8,
        "unknown default class 'amr'",
    ),
    Broken(
        "mjcf_range_nan",
        "mjcf",
        _mjcf('range="-1 1"/>\n        </body>', 'range="nan 1"/>\n        </body>'),
        "RS052",
        10,
        'range="nan 1" is not 2 numbers',
    ),
    Broken(
        "mjcf_range_1e999",
        "mjcf",
        _mjcf('range="-1 1"/>\n        </body>', 'range="-1 1e999"/>\n        </body>'),
        "RS052",
        10,
        "is not 2 numbers",
    ),
    Broken(
        "mjcf_missing_include",
        "mjcf",
        _mjcf("  <default>", '  <include file="gone.xml"/>\n  <default>'),
        "RS050",
        2,
        "cannot read included file 'gone.xml'",
    ),
    Broken(
        "mjcf_include_cycle", "mjcf", _include_cycle, "RS052", 2, "include cycle", file="part.xml"
    ),
    # a path that no one can read, root included (a chmod 000 file root would read anyway)
    Broken(
        "urdf_unreadable",
        "urdf",
        _unreadable,
        "RS050",
        1,
        "Too many levels of symbolic links",
        spec_line=3,
    ),
]

# register() is given the spec, and the spec names the description: every case applies


def _setup(case: Broken, folder: Path) -> tuple[Path, Path]:
    """(the spec, the description it names), made in ``folder``."""
    description = folder / ("robot.urdf" if case.kind == "urdf" else "robot.xml")
    case.make(description)
    spec = folder / "robot.yaml"
    spec.write_text(SPEC.format(kind=case.kind, file=description.name))
    return spec, description


def _lines(path: Path) -> int:
    if not path.is_file():
        return 1
    try:
        return max(len(path.read_bytes().splitlines()), 1)
    except OSError:
        return 1


def _assert_located(
    case: Broken,
    description: Path,
    errors: list[tuple[str, str, int, int, str]],
    spec: Path | None = None,
) -> None:
    """``errors``: (file, code, line, column, message); one must be the case's own.
    ``spec``: the spec the entry point was given (None: inspect, given the description)."""
    assert errors, f"{case.name}: no error"
    if spec is not None and case.spec_line is not None:
        located = [(Path(e[0]).name, e[1], e[2]) for e in errors]
        assert (spec.name, case.code, case.spec_line) in located, (case.name, errors)
        return
    expected_file = description.parent / case.file if case.file else description
    for file, code, line, column, _ in errors:
        assert code in CODES and line >= 1 and column >= 1, (file, code, line, column)
        if Path(file).is_file():
            assert line <= _lines(Path(file)), (file, code, line)
    matching = [e for e in errors if e[1] == case.code and Path(e[0]).name == expected_file.name]
    assert matching, f"{case.name}: expected {case.code} in {expected_file.name}, got {errors}"
    _, _, line, _, message = matching[0]
    assert line == case.line, (case.name, matching[0])
    assert case.words in message, (case.name, message)


def _from_json(output: str) -> list[tuple[str, str, int, int, str]]:
    return [
        (d["file"], d["code"], d["line"], d["column"], d["message"])
        for d in json.loads(output)["diagnostics"]
        if d["severity"] == "error"
    ]


def test_the_unbroken_descriptions_are_valid(tmp_path: Path) -> None:
    for kind, text, name in (("urdf", URDF, "robot.urdf"), ("mjcf", MJCF, "robot.xml")):
        folder = tmp_path / kind
        folder.mkdir()
        (folder / name).write_text(text)
        spec = folder / "robot.yaml"
        spec.write_text(SPEC.format(kind=kind, file=name))
        assert compile_spec(spec).ok, compile_spec(spec).diagnostics


@pytest.mark.parametrize("case", [c.param() for c in CASES])
def test_validate_locates_the_defect_in_the_description(case: Broken, tmp_path: Path) -> None:
    spec, description = _setup(case, tmp_path)
    result = invoke_robospec("validate", str(spec), "--format", "json")
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    _assert_located(case, description, _from_json(result.stdout), spec)


@pytest.mark.parametrize("case", [c.param() for c in CASES])
def test_build_locates_the_defect_and_writes_nothing(case: Broken, tmp_path: Path) -> None:
    spec, description = _setup(case, tmp_path)
    out = tmp_path / "pkg"
    result = invoke_robospec("build", str(spec), "-o", str(out), "--format", "json")
    assert result.exit_code == 1, result.output
    _assert_located(case, description, _from_json(result.stdout), spec)
    assert not out.exists()


@pytest.mark.parametrize("case", [c.param() for c in CASES])
def test_inspect_locates_the_defect(case: Broken, tmp_path: Path) -> None:
    _, description = _setup(case, tmp_path)
    result = invoke_robospec("inspect", str(description), "--format", "json")
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    _assert_located(case, description, _from_json(result.stderr))


@pytest.mark.parametrize("case", [c.param() for c in CASES if c.kind == "mjcf"])
def test_the_mujoco_route_refuses_the_broken_mjcf_at_the_defects_line(
    case: Broken, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # `loader: mujoco` (what new writes): MuJoCo compiles the file, which it must refuse at
    # the same line, as robospec's own reading says it or as MuJoCo does (RS790)
    spec, description = _setup(case, tmp_path)
    spec.write_text(
        spec.read_text().replace("{mjcf: robot.xml}", "{mjcf: robot.xml, loader: mujoco}")
    )
    result = invoke_robospec("validate", str(spec), "--format", "json")
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    located = [(Path(f).name, code, line) for f, code, line, _, _ in _from_json(result.stdout)]
    # an include cycle is as well located at the model's own <include> that starts it
    files = {case.file or description.name, description.name}
    expected = {(file, code, case.line) for file in files for code in (case.code, "RS790")}
    assert expected & set(located), located
    # MuJoCo's parser warnings (a NaN) are robospec's to report, not a log in the user's folder
    monkeypatch.chdir(tmp_path)
    invoke_robospec("validate", str(spec))
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


@pytest.mark.usefixtures("maniskill")  # register() imports ManiSkill first
@pytest.mark.parametrize("case", [c.param() for c in CASES])
def test_register_raises_spec_error_locating_the_defect_and_registers_nothing(
    case: Broken, tmp_path: Path
) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    spec, description = _setup(case, tmp_path)
    before = dict(REGISTERED_AGENTS)
    with pytest.raises(robospec.SpecError) as caught:
        robospec.register(spec, cache_dir=tmp_path / "cache")
    errors = [
        (d.location.file, d.code, d.location.line, d.location.column, d.message)
        for d in caught.value.diagnostics
        if d.is_error
    ]
    _assert_located(case, description, errors, spec)
    assert dict(REGISTERED_AGENTS) == before


def test_a_nested_include_that_is_no_cycle_is_a_warning_that_it_is_not_loaded(
    tmp_path: Path,
) -> None:
    model = tmp_path / "robot.xml"
    model.write_text(MJCF.replace("  <default>", '  <include file="part.xml"/>\n  <default>', 1))
    (tmp_path / "part.xml").write_text('<mujoco>\n  <include file="more.xml"/>\n</mujoco>\n')
    (tmp_path / "more.xml").write_text("<mujoco/>\n")
    spec = tmp_path / "robot.yaml"
    spec.write_text(SPEC.format(kind="mjcf", file="robot.xml"))
    result = compile_spec(spec)
    assert result.ok
    (warning,) = [d for d in result.diagnostics if d.severity.value == "warning"]
    assert (Path(warning.location.file).name, warning.location.line) == ("part.xml", 2)
    assert "not read by ManiSkill" in warning.message


@pytest.mark.parametrize("name", fast_first(["urdf_bad_xml", "urdf_fifo", "mjcf_include_cycle"]))
def test_a_real_process_prints_no_traceback(name: str, tmp_path: Path) -> None:
    (case,) = [c for c in CASES if c.name == name]
    spec, description = _setup(case, tmp_path)
    for command in (["validate", str(spec)], ["inspect", str(description)]):
        result = run_robospec(*command)
        assert result.returncode == 1, result.stderr
        assert "Traceback" not in result.stderr + result.stdout
        assert f"[{case.code}]" in result.stderr + result.stdout


@pytest.mark.parametrize(
    ("make", "says"), [(_folder, "it is a folder"), (_fifo, "it is not a regular file")]
)
def test_a_description_path_that_is_no_file_says_what_it_is_at_the_spec(
    tmp_path: Path, make: Callable[[Path], None], says: str
) -> None:
    make(tmp_path / "robot.urdf")
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        "robospec: 1\nuid: rs_thing\ndescription: {urdf: robot.urdf}\n"
        "controllers: {all: {type: pd_joint_pos, joints: '*', lower: null, upper: null,\n"
        "                    stiffness: 1e3, damping: 1e2}}\n"
        "control_modes: {pd_joint_pos: {all: all}}\n"
    )
    errors = [d for d in compile_spec(spec).diagnostics if d.is_error]
    assert [(d.code, d.location.line) for d in errors] == [("RS050", 3)]
    assert errors[0].message == f"cannot use 'robot.urdf' as a file: {says}"
