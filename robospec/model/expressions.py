"""Safe arithmetic for numbers written as text, e.g. ``-5*pi/8`` or ``1e3``.

The text is parsed with :mod:`ast` and only numeric literals, ``pi``/``tau``/``e``, unary
``+``/``-`` and the binary operators ``+ - * / **`` are accepted; nothing is ever evaluated as
Python. Exponents are bounded so ``9**9**9`` cannot hang the compiler.
"""

from __future__ import annotations

import ast
import math
import operator
from collections.abc import Callable

from robospec.load.source_map import WrittenNumber

CONSTANTS: dict[str, float] = {"pi": math.pi, "tau": math.tau, "e": math.e}
MAX_LENGTH = 200
MAX_EXPONENT = 64.0

_BINARY: dict[type[ast.operator], Callable[[float, float], float]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_UNARY: dict[type[ast.unaryop], Callable[[float], float]] = {
    ast.UAdd: operator.pos,
    ast.USub: operator.neg,
}


class ExpressionError(ValueError):
    """The text is not safe arithmetic over numbers and pi."""


def evaluate(text: str) -> float:
    """The value of ``text``, a :class:`WrittenNumber` that keeps ``text``."""
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"expression longer than {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError:
        raise ExpressionError(f"'{text}' is not a number or arithmetic over pi") from None
    value = _eval(tree.body, text)
    if not math.isfinite(value):
        raise ExpressionError(f"'{text}' is not a finite number")
    return WrittenNumber(value, text.strip())


def _eval(node: ast.AST, text: str) -> float:
    value = node.value if isinstance(node, ast.Constant) else None
    if isinstance(value, (int, float)) and not isinstance(value, bool):  # 1 and 1.0, not True
        return float(value)
    if isinstance(node, ast.Name) and node.id in CONSTANTS:
        return CONSTANTS[node.id]
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_eval(node.operand, text))
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left, right = _eval(node.left, text), _eval(node.right, text)
        if isinstance(node.op, ast.Pow) and abs(right) > MAX_EXPONENT:
            raise ExpressionError(f"exponent {right:g} in '{text}' is too large")
        try:
            return _BINARY[type(node.op)](left, right)
        except ZeroDivisionError:
            raise ExpressionError(f"division by zero in '{text}'") from None
        except OverflowError:
            raise ExpressionError(f"'{text}' overflows") from None
    if isinstance(node, ast.Name):
        known = ", ".join(sorted(CONSTANTS))
        raise ExpressionError(f"unknown name '{node.id}' in '{text}' (known: {known})")
    raise ExpressionError(f"'{text}' is not a number or arithmetic over pi")
