from __future__ import annotations

import math

import pytest

from robospec.model.expressions import ExpressionError, evaluate


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("pi/8", math.pi / 8),
        ("-pi*5/8", -math.pi * 5 / 8),
        ("3*pi/4", 3 * math.pi / 4),
        ("1e3", 1000.0),
        ("2**3", 8.0),
        ("-(1 + 2)", -3.0),
        ("tau", math.tau),
    ],
)
def test_arithmetic_over_pi_evaluates_like_python(text: str, value: float) -> None:
    assert evaluate(text) == value


@pytest.mark.parametrize(
    "text",
    [
        "__import__('os')",
        "pi.real",
        "open('x')",
        "[1]",
        "1 if 1 else 2",
        "x",
        "9**9**9",
        "1/0",
        "lambda: 1",
        "'a'",
        "1e400",
        "a" * 300,
    ],
)
def test_anything_but_arithmetic_is_rejected_without_evaluation(text: str) -> None:
    with pytest.raises(ExpressionError):
        evaluate(text)
