"""Which expressions of a module are written in parentheses.

The emitter builds code as ``ast`` nodes, which hold no parentheses: these are the ones
Python's grammar needs (those :func:`ast.unparse` writes), plus the ones ruff always writes
around a power under a unary operator (``-(x**2)``). The layout treats them as ruff treats
parentheses found in source code.
"""

from __future__ import annotations

import ast
from enum import IntEnum


class _Binding(IntEnum):
    """How tightly an expression binds (the order of ``ast._Precedence``)."""

    TEST = 1
    OR = 2
    AND = 3
    NOT = 4
    COMPARISON = 5
    BITWISE_OR = 6
    BITWISE_XOR = 7
    BITWISE_AND = 8
    SHIFT = 9
    ARITHMETIC = 10
    TERM = 11
    FACTOR = 12
    POWER = 13
    ATOM = 14


_BINARY = {
    ast.BitOr: _Binding.BITWISE_OR,
    ast.BitXor: _Binding.BITWISE_XOR,
    ast.BitAnd: _Binding.BITWISE_AND,
    ast.LShift: _Binding.SHIFT,
    ast.RShift: _Binding.SHIFT,
    ast.Add: _Binding.ARITHMETIC,
    ast.Sub: _Binding.ARITHMETIC,
    ast.Mult: _Binding.TERM,
    ast.MatMult: _Binding.TERM,
    ast.Div: _Binding.TERM,
    ast.FloorDiv: _Binding.TERM,
    ast.Mod: _Binding.TERM,
    ast.Pow: _Binding.POWER,
}


def _binding(node: ast.expr) -> _Binding:
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)]
    if isinstance(node, ast.UnaryOp):
        return _Binding.NOT if isinstance(node.op, ast.Not) else _Binding.FACTOR
    if isinstance(node, ast.Compare):
        return _Binding.COMPARISON
    if isinstance(node, ast.BoolOp):
        return _Binding.AND if isinstance(node.op, ast.And) else _Binding.OR
    return _Binding.ATOM


def parenthesized_expressions(tree: ast.AST) -> set[int]:
    """``id()`` of every expression in ``tree`` that is written in parentheses."""
    found: set[int] = set()
    indices: set[int] = set()  # tuples indexing a subscript, written without parentheses
    tuples: list[ast.Tuple] = []

    def need(node: ast.expr, binding: _Binding) -> None:
        if _binding(node) < binding:
            found.add(id(node))

    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp):
            binding = _BINARY[type(node.op)]
            right_associative = isinstance(node.op, ast.Pow)
            need(node.left, _Binding(binding + 1) if right_associative else binding)
            need(node.right, binding if right_associative else _Binding(binding + 1))
        elif isinstance(node, ast.UnaryOp):
            need(node.operand, _binding(node))
            if isinstance(node.operand, ast.BinOp) and isinstance(node.operand.op, ast.Pow):
                found.add(id(node.operand))
        elif isinstance(node, ast.Compare):
            for operand in (node.left, *node.comparators):
                need(operand, _Binding.BITWISE_OR)
        elif isinstance(node, ast.BoolOp):
            for value in node.values:
                need(value, _Binding(_binding(node) + 1))
        elif isinstance(node, ast.Subscript):
            need(node.value, _Binding.ATOM)
            indices.add(id(node.slice))
        elif isinstance(node, ast.Attribute):
            need(node.value, _Binding.ATOM)
        elif isinstance(node, ast.Call):
            need(node.func, _Binding.ATOM)
        elif isinstance(node, ast.Tuple):
            tuples.append(node)
    found.update(id(node) for node in tuples if id(node) not in indices)
    return found
