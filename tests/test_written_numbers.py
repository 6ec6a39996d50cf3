"""Numbers reach the generated code as the spec wrote them, and mean exactly the same.

The loader keeps a YAML or TOML float's text, the model keeps the text of arithmetic
(``pi/8``) and of integers; the value stays a float for everything that computes with it. The
emitter writes the text back (``np.pi / 8``, ``1e3``, ``100``) only where Python computes
exactly the validated value from it.
"""

from __future__ import annotations

import ast
import copy
import math
import pickle
import types
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_generated_code import FUZZ_SCALE

from robospec.emit.generate import emit_module
from robospec.emit.layout import format_module
from robospec.emit.numbers import number_expr
from robospec.load.reader import parse_spec_bytes
from robospec.load.source_map import WrittenNumber
from robospec.model.expressions import ExpressionError, evaluate
from robospec.pipeline import compile_spec

# what generated code computes `np.pi` and `np.e` as (numpy's are these floats)
NUMPY = types.SimpleNamespace(pi=math.pi, e=math.e)

SPEC = """robospec: 1
uid: rs_written
description: {{urdf: "{{maniskill_assets}}/robots/panda/panda_v2.urdf"}}
groups: {{arm: "panda_joint[1-7]", gripper: "panda_finger_*"}}
keyframes: {{rest: {{qpos: {qpos}}}}}
controllers:
  arm: {{type: pd_joint_pos, joints: arm, lower: -pi, upper: pi,
        stiffness: 1e3, damping: 1E2, force_limit: 100}}
  arm_delta: {{extends: arm, lower: -.1, upper: .1, use_delta: true}}
  gripper: {{type: pd_joint_pos, joints: gripper, lower: 0, upper: 0.04,
            stiffness: 1e3, damping: 1e2}}
control_modes:
  pd_joint_pos: {{arm: arm, gripper: gripper}}
  pd_joint_delta_pos: {{arm: arm_delta, gripper: gripper}}
"""


def written(source: str) -> str:
    """The number expression in the one-line module ``x = ...``."""
    return source.split(" = ", 1)[1].strip()


def emitted(value: float) -> str:
    module = ast.Module([ast.Assign([ast.Name("x", ast.Store())], number_expr(value))], [])
    return written(format_module(ast.fix_missing_locations(module)))


def test_a_written_number_is_the_float_it_stands_for() -> None:
    number = evaluate("pi/8")
    assert isinstance(number, WrittenNumber) and isinstance(number, float)
    assert number == math.pi / 8 and hash(number) == hash(math.pi / 8)
    assert repr(number) == repr(math.pi / 8) and number.text == "pi/8"
    assert type(number * 2) is float
    for clone in (pickle.loads(pickle.dumps(number)), copy.deepcopy(number)):
        assert clone == number and clone.text == "pi/8"


@pytest.mark.parametrize(
    ("text", "code"),
    [
        ("pi/8", "np.pi / 8"),
        ("-5*pi/8", "-5 * np.pi / 8"),
        ("-pi*5/8", "-np.pi * 5 / 8"),
        ("3*pi/4", "3 * np.pi / 4"),
        ("tau/4", "2 * np.pi / 4"),
        ("1/tau", "1 / (2 * np.pi)"),
        ("pi**2", "np.pi**2"),
        ("-pi**2", "-(np.pi**2)"),
        ("(pi/8)", "np.pi / 8"),
        ("e", "np.e"),
        ("1e3", "1e3"),
        ("1E-3", "1e-3"),
        (".5", "0.5"),
        ("100", "100"),
    ],
)
def test_arithmetic_is_written_as_the_spec_wrote_it(text: str, code: str) -> None:
    assert emitted(evaluate(text)) == code


def test_text_that_python_computes_differently_is_written_as_its_value() -> None:
    # integer arithmetic is exact where the model's float arithmetic rounds 2**53 + 1 down
    number = evaluate("(2**53+1)*3")
    assert eval("(2**53 + 1) * 3") != number
    assert emitted(number) == "2.7021597764222976e16"  # the float, as ruff writes it


@settings(max_examples=max(int(300 * FUZZ_SCALE), 20), deadline=None)
@given(
    st.recursive(
        st.one_of(
            st.sampled_from(["pi", "tau", "e"]),
            st.integers(0, 10**6).map(str),
            st.floats(0, 1e6, allow_nan=False).map(repr),
            st.sampled_from(["1e3", "2.5E-2", ".25", "7."]),
        ),
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from("+-*/"), inner).map(lambda p: f"({p[0]}{p[1]}{p[2]})"),
            st.tuples(inner, st.integers(0, 5)).map(lambda p: f"({p[0]})**{p[1]}"),
            inner.map(lambda text: f"-{text}"),
        ),
        max_leaves=6,
    )
)
def test_generated_code_computes_exactly_the_validated_number(text: str) -> None:
    try:
        number = evaluate(text)
    except ExpressionError:
        return  # division by zero, overflow: the model refuses the spec
    computed = eval(emitted(number), {"np": NUMPY})
    assert repr(float(computed)) == repr(number)


@pytest.mark.parametrize(
    ("text", "fmt", "path"),
    [
        ("x: 1e3\n", "yaml", ("x",)),
        ("x: [0.5, -.25, 1_000.5]\n", "yaml", ("x", 2)),
        ("x: {y: +2.50}\n", "yaml", ("x", "y")),
        ("x = 1e3\n", "toml", ("x",)),
        ("x = [0.5, -0.25, 1_000.5]\n", "toml", ("x", 2)),
        ("[x]\ny = +2.50\n", "toml", ("x", "y")),
    ],
)
def test_the_loader_keeps_the_text_of_a_float(text: str, fmt: str, path: tuple) -> None:
    loaded, problems = parse_spec_bytes(text.encode(), "spec", fmt)
    assert loaded is not None, problems
    value = loaded.data
    for key in path:
        value = value[key]
    assert isinstance(value, WrittenNumber), value
    assert float(value.text.replace("_", "")) == value


def test_an_anchored_float_and_its_aliases_keep_the_anchors_text() -> None:
    loaded, _ = parse_spec_bytes(b"a: &gain !!float 1e3\nb: *gain\n", "spec", "yaml")
    assert loaded is not None
    assert loaded.data["a"].text == loaded.data["b"].text == "1e3"


def test_a_float_whose_text_is_not_where_the_source_map_says_is_a_plain_float() -> None:
    # a key merged in with `<<` is placed at its mapping: no number is written there
    loaded, _ = parse_spec_bytes(b"base: &base {k: 2.5}\nx:\n  <<: *base\n", "spec", "yaml")
    assert loaded is not None
    assert loaded.data["base"]["k"].text == "2.5"
    assert type(loaded.data["x"]["k"]) is float and loaded.data["x"]["k"] == 2.5


def test_the_spec_s_numbers_reach_the_module_as_written(tmp_path: Path) -> None:
    spec = tmp_path / "written.yaml"
    spec.write_text(SPEC.format(qpos="[0, pi/8, 0, -5*pi/8, 0, 3*pi/4, pi/4, 0.04, 0.04]"))
    result = compile_spec(spec)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    source = emit_module(result.robot, tmp_path)
    assert "[0, np.pi / 8, 0, -5 * np.pi / 8, 0, 3 * np.pi / 4, np.pi / 4, 0.04, 0.04]" in source
    assert "arm_stiffness = 1e3\n" in source and "arm_damping = 1e2\n" in source
    assert "arm_force_limit = 100\n" in source
    assert "lower=-np.pi," in source and "lower=-0.1," in source
    assert "stiffness=1e3," in source  # the gripper's own, written as the spec wrote it


def test_an_array_of_integers_stays_a_float_array(tmp_path: Path) -> None:
    spec = tmp_path / "zeros.yaml"
    spec.write_text(SPEC.format(qpos="[0, 0, 0, -2, 0, 2, 1, 0, 0]"))
    result = compile_spec(spec)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    source = emit_module(result.robot, tmp_path)
    # numpy would make an integer array of [0, 0, ...]: the keyframe stays float64
    assert "qpos=np.array([0.0, 0.0, 0.0, -2.0, 0.0, 2.0, 1.0, 0.0, 0.0])" in source
