"""What ruff's formatter asks of an expression before laying it out: what it needs around it
to break over lines, whether a call chain is "fluent", whether its own brackets can break
instead of optional parentheses (ruff's ``NeedsParentheses``, ``CallChainLayout``,
``can_omit_optional_parentheses``), and how operators rank when they split.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass
from enum import IntEnum

from robospec.emit.layout.literals import number_text

# what an expression needs around it to break over lines (ruff's OptionalParentheses)
MULTILINE, BEST_FIT, NEVER_NEEDS, ALWAYS_NEEDS = "multiline", "best_fit", "never", "always"
# call chains (ruff's CallChainLayout): fluent chains break before each `.attribute`
DEFAULT, FLUENT, NON_FLUENT = "default", "fluent", "non_fluent"


class Precedence(IntEnum):
    """ruff's OperatorPrecedence: the order in which operators split (lowest binds last)."""

    NONE = 0
    ATTRIBUTE = 1
    EXPONENTIAL = 2
    BITWISE_INVERSION = 3
    MULTIPLICATIVE = 4
    ADDITIVE = 5
    SHIFT = 6
    BITWISE_AND = 7
    BITWISE_XOR = 8
    BITWISE_OR = 9
    COMPARATOR = 10
    BOOLEAN = 11


BINARY_OPERATORS: dict[type[ast.operator], tuple[str, Precedence]] = {
    ast.Add: ("+", Precedence.ADDITIVE),
    ast.Sub: ("-", Precedence.ADDITIVE),
    ast.Mult: ("*", Precedence.MULTIPLICATIVE),
    ast.MatMult: ("@", Precedence.MULTIPLICATIVE),
    ast.Div: ("/", Precedence.MULTIPLICATIVE),
    ast.FloorDiv: ("//", Precedence.MULTIPLICATIVE),
    ast.Mod: ("%", Precedence.MULTIPLICATIVE),
    ast.Pow: ("**", Precedence.EXPONENTIAL),
    ast.LShift: ("<<", Precedence.SHIFT),
    ast.RShift: (">>", Precedence.SHIFT),
    ast.BitAnd: ("&", Precedence.BITWISE_AND),
    ast.BitXor: ("^", Precedence.BITWISE_XOR),
    ast.BitOr: ("|", Precedence.BITWISE_OR),
}
COMPARATORS: dict[type[ast.cmpop], str] = {
    ast.Eq: "==",
    ast.NotEq: "!=",
    ast.Lt: "<",
    ast.LtE: "<=",
    ast.Gt: ">",
    ast.GtE: ">=",
    ast.Is: "is",
    ast.IsNot: "is not",
    ast.In: "in",
    ast.NotIn: "not in",
}
UNARY_OPERATORS: dict[type[ast.unaryop], str] = {
    ast.USub: "-",
    ast.UAdd: "+",
    ast.Invert: "~",
    ast.Not: "not ",
}


IsParenthesized = Callable[[ast.expr], bool]


def needs_parentheses(node: ast.expr, parenthesized: IsParenthesized) -> str:
    """ruff's ``NeedsParentheses``: what an expression needs to break over lines."""
    if isinstance(node, (ast.Name, ast.Constant, ast.JoinedStr)):
        return BEST_FIT
    if isinstance(node, (ast.List, ast.Tuple, ast.Dict, ast.ListComp, ast.DictComp)):
        return NEVER_NEEDS
    if isinstance(node, (ast.BinOp, ast.Compare, ast.BoolOp, ast.Slice)):
        return MULTILINE
    if isinstance(node, ast.Starred):
        return needs_parentheses(node.value, parenthesized)
    if isinstance(node, ast.UnaryOp):
        if parenthesized(node.operand):
            return NEVER_NEEDS
        return needs_parentheses(node.operand, parenthesized)
    if isinstance(node, (ast.Call, ast.Attribute, ast.Subscript)):
        if call_chain_layout(node, parenthesized) == FLUENT:
            return MULTILINE
        inner = node.func if isinstance(node, ast.Call) else node.value
        if parenthesized(inner):
            return NEVER_NEEDS
        return needs_parentheses(inner, parenthesized)
    raise TypeError(f"the emitter does not write {type(node).__name__} expressions")


def call_chain_layout(node: ast.expr, parenthesized: IsParenthesized) -> str:
    """Fluent when at least two attribute values in the chain are calls or subscripts."""
    count = 0
    while True:
        if isinstance(node, ast.Attribute):
            if parenthesized(node.value):
                count += 1  # a parenthesized root counts as a call
                break
            if isinstance(node.value, (ast.Call, ast.Subscript)):
                count += 1
            node = node.value
        elif isinstance(node, (ast.Call, ast.Subscript)):
            inner = node.func if isinstance(node, ast.Call) else node.value
            if parenthesized(inner):
                break
            node = inner
        else:
            break
    return FLUENT if count >= 2 else NON_FLUENT


def has_own_parentheses(node: ast.expr) -> str | None:
    """``"non_empty"``/``"empty"`` for an expression with brackets of its own, else None."""
    if isinstance(node, (ast.ListComp, ast.DictComp, ast.Subscript)):
        return "non_empty"
    if isinstance(node, ast.List):
        return "non_empty" if node.elts else "empty"
    if isinstance(node, ast.Dict):
        return "non_empty" if node.keys else "empty"
    if isinstance(node, ast.Call):
        return "non_empty" if node.args or node.keywords else "empty"
    return None


def has_parentheses(node: ast.expr, parenthesized: IsParenthesized) -> str | None:
    own = has_own_parentheses(node)
    if own == "non_empty":
        return own
    if parenthesized(node):
        return "non_empty"
    return own


@dataclass
class _CanOmitVisitor:
    parenthesized: IsParenthesized
    max_precedence: Precedence = Precedence.NONE
    max_precedence_count: int = 0
    any_parenthesized: bool = False
    last: ast.expr | None = None
    first: ast.expr | str | None = None  # an expression, or "token" (`-x`, `not x`)

    def update(self, precedence: Precedence, count: int = 1) -> None:
        if precedence > self.max_precedence:
            self.max_precedence, self.max_precedence_count = precedence, count
        elif precedence == self.max_precedence:
            self.max_precedence_count += count

    def visit(self, node: ast.expr) -> None:
        self.last = node
        if self.parenthesized(node):
            self.any_parenthesized = True
        else:
            self.visit_subexpression(node)
        if self.first is None:
            self.first = node

    def visit_subexpression(self, node: ast.expr) -> None:
        if isinstance(node, (ast.List, ast.Dict, ast.ListComp, ast.DictComp)):
            self.any_parenthesized = True
            return
        if isinstance(node, ast.BoolOp):
            self.update(Precedence.BOOLEAN, len(node.values) - 1)
        elif isinstance(node, ast.BinOp):
            self.update(BINARY_OPERATORS[type(node.op)][1])
        elif isinstance(node, ast.Compare):
            self.update(Precedence.COMPARATOR, len(node.ops))
        elif isinstance(node, ast.Call):
            self.any_parenthesized = True
            self.visit(node.func)
            self.last = node
            return
        elif isinstance(node, ast.Subscript):
            self.any_parenthesized = True
            self.visit(node.value)
            self.last = node
            return
        elif isinstance(node, ast.Attribute):
            self.visit(node.value)
            if has_parentheses(node.value, self.parenthesized) is not None:
                self.update(Precedence.ATTRIBUTE)
            self.last = node
            return
        elif isinstance(node, ast.UnaryOp):
            if isinstance(node.op, ast.Invert):
                self.update(Precedence.BITWISE_INVERSION)
            if self.first is None:
                self.first = "token"
        elif isinstance(node, (ast.Name, ast.Constant, ast.JoinedStr, ast.Slice)):
            return
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.expr):
                self.visit(child)


def can_omit_optional_parentheses(node: ast.expr, parenthesized: IsParenthesized) -> bool:
    """ruff's ``can_omit_optional_parentheses`` (after black's
    ``_maybe_split_omitting_optional_parens``): break the expression's own last (or first)
    brackets instead of wrapping it in parentheses."""
    visitor = _CanOmitVisitor(parenthesized)
    visitor.visit_subexpression(node)
    if not visitor.any_parenthesized or visitor.max_precedence_count > 1:
        return False
    if visitor.max_precedence in (Precedence.NONE, Precedence.ATTRIBUTE):
        return True

    def breaks_brackets(candidate: ast.expr | str | None) -> bool:
        return (
            isinstance(candidate, ast.expr)
            and not isinstance(candidate, ast.Subscript)
            and has_parentheses(candidate, parenthesized) == "non_empty"
        )

    return breaks_brackets(visitor.last) or breaks_brackets(visitor.first)


def operator_precedence(operator: ast.expr | str) -> Precedence:
    assert isinstance(operator, str)
    if operator in ("and", "or"):
        return Precedence.BOOLEAN
    for text, precedence in BINARY_OPERATORS.values():
        if text == operator:
            return precedence
    return Precedence.COMPARATOR


def is_simple_power_operand(node: ast.expr) -> bool:
    if isinstance(node, ast.UnaryOp):
        return not isinstance(node.op, ast.Not) and is_simple_power_operand(node.operand)
    if isinstance(node, ast.Constant):
        return isinstance(node.value, (int, float, complex)) or node.value is None
    if isinstance(node, ast.Attribute):
        return is_simple_power_operand(node.value)
    return isinstance(node, ast.Name)


def is_simple(node: ast.expr) -> bool:
    if isinstance(node, ast.UnaryOp) and not isinstance(node.op, ast.Not):
        return is_simple(node.operand)
    return isinstance(node, (ast.Constant, ast.Name))


def is_base_ten_number(node: ast.expr) -> bool:
    if not isinstance(node, ast.Constant) or isinstance(node.value, bool):
        return False
    if isinstance(node.value, float):
        return True
    return isinstance(node.value, int) and not number_text(node).lower().startswith(
        ("0x", "0o", "0b")
    )
