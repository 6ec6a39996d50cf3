"""Statements and modules as documents, laid out as ``ruff format`` lays them out.

Blank lines follow ruff's (and isort's) rules: one after the module docstring, between import
sections and after imports (two before a class or a function); two around top-level classes and
functions; one around methods and after a class docstring; none elsewhere.
"""

from __future__ import annotations

import ast
import functools
import textwrap
from collections.abc import Collection

from robospec.emit.layout.analysis import BEST_FIT, needs_parentheses
from robospec.emit.layout.document import (
    EMPTY_LINE,
    HARD_LINE,
    INDENT_WIDTH,
    SOFT_LINE_OR_SPACE,
    BestFitParenthesize,
    Doc,
    Group,
    Indent,
    Text,
    concat,
    if_group_breaks,
    print_document,
    soft_block_indent,
)
from robospec.emit.layout.expressions import (
    COMPOUND,
    IF_BREAKS,
    NEVER,
    OPTIONAL,
    PARENTHESIZED,
    TOP_LEVEL,
    ExpressionLayout,
    Level,
)
from robospec.emit.layout.imports import import_section
from robospec.emit.layout.literals import docstring_lines
from robospec.emit.layout.parentheses import parenthesized_expressions

LINE_LENGTH = 100
# what a suite of statements is the body of: blank lines differ
MODULE, CLASS, FUNCTION, BLOCK = "module", "class", "function", "block"
ARITHMETIC = (ast.BitOr, ast.BitXor, ast.LShift, ast.RShift, ast.Add, ast.Sub)


def format_module(module: ast.Module, paragraphs: Collection[int] = ()) -> str:
    """The module's source, exactly as ``ruff format --line-length 100`` would write it.
    ``paragraphs`` holds the ``id()`` of statements to set off by a blank line (ruff keeps
    one blank line between statements where the source has it)."""
    layout = ExpressionLayout(parenthesized_expressions(module))
    document = _Statements(layout, paragraphs).suite(module.body, MODULE, 0)
    return print_document(concat(document, HARD_LINE), LINE_LENGTH)


class _Statements:
    def __init__(self, layout: ExpressionLayout, paragraphs: Collection[int]) -> None:
        self.layout = layout
        self.paragraphs = paragraphs

    def suite(self, body: list[ast.stmt], kind: str, depth: int) -> Doc:
        level: Level = (TOP_LEVEL, None) if kind == MODULE else (COMPOUND, None)
        docs: list[Doc] = []
        previous: ast.stmt | None = None
        for index, statement in enumerate(body):
            if previous is not None:
                blank_lines = _blank_lines(previous, statement, kind, index == 1)
                if id(statement) in self.paragraphs:
                    blank_lines = max(blank_lines, 1)
                docs.append(HARD_LINE)
                docs += [EMPTY_LINE] * blank_lines
            if index == 0 and kind != BLOCK and _is_docstring(statement):
                docs.append(self.docstring(statement, depth))
            else:
                docs.append(
                    self.layout.at_level(level, functools.partial(self.statement, statement, depth))
                )
            previous = statement
        return concat(*docs)

    def statement(self, node: ast.stmt, depth: int) -> Doc:
        layout = self.layout
        if isinstance(node, ast.Import):
            (alias,) = node.names
            return Text(f"import {_alias(alias)}")
        if isinstance(node, ast.ImportFrom):
            return self.import_from(node)
        if isinstance(node, ast.Assign):
            (target,) = node.targets
            return concat(layout.expression(target), Text(" = "), self.last_expression(node.value))
        if isinstance(node, ast.Return):
            if node.value is None:
                return Text("return")
            return concat(Text("return "), self.last_expression(node.value))
        if isinstance(node, ast.Expr):
            value = node.value
            if isinstance(value, ast.BinOp) and isinstance(value.op, ARITHMETIC):
                return layout.maybe_parenthesize(value, OPTIONAL)
            return layout.expression(value)
        if isinstance(node, ast.For):
            if node.orelse:
                raise TypeError("the emitter does not write for-else")
            names: list[Doc] = [layout.expression(node.target)]
            if isinstance(node.target, ast.Tuple) and node.target.elts:
                # `for name, value in ...`, as ruff writes a tuple target: no parentheses
                names = [layout.expression(e) for e in node.target.elts]
                names[1:] = [concat(Text(", "), part) for part in names[1:]]
            header = concat(
                Text("for "),
                *names,
                Text(" in "),
                layout.maybe_parenthesize(node.iter, IF_BREAKS),
            )
            return self.clause(header, node.body, BLOCK, depth)
        if isinstance(node, ast.If):
            return self.if_chain(node, "if", depth)
        if isinstance(node, ast.While):
            if node.orelse:
                raise TypeError("the emitter does not write while-else")
            header = concat(Text("while "), layout.maybe_parenthesize(node.test, IF_BREAKS))
            return self.clause(header, node.body, BLOCK, depth)
        if isinstance(node, ast.FunctionDef):
            return self.function(node, depth)
        if isinstance(node, ast.ClassDef):
            return self.class_def(node, depth)
        raise TypeError(f"the emitter does not write {type(node).__name__} statements")

    def last_expression(self, value: ast.expr) -> Doc:
        """The value of an assignment or a return (ruff's ``FormatStatementsLastExpression``,
        left to right): a name or literal gets parentheses only if it then fits; anything
        else breaks its own brackets first."""
        layout = self.layout
        inline = isinstance(value, ast.Name) or (
            isinstance(value, ast.Constant) and value.value is not Ellipsis
        )
        if isinstance(value, (ast.Constant, ast.JoinedStr)) and not inline:
            inline = needs_parentheses(value, layout.is_parenthesized) == BEST_FIT
        if isinstance(value, ast.JoinedStr):
            inline = True
        if inline:
            return BestFitParenthesize(layout.expression(value, NEVER), layout.group_id())
        return layout.maybe_parenthesize(value, IF_BREAKS)

    def import_from(self, node: ast.ImportFrom) -> Doc:
        names: list[Doc] = [Text(_alias(alias)) for alias in node.names]
        module = "." * node.level + (node.module or "")
        names_doc = self.layout.parenthesize_if_expands(
            lambda: self.layout.comma_separated(names, one_or_more=True)
        )
        return concat(Text(f"from {module} import "), names_doc)

    def if_chain(self, node: ast.If, keyword: str, depth: int) -> Doc:
        """``if``/``elif`` and its ``else``: a lone ``if`` in an ``else`` is an ``elif``."""
        header = concat(Text(f"{keyword} "), self.layout.maybe_parenthesize(node.test, IF_BREAKS))
        doc = self.clause(header, node.body, BLOCK, depth)
        if not node.orelse:
            return doc
        alone = node.orelse[0] if len(node.orelse) == 1 else None
        if isinstance(alone, ast.If):
            return concat(doc, HARD_LINE, self.if_chain(alone, "elif", depth))
        return concat(doc, HARD_LINE, self.clause(Text("else"), node.orelse, BLOCK, depth))

    def clause(self, header: Doc, body: list[ast.stmt], kind: str, depth: int) -> Doc:
        # the line break after the block belongs to whatever follows it
        block = self.suite(body, kind, depth + 1)
        return concat(header, Text(":"), Indent(concat(HARD_LINE, block)))

    def decorators(self, node: ast.FunctionDef | ast.ClassDef) -> list[Doc]:
        docs: list[Doc] = []
        for decorator in node.decorator_list:
            docs += [Text("@"), self.layout.maybe_parenthesize(decorator, OPTIONAL), HARD_LINE]
        return docs

    def function(self, node: ast.FunctionDef, depth: int) -> Doc:
        if node.returns is not None or node.args.vararg or node.args.kwarg:
            raise TypeError("the emitter writes plain functions only")
        header = concat(Text(f"def {node.name}"), Group(self.parameters(node.args)))
        return concat(*self.decorators(node), self.clause(header, node.body, FUNCTION, depth))

    def parameters(self, arguments: ast.arguments) -> Doc:
        if arguments.posonlyargs or arguments.kwonlyargs:
            raise TypeError("the emitter writes plain parameters only")
        parameters = arguments.args
        if not parameters:
            return Text("()")
        defaults: list[ast.expr | None] = [None] * (len(parameters) - len(arguments.defaults))
        defaults += arguments.defaults

        def inner() -> Doc:
            parts: list[Doc] = []
            for index, (parameter, default) in enumerate(zip(parameters, defaults, strict=True)):
                if index:
                    parts += [Text(","), SOFT_LINE_OR_SPACE]
                parts.append(Text(parameter.arg))
                if default is not None:
                    parts += [Text("="), self.layout.expression(default)]
            parts.append(if_group_breaks(Text(",")))
            return concat(*parts)

        def layout() -> Doc:
            content = inner()
            if len(parameters) == 1:
                return concat(Text("("), soft_block_indent(content), Text(")"))
            return concat(Text("("), soft_block_indent(Group(content)), Text(")"))

        return self.layout.at_level((PARENTHESIZED, None), layout)

    def class_def(self, node: ast.ClassDef, depth: int) -> Doc:
        header: list[Doc] = [Text(f"class {node.name}")]
        if node.bases or node.keywords:
            call = ast.Call(ast.Name(node.name, ast.Load()), node.bases, node.keywords)
            header.append(self.layout.arguments(call))
        body = self.clause(concat(*header), node.body, CLASS, depth)
        return concat(*self.decorators(node), body)

    def docstring(self, node: ast.stmt, depth: int) -> Doc:
        """Triple double quotes, closing on a line of their own after a final line break.
        Lines too long for the width are wrapped between words (ruff keeps line breaks in
        docstrings as they are: a name too long for any line stands on one of its own)."""
        assert isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
        assert isinstance(node.value.value, str)
        lines = docstring_lines(node.value.value)
        width = LINE_LENGTH - INDENT_WIDTH * depth
        wrapped: list[str] = []
        for index, line in enumerate(lines):
            # room for the opening quotes, and for the closing ones on a one-line docstring
            quotes = 3 if index == 0 or len(lines) == 1 else 0
            wrapped += _wrap(line, width - quotes) or [""]
        first, *rest = wrapped
        docs: list[Doc] = [Text('"""' + first)]
        blank = False
        for index, line in enumerate(rest):
            last = index == len(rest) - 1
            if not line and not last:
                blank = True
                continue
            docs.append(EMPTY_LINE if blank else HARD_LINE)
            blank = False
            if line:
                docs.append(Text(line))
        docs.append(Text('"""'))
        return concat(*docs)


def _wrap(line: str, width: int) -> list[str]:
    if len(line) <= width:
        return [line]
    return textwrap.wrap(line, width, break_long_words=False, break_on_hyphens=False)


def _alias(alias: ast.alias) -> str:
    return alias.name if alias.asname is None else f"{alias.name} as {alias.asname}"


def _is_docstring(node: ast.stmt) -> bool:
    return (
        isinstance(node, ast.Expr)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
    )


def _blank_lines(previous: ast.stmt, statement: ast.stmt, kind: str, second: bool) -> int:
    definitions = (ast.FunctionDef, ast.ClassDef)
    if isinstance(statement, definitions) or isinstance(previous, definitions):
        return 2 if kind == MODULE else 1
    imports = (ast.Import, ast.ImportFrom)
    if isinstance(previous, imports):
        if not isinstance(statement, imports):
            return 1
        return int(import_section(previous) != import_section(statement))
    if second and kind in (MODULE, CLASS) and _is_docstring(previous):
        return 1
    return 0
