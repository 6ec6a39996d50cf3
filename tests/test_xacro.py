"""expand_xacro: expansion in a child process, located failures, time and memory limits."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

from robospec.description.xacro import expand_xacro

HEAD = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
TAIL = "</robot>\n"


def write(tmp_path: Path, body: str, name: str = "robot.urdf.xacro") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + body + TAIL, encoding="utf-8")
    return path


def test_expands_with_args_and_defaults(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:arg name="prefix" default="a_"/>\n'
        '  <xacro:arg name="length" default="0.3"/>\n'
        '  <xacro:property name="half" value="${$(arg length) / 2}"/>\n'
        '  <link name="$(arg prefix)base"><origin xyz="0 0 ${half}"/></link>\n',
    )
    text, diags = expand_xacro(str(path), {"length": "0.5"})
    assert diags == []
    assert text is not None
    assert '<link name="a_base">' in text
    assert 'xyz="0 0 0.25"' in text
    assert "xacro:" not in text


def test_includes_resolve_against_the_file(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    write(tmp_path / "parts", '  <link name="included"/>\n', name="part.xacro")
    path = write(tmp_path, '  <xacro:include filename="parts/part.xacro"/>\n')
    text, diags = expand_xacro(str(path), {})
    assert diags == []
    assert text is not None and '<link name="included"/>' in text


def test_xacro_is_not_imported_in_this_process() -> None:
    code = "import sys, robospec.description.xacro; print('xacro' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_missing_file(tmp_path: Path) -> None:
    missing = str(tmp_path / "nope.xacro")
    text, diags = expand_xacro(missing, {})
    assert text is None
    assert [(d.code, d.location.file, d.location.line) for d in diags] == [("RS053", missing, 1)]
    assert "no such file" in diags[0].message


def test_missing_include(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:include filename="nothere.xacro"/>\n')
    text, diags = expand_xacro(str(path), {})
    assert text is None
    assert [d.code for d in diags] == ["RS053"]
    assert diags[0].location.file == str(path)
    assert "nothere.xacro" in diags[0].message


def test_xml_syntax_error_is_located(tmp_path: Path) -> None:
    path = write(tmp_path, '  <link name="a">\n  </lnk>\n')
    text, diags = expand_xacro(str(path), {})
    assert text is None
    assert len(diags) == 1
    d = diags[0]
    assert (d.code, d.location.file, d.location.line, d.location.column) == (
        "RS053",
        str(path),
        4,
        5,
    )
    assert "mismatched tag" in d.message


def test_error_in_included_file_is_located_there(tmp_path: Path) -> None:
    write(tmp_path, '  <link name="a">\n  </lnk>\n', name="part.xacro")
    path = write(tmp_path, '  <xacro:include filename="part.xacro"/>\n')
    _, diags = expand_xacro(str(path), {})
    assert [(d.code, d.location.file, d.location.line) for d in diags] == [
        ("RS053", str(tmp_path / "part.xacro"), 4)
    ]
    assert diags[0].hint is not None and "robot.urdf.xacro" in diags[0].hint


def test_undefined_property_is_located_at_its_expression(tmp_path: Path) -> None:
    path = write(tmp_path, '  <link name="a">\n    <origin xyz="0 0 ${foo * 2}"/>\n  </link>\n')
    text, diags = expand_xacro(str(path), {})
    assert text is None
    assert [(d.code, d.location.line, d.location.column) for d in diags] == [("RS053", 4, 22)]
    assert "name 'foo' is not defined" in diags[0].message
    assert "\n" not in diags[0].message


def test_undefined_arg_is_located(tmp_path: Path) -> None:
    path = write(tmp_path, '  <link name="$(arg nope)"/>\n')
    _, diags = expand_xacro(str(path), {})
    assert [(d.code, d.location.line, d.location.column) for d in diags] == [("RS053", 3, 15)]
    assert "nope" in diags[0].message


def test_eval_with_dunder_is_refused(tmp_path: Path) -> None:
    path = write(tmp_path, "  <link name=\"$(eval __import__('os').getcwd())\"/>\n")
    text, diags = expand_xacro(str(path), {})
    assert text is None
    assert [d.code for d in diags] == ["RS053"]
    assert "double underscore" in diags[0].message


def test_runaway_recursion_is_an_error_not_a_crash(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:macro name="m"><xacro:m/></xacro:macro>\n  <xacro:m/>\n')
    text, diags = expand_xacro(str(path), {})
    assert text is None
    assert [d.code for d in diags] == ["RS053"]
    assert "recursion" in diags[0].message


def test_memory_bomb_hits_the_memory_limit(tmp_path: Path) -> None:
    path = write(tmp_path, '  <link name="${2**2**34}"/>\n')
    start = time.monotonic()
    text, diags = expand_xacro(str(path), {}, memory_bytes=256 << 20, timeout_s=60)
    assert time.monotonic() - start < 30
    assert text is None
    assert [(d.code, d.location.file) for d in diags] == [("RS054", str(path))]
    assert "memory limit of 256 MiB" in diags[0].message


def test_string_bomb_hits_the_memory_limit(tmp_path: Path) -> None:
    path = write(tmp_path, "  <link name=\"${'x' * 10**10}\"/>\n")
    _, diags = expand_xacro(str(path), {}, memory_bytes=256 << 20)
    assert [d.code for d in diags] == ["RS054"]
    assert "memory" in diags[0].message


def test_long_computation_hits_the_timeout(tmp_path: Path) -> None:
    path = write(tmp_path, '  <link name="${python.sum(python.range(10**12))}"/>\n')
    start = time.monotonic()
    text, diags = expand_xacro(str(path), {}, timeout_s=2, memory_bytes=256 << 20)
    elapsed = time.monotonic() - start
    assert text is None
    assert [(d.code, d.location.file) for d in diags] == [("RS054", str(path))]
    assert "time limit of 2 s" in diags[0].message
    assert elapsed < 10


def test_printing_from_the_file_cannot_corrupt_the_answer(tmp_path: Path) -> None:
    # xacro.message() writes to stdout in xacro's own process; the answer must survive it.
    path = write(tmp_path, "  <link name=\"a${xacro.message('hello')}\"/>\n")
    text, diags = expand_xacro(str(path), {})
    assert diags == []
    assert text is not None and '<link name="a"/>' in text
