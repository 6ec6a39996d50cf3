"""Expressions as documents, following the rules of ruff's Python formatter.

Each function here mirrors one of ``ruff_python_formatter``'s: calls, subscripts and
collections break inside their brackets (one item per line, with a trailing comma, when the
items do not fit on one indented line); binary expressions break before operators of the lowest
precedence inside parentheses; an expression that ends a statement gets parentheses of its own
only when that is the best way to fit it. The "node level" says whether an expression sits
directly in a statement, under optional parentheses (with their group), or inside brackets,
as ruff's does. Only the expressions the emitter writes are covered; anything else is an error.

Parentheses are those Python's grammar needs (as :func:`ast.unparse` writes them): they play
the part of ruff's "parenthesized in the source".
"""

from __future__ import annotations

import ast
import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

from robospec.emit.layout.analysis import (
    ALWAYS_NEEDS,
    BEST_FIT,
    BINARY_OPERATORS,
    COMPARATORS,
    DEFAULT,
    FLUENT,
    MULTILINE,
    NON_FLUENT,
    UNARY_OPERATORS,
    call_chain_layout,
    can_omit_optional_parentheses,
    is_base_ten_number,
    is_simple,
    is_simple_power_operand,
    needs_parentheses,
    operator_precedence,
)
from robospec.emit.layout.document import (
    EXPANDED,
    FLAT,
    SOFT_LINE,
    SOFT_LINE_OR_SPACE,
    SPACE,
    BestFitParenthesize,
    ConditionalGroup,
    Doc,
    FitsExpanded,
    Group,
    IndentIfGroupBreaks,
    Text,
    concat,
    if_group_breaks,
    if_group_fits_on_line,
    soft_block_indent,
)
from robospec.emit.layout.literals import constant_text, fstring_text

# node levels (ruff's NodeLevel): a statement, an expression (optionally under the optional
# parentheses of group ``id``), or inside parentheses/brackets
TOP_LEVEL, COMPOUND, EXPRESSION, PARENTHESIZED = "top", "compound", "expression", "paren"
Level = tuple[str, "int | None"]

# how an expression is parenthesized when it is formatted (ruff's Parentheses)
PRESERVE, ALWAYS, NEVER = "preserve", "always", "never"
# what the statement asks for (ruff's Parenthesize)
OPTIONAL, IF_BREAKS, IF_REQUIRED = "optional", "if_breaks", "if_required"


@dataclass
class ExpressionLayout:
    """Turns expressions into documents; holds the node level and numbers the groups."""

    parenthesized: set[int]  # id() of every expression written in parentheses
    level: Level = (TOP_LEVEL, None)
    _ids: itertools.count[int] = field(default_factory=lambda: itertools.count(1))

    def group_id(self) -> int:
        return next(self._ids)

    def at_level(self, level: Level, build: Callable[[], Doc]) -> Doc:
        saved, self.level = self.level, level
        try:
            return build()
        finally:
            self.level = saved

    def is_parenthesized(self, node: ast.expr) -> bool:
        return id(node) in self.parenthesized

    # -- ruff's builders --------------------------------------------------------------------

    def brackets(self, left: str, build: Callable[[], Doc], right: str) -> Doc:
        """ruff's ``parenthesized``: the content breaks onto its own indented lines."""
        current = self.level
        content = self.at_level((PARENTHESIZED, None), build)
        indented: Doc = Group(soft_block_indent(content))
        if current[0] == EXPRESSION and current[1] is not None:
            indented = FitsExpanded(indented, (FLAT, current[1]))
        return concat(Text(left), indented, Text(right))

    def optional_parentheses(self, build: Callable[[], Doc]) -> Doc:
        group_id = self.group_id()
        content = self.at_level((EXPRESSION, group_id), build)
        return Group(
            concat(
                if_group_breaks(Text("(")),
                IndentIfGroupBreaks(concat(SOFT_LINE, content), group_id),
                SOFT_LINE,
                if_group_breaks(Text(")")),
            ),
            group_id,
        )

    def parenthesize_if_expands(self, build: Callable[[], Doc]) -> Doc:
        def layout() -> Doc:
            group_id = self.group_id()
            return Group(
                concat(
                    if_group_breaks(Text("(")),
                    IndentIfGroupBreaks(concat(SOFT_LINE, build()), group_id),
                    SOFT_LINE,
                    if_group_breaks(Text(")")),
                ),
                group_id,
            )

        return self.at_level((PARENTHESIZED, None), layout)

    def best_fit_parenthesize(self, build: Callable[[], Doc]) -> Doc:
        group_id = self.group_id()
        return BestFitParenthesize(self.at_level((EXPRESSION, group_id), build), group_id)

    def soft_line_break(self, or_space: bool) -> Doc:
        """ruff's ``in_parentheses_only_soft_line_break(_or_space)``."""
        kind, group_id = self.level
        if kind == PARENTHESIZED:
            return SOFT_LINE_OR_SPACE if or_space else SOFT_LINE
        if kind == EXPRESSION and group_id is not None:
            if not or_space:
                return if_group_breaks(SOFT_LINE, group_id)
            return concat(
                if_group_breaks(SOFT_LINE_OR_SPACE, group_id),
                if_group_fits_on_line(SPACE, group_id),
            )
        return SPACE if or_space else concat()

    def in_parentheses_only_group(self, content: Doc) -> Doc:
        kind, group_id = self.level
        if kind == EXPRESSION and group_id is not None:
            return ConditionalGroup(content, EXPANDED, group_id)
        if kind == PARENTHESIZED:
            return Group(content)
        return content

    def in_parentheses_only_if_group_breaks(self, content: Doc) -> Doc:
        kind, group_id = self.level
        if kind == EXPRESSION and group_id is not None:
            return if_group_breaks(content, group_id)
        if kind == PARENTHESIZED:
            return if_group_breaks(content)
        return concat()

    def comma_separated(self, items: list[Doc], *, one_or_more: bool = False) -> Doc:
        """Items joined by ``,`` and a soft line break; a trailing comma when the group breaks
        (for one item only with ``one_or_more``)."""
        parts: list[Doc] = []
        for index, item in enumerate(items):
            if index:
                parts += [Text(","), SOFT_LINE_OR_SPACE]
            parts.append(item)
        if items and (len(items) > 1 or one_or_more):
            parts.append(if_group_breaks(Text(",")))
        return concat(*parts)

    # -- expressions ------------------------------------------------------------------------

    def expression(self, node: ast.expr, parentheses: str = PRESERVE) -> Doc:
        """ruff's ``FormatExpr``."""
        if parentheses == ALWAYS or (parentheses == PRESERVE and self.is_parenthesized(node)):
            return self.brackets("(", lambda: self.fields(node), ")")
        if self.level[0] in (TOP_LEVEL, COMPOUND):
            return self.at_level((EXPRESSION, None), lambda: self.fields(node))
        return self.fields(node)

    def fields(self, node: ast.expr, chain: str = DEFAULT) -> Doc:
        if isinstance(node, ast.Name):
            return Text(node.id)
        if isinstance(node, ast.Constant):
            return Text(constant_text(node))
        if isinstance(node, ast.JoinedStr):
            return Text(fstring_text(node))
        if isinstance(node, ast.Attribute):
            return self.attribute(node, chain)
        if isinstance(node, ast.Call):
            return self.call(node, chain)
        if isinstance(node, ast.Subscript):
            return self.subscript(node, chain)
        if isinstance(node, ast.List):
            return self.sequence("[", node.elts, "]")
        if isinstance(node, ast.Tuple):
            if len(node.elts) == 1:
                return self.brackets(
                    "(", lambda: concat(self.expression(node.elts[0]), Text(",")), ")"
                )
            return self.sequence("(", node.elts, ")")
        if isinstance(node, ast.Dict):
            return self.dictionary(node)
        if isinstance(node, (ast.ListComp, ast.DictComp)):
            return self.comprehension(node)
        if isinstance(node, (ast.BinOp, ast.Compare, ast.BoolOp)):
            return self.binary_like(node)
        if isinstance(node, ast.UnaryOp):
            operand = node.operand
            pow_operand = isinstance(operand, ast.BinOp) and isinstance(operand.op, ast.Pow)
            operator = Text(UNARY_OPERATORS[type(node.op)])
            return concat(operator, self.expression(operand, ALWAYS if pow_operand else PRESERVE))
        if isinstance(node, ast.Slice):
            return self.slice(node)
        if isinstance(node, ast.Starred):
            return concat(Text("*"), self.expression(node.value))
        raise TypeError(f"the emitter does not write {type(node).__name__} expressions")

    def sequence(self, left: str, elements: list[ast.expr], right: str) -> Doc:
        if not elements:
            return Text(left + right)
        return self.brackets(
            left,
            lambda: self.comma_separated([self.expression(e) for e in elements]),
            right,
        )

    def dictionary(self, node: ast.Dict) -> Doc:
        if not node.keys:
            return Text("{}")

        def pairs() -> Doc:
            items: list[Doc] = []
            for key, value in zip(node.keys, node.values, strict=True):
                if key is None:
                    raise TypeError("the emitter does not write ** in dict displays")
                items.append(
                    Group(concat(self.expression(key), Text(":"), SPACE, self.expression(value)))
                )
            return self.comma_separated(items)

        return self.brackets("{", pairs, "}")

    def comprehension(self, node: ast.ListComp | ast.DictComp) -> Doc:
        def generators() -> list[Doc]:
            docs: list[Doc] = []
            for index, generator in enumerate(node.generators):
                if generator.ifs or generator.is_async:
                    raise TypeError("the emitter writes plain comprehensions only")
                if index:
                    docs.append(SOFT_LINE_OR_SPACE)
                docs.append(
                    concat(
                        Text("for "),
                        self.expression(generator.target),
                        Text(" in "),
                        self.expression(generator.iter),
                    )
                )
            return docs

        def content() -> Doc:
            element: Doc
            if isinstance(node, ast.DictComp):
                key = concat(Group(self.expression(node.key)), Text(":"), SPACE)
                element = concat(key, self.expression(node.value))
            else:
                element = Group(self.expression(node.elt))
            return Group(concat(element, SOFT_LINE_OR_SPACE, *generators()))

        left, right = ("{", "}") if isinstance(node, ast.DictComp) else ("[", "]")
        return self.brackets(left, content, right)

    def slice(self, node: ast.Slice) -> Doc:
        parts = (node.lower, node.upper, node.step)
        if not all(part is None or is_simple(part) for part in parts):
            raise TypeError("the emitter writes slices of names and numbers only")
        docs: list[Doc] = []
        if node.lower is not None:
            docs.append(self.expression(node.lower))
        docs.append(Text(":"))
        if node.upper is not None:
            docs.append(self.expression(node.upper))
        if node.step is not None:
            docs += [Text(":"), self.expression(node.step)]
        return concat(*docs)

    # -- calls, attributes, subscripts --------------------------------------------------------

    def chain_layout(self, node: ast.expr, chain: str) -> str:
        """ruff's ``CallChainLayout::apply_in_node``."""
        if chain != DEFAULT:
            return chain
        if self.level[0] == PARENTHESIZED or (
            self.level[0] == EXPRESSION and self.level[1] is not None
        ):
            return call_chain_layout(node, self.is_parenthesized)
        return NON_FLUENT

    def chain_value(self, value: ast.expr, layout: str) -> Doc:
        """The value of a call, attribute or subscript, continuing the chain's layout."""
        if self.is_parenthesized(value):
            return self.expression(value, ALWAYS)
        if isinstance(value, ast.Attribute):
            return self.attribute(value, layout)
        if isinstance(value, ast.Call):
            return self.call(value, layout)
        if isinstance(value, ast.Subscript):
            return self.subscript(value, layout)
        return self.expression(value, NEVER)

    def call(self, node: ast.Call, chain: str = DEFAULT) -> Doc:
        layout = self.chain_layout(node, chain)
        doc = concat(self.chain_value(node.func, layout), self.arguments(node))
        return Group(doc) if layout == FLUENT and chain == DEFAULT else doc

    def arguments(self, node: ast.Call) -> Doc:
        if not node.args and not node.keywords:
            return Text("()")

        def all_arguments() -> Doc:
            if len(node.args) == 1 and not node.keywords:
                entries = [self.expression(node.args[0], NEVER)]
            else:
                entries = [self.expression(arg) for arg in node.args]
                for keyword in node.keywords:
                    if keyword.arg is None:
                        raise TypeError("the emitter does not write ** arguments")
                    entries.append(concat(Text(keyword.arg + "="), self.expression(keyword.value)))
            return Group(self.comma_separated(entries))

        return self.brackets("(", all_arguments, ")")

    def attribute(self, node: ast.Attribute, chain: str = DEFAULT) -> Doc:
        layout = self.chain_layout(node, chain)
        value = node.value
        parenthesize_value = is_base_ten_number(value) or self.is_parenthesized(value)
        if layout == FLUENT and not parenthesize_value:
            value_doc = self.chain_value(value, layout)
        else:
            value_doc = self.expression(value, ALWAYS if parenthesize_value else NEVER)
        parts = [value_doc]
        if layout == FLUENT and (
            parenthesize_value or isinstance(value, (ast.Call, ast.Subscript))
        ):
            parts.append(SOFT_LINE)
        parts.append(Text("." + node.attr))
        doc = concat(*parts)
        return Group(doc) if layout == FLUENT and chain == DEFAULT else doc

    def subscript(self, node: ast.Subscript, chain: str = DEFAULT) -> Doc:
        layout = self.chain_layout(node, chain)
        value_doc = self.chain_value(node.value, layout)

        def index() -> Doc:
            key = node.slice
            if isinstance(key, ast.Tuple) and not self.is_parenthesized(key):
                if len(key.elts) == 1:
                    raise TypeError("the emitter does not write one-element tuple indices")
                return Group(self.comma_separated([self.expression(e) for e in key.elts]))
            return self.expression(key)

        doc = concat(value_doc, self.brackets("[", index, "]"))
        return Group(doc) if layout == FLUENT and chain == DEFAULT else doc

    # -- binary expressions (ruff's BinaryLike) -----------------------------------------------

    def binary_like(self, node: ast.BinOp | ast.Compare | ast.BoolOp) -> Doc:
        parts: list[ast.expr | str] = []
        self._flatten(node, parts)
        return self.in_parentheses_only_group(self._binary_slice(parts))

    def _flatten(self, node: ast.expr, parts: list[ast.expr | str]) -> None:
        """Operands and operator texts of a chain of operations not written in parentheses."""
        if isinstance(node, ast.BinOp):
            self._operand(node.left, parts)
            parts.append(BINARY_OPERATORS[type(node.op)][0])
            self._operand(node.right, parts)
        elif isinstance(node, ast.Compare):
            self._operand(node.left, parts)
            for operator, comparator in zip(node.ops, node.comparators, strict=True):
                parts.append(COMPARATORS[type(operator)])
                self._operand(comparator, parts)
        else:
            assert isinstance(node, ast.BoolOp)
            word = "and" if isinstance(node.op, ast.And) else "or"
            for index, value in enumerate(node.values):
                if index:
                    parts.append(word)
                self._operand(value, parts)

    def _operand(self, node: ast.expr, parts: list[ast.expr | str]) -> None:
        chained = isinstance(node, (ast.BinOp, ast.Compare, ast.BoolOp))
        if chained and not self.is_parenthesized(node):
            self._flatten(node, parts)
        else:
            parts.append(node)

    def _binary_slice(self, parts: list[ast.expr | str]) -> Doc:
        if len(parts) == 1:
            return self._operand_doc(parts[0])
        lowest = max(operator_precedence(p) for p in parts[1::2])
        docs: list[Doc] = []
        start = 0
        for index in range(1, len(parts), 2):
            operator = parts[index]
            assert isinstance(operator, str)
            if operator_precedence(operator) != lowest:
                continue
            left, right = parts[start:index], parts[index + 1 :]
            is_pow = operator == "**" and _is_simple_power(left[-1], right[0], self)
            docs.append(self._side(left))
            docs.append(self.soft_line_break(not is_pow))
            docs.append(Text(operator))
            docs.append(self.in_parentheses_only_if_group_breaks(SPACE) if is_pow else SPACE)
            start = index + 1
        docs.append(self._side(parts[start:]))
        return concat(*docs)

    def _side(self, parts: list[ast.expr | str]) -> Doc:
        if len(parts) == 1:
            return self._operand_doc(parts[0])
        return self.in_parentheses_only_group(self._binary_slice(parts))

    def _operand_doc(self, part: ast.expr | str) -> Doc:
        assert isinstance(part, ast.expr)
        return self.expression(part, ALWAYS if self.is_parenthesized(part) else NEVER)

    # -- parentheses around whole expressions -------------------------------------------------

    def maybe_parenthesize(self, node: ast.expr, parenthesize: str) -> Doc:
        """ruff's ``maybe_parenthesize_expression``."""
        if parenthesize == OPTIONAL and self.is_parenthesized(node):
            return self.expression(node, ALWAYS)
        needs = needs_parentheses(node, self.is_parenthesized)
        in_parentheses = self.level[0] == PARENTHESIZED or (
            self.level[0] == EXPRESSION and self.level[1] is not None
        )
        if needs != ALWAYS_NEEDS and in_parentheses:
            return self.expression(node, NEVER)

        def unparenthesized() -> Doc:
            return self.expression(node, NEVER)

        if needs == MULTILINE:
            if parenthesize == IF_REQUIRED:
                return unparenthesized()
            if can_omit_optional_parentheses(node, self.is_parenthesized):
                return self.optional_parentheses(unparenthesized)
            return self.parenthesize_if_expands(unparenthesized)
        if needs == BEST_FIT:
            if parenthesize == IF_BREAKS:
                return self.best_fit_parenthesize(unparenthesized)
            return unparenthesized()
        if needs == ALWAYS_NEEDS:
            return self.expression(node, ALWAYS)
        return unparenthesized()


def _is_simple_power(left: ast.expr | str, right: ast.expr | str, layout: ExpressionLayout) -> bool:
    """Both operands of ``**`` are names, numbers or attribute chains: no spaces (``x**2``)."""
    assert isinstance(left, ast.expr) and isinstance(right, ast.expr)
    return (
        is_simple_power_operand(left)
        and is_simple_power_operand(right)
        and not layout.is_parenthesized(left)
        and not layout.is_parenthesized(right)
    )
