"""expand_xacro: expansion in a child process, located failures, time and memory limits."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

from robospec.description.xacro import (
    DEFAULT_MEMORY_BYTES,
    DEFAULT_TIMEOUT_S,
    configured_limits,
    expand_xacro,
)
from robospec.description.xacro_content import xacro_content
from robospec.diagnostics.codes import XACRO_CONTENT

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


@pytest.mark.slow
def test_memory_bomb_hits_the_memory_limit(tmp_path: Path) -> None:
    path = write(tmp_path, '  <link name="${2**2**34}"/>\n')
    # the message names the limit that stopped it: the memory limit, long before the clock's
    text, diags = expand_xacro(str(path), {}, memory_bytes=128 << 20, timeout_s=60)
    assert text is None
    assert [(d.code, d.location.file) for d in diags] == [("RS054", str(path))]
    assert "memory limit of 128 MiB" in diags[0].message


def test_string_bomb_hits_the_memory_limit(tmp_path: Path) -> None:
    path = write(tmp_path, "  <link name=\"${'x' * 10**10}\"/>\n")
    _, diags = expand_xacro(str(path), {}, memory_bytes=256 << 20, timeout_s=60)
    assert [d.code for d in diags] == ["RS054"]
    assert "memory limit of 256 MiB" in diags[0].message  # the memory limit ends it, not the clock


@pytest.mark.slow
def test_long_computation_hits_the_timeout(tmp_path: Path) -> None:
    # hours of work: only the time limit ends it, and the message says that it did
    path = write(tmp_path, '  <link name="${python.sum(python.range(10**12))}"/>\n')
    text, diags = expand_xacro(str(path), {}, timeout_s=1, memory_bytes=256 << 20)
    assert text is None
    assert [(d.code, d.location.file) for d in diags] == [("RS054", str(path))]
    assert "time limit of 1 s" in diags[0].message


def test_printing_from_the_file_cannot_corrupt_the_answer(tmp_path: Path) -> None:
    # xacro.message() writes to stdout in xacro's own process; the answer must survive it.
    path = write(tmp_path, "  <link name=\"a${xacro.message('hello')}\"/>\n")
    text, diags = expand_xacro(str(path), {})
    assert diags == []
    assert text is not None and '<link name="a"/>' in text


# -- a xacro file is code: what it can do, and what the limits do about it ---------------------

# xacro's expression "sandbox" refuses names with "__", but strings can be glued together: these
# properties reach the os module, as any xacro file could. OS['system'](...) runs a shell.
ESCAPE_TO_OS = """\
  <xacro:property name="S"
    value="${python.vars(python.type)['_'+'_subclasses_'+'_'](python.type(1).mro()[-1])}"/>
  <xacro:property name="W"
    value="${[c for c in S if python.repr(c) == &quot;&lt;class 'os._wrap_close'&gt;&quot;][0]}"/>
  <xacro:property name="F" value="${python.vars(W)['_'+'_init_'+'_']}"/>
  <xacro:property name="G" value="${python.vars(python.type(F))['_'+'_globals_'+'_']}"/>
  <xacro:property name="OS" value="${python.vars(python.type(G))['_'+'_get_'+'_'](G, F)}"/>
"""


def test_the_sandbox_escape_used_below_really_reaches_os(tmp_path: Path) -> None:
    path = write(tmp_path, ESCAPE_TO_OS + "  <link name=\"${OS['getcwd']()}\"/>\n")
    text, diags = expand_xacro(str(path), {})
    assert diags == []
    assert text is not None and f'<link name="{tmp_path}"/>' in text


def background(tmp_path: Path) -> tuple[str, Path]:
    """A shell line that leaves a process running for a minute, and the file that will hold
    that process's id."""
    pid_file = tmp_path / "background.pid"
    return f"(sleep 60; touch {tmp_path / 'SURVIVED'}) &amp; echo $! &gt;{pid_file}", pid_file


def ended(pid: int, within_s: float = 30) -> bool:
    """Whether process ``pid`` is gone (or a zombie: it has ended, no one reaped it yet),
    waiting up to ``within_s`` for it: a generous bound, met at once when all is well."""
    deadline = time.monotonic() + within_s
    while True:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except FileNotFoundError:
            return True
        if state == "Z":
            return True
        if time.monotonic() > deadline:
            return False
        time.sleep(0.02)


def test_a_process_the_file_leaves_running_is_killed_when_expansion_ends(tmp_path: Path) -> None:
    shell, pid_file = background(tmp_path)
    path = write(tmp_path, ESCAPE_TO_OS + f"  <link name=\"a${{OS['system']('{shell}')}}\"/>\n")
    text, diags = expand_xacro(str(path), {}, timeout_s=60)
    # no RS054: the process it left running (holding the output pipes) did not hold us up
    assert diags == [] and text is not None and '<link name="a0"/>' in text
    pid = int(pid_file.read_text())
    assert ended(pid), "a process started by the xacro file outlived the expansion"


@pytest.mark.slow
def test_a_process_started_before_a_runaway_loop_dies_with_it(tmp_path: Path) -> None:
    shell, pid_file = background(tmp_path)
    path = write(
        tmp_path,
        ESCAPE_TO_OS
        + f"  <xacro:property name=\"started\" value=\"${{OS['system']('{shell}')}}\"/>\n"
        + '  <link name="${started + python.sum(python.range(10**12))}"/>\n',
    )
    _, diags = expand_xacro(str(path), {}, timeout_s=1)
    assert [d.code for d in diags] == ["RS054"] and "time limit of 1 s" in diags[0].message
    assert ended(int(pid_file.read_text()))


def test_a_fork_that_keeps_the_answer_pipe_open_cannot_hold_the_expansion(tmp_path: Path) -> None:
    # the forked copy carries on expanding the same file, for hours; the parent answers "a1".
    # Waiting for the pipe to close would end in the time limit (RS054), not in that answer.
    path = write(
        tmp_path,
        ESCAPE_TO_OS
        + '  <xacro:property name="pid" value="${OS[\'fork\']()}"/>\n'
        + '  <link name="a${1 if pid else python.sum(python.range(10**12))}"/>\n',
    )
    text, diags = expand_xacro(str(path), {}, timeout_s=60)
    assert diags == [] and text is not None and '<link name="a1"/>' in text


@pytest.mark.parametrize(
    "flood",
    [
        "OS['write'](1, b'x' * 65536)",  # its stdout
        "OS['write'](2, b'x' * 65536)",  # its stderr
        "xacro.message('x' * 65536)",  # xacro's own printing
    ],
    ids=["stdout", "stderr", "xacro.message"],
)
def test_output_flooding_is_stopped_at_the_output_limit(tmp_path: Path, flood: str) -> None:
    path = write(
        tmp_path, ESCAPE_TO_OS + f'  <link name="${{[{flood} for i in python.range(10**9)]}}"/>\n'
    )
    text, diags = expand_xacro(str(path), {}, timeout_s=60)
    assert text is None
    assert [d.code for d in diags] == ["RS054"]
    assert "printed more than 64 MiB" in diags[0].message  # the output limit, not the clock


def test_a_file_including_itself_stops_at_once_with_a_short_hint(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:include filename="robot.urdf.xacro"/>\n')
    _, diags = expand_xacro(str(path), {}, timeout_s=60)
    assert [d.code for d in diags] == ["RS053"]  # the nesting limit, not the clock
    assert "nested more than 50 deep" in diags[0].message
    assert diags[0].hint is not None and len(diags[0].hint) < 1000 and "more" in diags[0].hint


def test_two_files_including_each_other_stop_at_once(tmp_path: Path) -> None:
    write(tmp_path, '  <xacro:include filename="robot.urdf.xacro"/>\n', name="other.xacro")
    path = write(tmp_path, '  <xacro:include filename="other.xacro"/>\n')
    _, diags = expand_xacro(str(path), {}, timeout_s=60)
    assert [d.code for d in diags] == ["RS053"] and "nested" in diags[0].message


def test_limits_come_from_the_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROBOSPEC_XACRO_TIMEOUT", "0.5")
    monkeypatch.setenv("ROBOSPEC_XACRO_MEMORY_MB", "200")
    assert configured_limits() == (0.5, 200 << 20)
    slow = write(tmp_path, '  <link name="${python.sum(python.range(10**12))}"/>\n')
    _, diags = expand_xacro(str(slow), {})
    assert "time limit of 0.5 s" in diags[0].message
    # the memory limit alone, with time to reach it on a loaded machine (the time limit of 0.5 s
    # raced it there: allocating 200 MiB may take longer)
    monkeypatch.setenv("ROBOSPEC_XACRO_TIMEOUT", "60")
    big = write(tmp_path, "  <link name=\"${'x' * 10**10}\"/>\n", name="big.xacro")
    _, diags = expand_xacro(str(big), {})
    assert "memory limit of 200 MiB" in diags[0].message


@pytest.mark.parametrize("value", ["", "0", "-5", "nan", "inf", "lots"])
def test_a_limit_set_to_nonsense_keeps_the_default(
    monkeypatch: pytest.MonkeyPatch, value: str
) -> None:
    monkeypatch.setenv("ROBOSPEC_XACRO_TIMEOUT", value)
    monkeypatch.setenv("ROBOSPEC_XACRO_MEMORY_MB", value)
    assert configured_limits() == (DEFAULT_TIMEOUT_S, DEFAULT_MEMORY_BYTES)


# An audit hook in a real `robospec validate` process: every process it would start is printed.
AUDIT = """\
import sys
def hook(event, args):
    if event in ("subprocess.Popen", "os.system", "os.posix_spawn", "os.fork", "os.exec",
                 "os.spawn", "os.startfile"):
        # the whole call: its length depends on where the checkout lives
        print("STARTED", event, repr(args), file=sys.stderr)
sys.addaudithook(hook)
from robospec.cli import main
sys.argv = ["robospec", "validate", *sys.argv[1:]]
main()
"""


@pytest.mark.parametrize(
    "spec", ["specs/maniskill/panda.yaml", "tests/specs/positive/minimal.yaml"]
)
def test_validating_a_spec_without_xacro_starts_no_process(spec: str) -> None:
    root = Path(__file__).resolve().parent.parent
    result = subprocess.run(
        [sys.executable, "-c", AUDIT, spec], cwd=root, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "STARTED" not in result.stderr, result.stderr
    assert "xacro" not in result.stderr


def test_the_audit_hook_sees_the_xacro_child_of_a_xacro_spec() -> None:
    # the control for the test above: the hook does see the child when there is one
    root = Path(__file__).resolve().parent.parent
    result = subprocess.run(
        [sys.executable, "-c", AUDIT, "specs/twolink.toml"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "STARTED subprocess.Popen" in result.stderr and "_xacro_child.py" in result.stderr


TWOLINK_XACRO = Path(__file__).resolve().parent.parent / "specs" / "robots" / "twolink"


def _twolink_named_urdf(tmp_path: Path, urdf_text: str) -> Path:
    """specs/twolink.toml with its description a ``urdf:`` named ``twolink.urdf``."""
    (tmp_path / "twolink.urdf").write_text(urdf_text, encoding="utf-8")
    spec = (TWOLINK_XACRO.parent.parent / "twolink.toml").read_text(encoding="utf-8")
    described = (
        'xacro = "robots/twolink/twolink.urdf.xacro"\n'
        'args = { prefix = "twolink_", link_length = 0.35 }\n'
    )
    assert described in spec
    (tmp_path / "twolink.toml").write_text(
        spec.replace(described, 'urdf = "twolink.urdf"\n'), encoding="utf-8"
    )
    return tmp_path / "twolink.toml"


def test_a_urdf_file_whose_content_is_xacro_is_expanded_as_xacro_and_said_so(
    tmp_path: Path,
) -> None:
    from robospec.pipeline import compile_spec

    xacro = (TWOLINK_XACRO / "twolink.urdf.xacro").read_text(encoding="utf-8")
    compiled = compile_spec(_twolink_named_urdf(tmp_path, xacro))
    assert [d.format_text() for d in compiled.diagnostics if d.is_error] == []
    assert compiled.robot is not None
    assert len(compiled.robot.active_joints) == 5  # the base yaw, shoulder, elbow; two fingers
    (said,) = [d for d in compiled.diagnostics if d.code == XACRO_CONTENT]
    line = xacro.splitlines().index('  <xacro:arg name="prefix" default="twolink_"/>') + 1
    assert (said.location.file, said.location.line) == (str(tmp_path / "twolink.urdf"), line)
    assert "expanded it as xacro" in said.message and "<xacro:arg>" in said.message


def test_an_expression_alone_makes_a_urdf_xacro_and_the_namespace_alone_does_not() -> None:
    expression = HEAD + '  <link name="${name}"/>\n' + TAIL
    found = xacro_content("robot.urdf", expression.encode())
    assert found is not None and 'name="${name}"' in found.message
    # an expansion keeps the namespace declaration (and a comment may say "xacro:")
    plain = HEAD + "  <!-- expanded from xacro: robot.urdf.xacro -->\n  <link name='a'/>\n" + TAIL
    assert xacro_content("robot.urdf", plain.encode()) is None
