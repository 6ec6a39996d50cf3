"""Numbers as the spec wrote them: ``pi/8`` is written ``np.pi / 8``, ``1e3`` stays ``1e3``.

A number the spec wrote as text (arithmetic, or a literal in YAML or TOML) carries that text
(:class:`robospec.model.expressions.WrittenNumber`). It is parsed again with :mod:`ast`
and rebuilt from the same few node kinds the model's safe arithmetic accepts, ``pi`` as
``np.pi``: text never reaches generated code except as number literals the parser read. The
rebuilt expression is used only when Python computes from it exactly the value the spec
validated to (integer arithmetic can differ from the model's float arithmetic, ``3**40`` say);
otherwise, and for numbers without text, the value is written as Python writes the float.
"""

from __future__ import annotations

import ast
import math
import operator
from collections.abc import Callable
from typing import Any

from robospec.model.expressions import MAX_LENGTH

_BINARY: dict[type[ast.operator], Callable[[Any, Any], Any]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_UNARY: dict[type[ast.unaryop], Callable[[Any], Any]] = {
    ast.UAdd: operator.pos,
    ast.USub: operator.neg,
}
# the model's constants, as numpy names them; numpy has no tau: it is written 2 * np.pi
_CONSTANTS = {"pi": ("pi", math.pi), "e": ("e", math.e)}
# an unbounded limit, written as ManiSkill's own agents write it
_INFINITY = ("inf", math.inf)


def number_expr(value: float) -> ast.expr:
    """``value`` as the spec wrote it, if it has text that gives exactly it; else its repr;
    an infinite bound as ``np.inf`` or ``-np.inf``."""
    if math.isinf(value):
        inf = ast.Attribute(ast.Name("np", ast.Load()), _INFINITY[0], ast.Load())
        return inf if value > 0 else ast.UnaryOp(ast.USub(), inf)
    text = getattr(value, "text", None)
    if isinstance(text, str) and len(text) <= MAX_LENGTH:
        written = _written(text)
        if written is not None and same_number(python_value(written), value):
            return written
    return literal(value)


def literal(value: float | int) -> ast.expr:
    """A plain literal (``-`` as an operator, as Python writes negative numbers)."""
    if math.copysign(1.0, value) < 0:
        return ast.UnaryOp(ast.USub(), ast.Constant(-value))
    return ast.Constant(value if type(value) in (int, float) else float(value))


def same_number(computed: Any, value: float) -> bool:
    """``computed`` is ``value``: equal, and with the same sign when zero."""
    if isinstance(computed, bool) or not isinstance(computed, (int, float)):
        return False
    try:
        as_float = float(computed)
    except OverflowError:
        return False
    return as_float == value and math.copysign(1.0, as_float) == math.copysign(1.0, value)


def python_value(node: ast.expr) -> Any:
    """What the generated code computes from ``node`` (a number expression from here)."""
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.Attribute):
        return next(v for name, v in (*_CONSTANTS.values(), _INFINITY) if name == node.attr)
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](python_value(node.operand))
    assert isinstance(node, ast.BinOp)
    try:
        return _BINARY[type(node.op)](python_value(node.left), python_value(node.right))
    except (ZeroDivisionError, OverflowError):
        return None


def _written(text: str) -> ast.expr | None:
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError:
        return None
    return _rebuild(tree.body, text.strip())


def _rebuild(node: ast.expr, text: str) -> ast.expr | None:
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        rebuilt = ast.Constant(node.value)
        # the literal as written (`1e3`, not 1000.0); the layout writes it the way ruff does
        rebuilt.text = ast.get_source_segment(text, node)  # type: ignore[attr-defined]
        return rebuilt
    if isinstance(node, ast.Name) and node.id in _CONSTANTS:
        return ast.Attribute(ast.Name("np", ast.Load()), _CONSTANTS[node.id][0], ast.Load())
    if isinstance(node, ast.Name) and node.id == "tau":
        pi = ast.Attribute(ast.Name("np", ast.Load()), "pi", ast.Load())
        return ast.BinOp(ast.Constant(2), ast.Mult(), pi)
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        operand = _rebuild(node.operand, text)
        return None if operand is None else ast.UnaryOp(type(node.op)(), operand)
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left, right = _rebuild(node.left, text), _rebuild(node.right, text)
        if left is None or right is None:
            return None
        return ast.BinOp(left, type(node.op)(), right)
    return None
