"""Unparse an ``ast`` module the way a person would lay it out: calls, lists and dicts that do
not fit on one line get one element per line, with a trailing comma."""

from __future__ import annotations

import ast
import json

LINE_LENGTH = 99
INDENT = "    "


def format_expression(node: ast.expr, indent: str) -> str:
    flat = ast.unparse(node)
    if len(indent) + len(flat) <= LINE_LENGTH or not _breakable(node):
        return flat
    inner = indent + INDENT
    if isinstance(node, ast.Call):
        head = format_expression(node.func, indent)
        items = [format_expression(a, inner) for a in node.args]
        items += [
            f"{k.arg}={format_expression(k.value, inner)}"
            if k.arg
            else f"**{format_expression(k.value, inner)}"
            for k in node.keywords
        ]
        return _block(head + "(", items, ")", indent)
    if isinstance(node, ast.List):
        return _block("[", [format_expression(e, inner) for e in node.elts], "]", indent)
    if isinstance(node, ast.Tuple):
        return _block("(", [format_expression(e, inner) for e in node.elts], ")", indent)
    assert isinstance(node, ast.Dict)
    items = [
        f"{format_expression(k, inner)}: {format_expression(v, inner)}"  # type: ignore[arg-type]
        for k, v in zip(node.keys, node.values, strict=True)
    ]
    return _block("{", items, "}", indent)


def _breakable(node: ast.expr) -> bool:
    if isinstance(node, ast.Call):
        return bool(node.args or node.keywords)
    if isinstance(node, (ast.List, ast.Tuple)):
        return bool(node.elts)
    return isinstance(node, ast.Dict) and bool(node.keys)


def _block(opening: str, items: list[str], closing: str, indent: str) -> str:
    inner = indent + INDENT
    body = "".join(f"{inner}{item},\n" for item in items)
    return f"{opening}\n{body}{indent}{closing}"


def format_module(module: ast.Module) -> str:
    lines: list[str] = []
    _statements(module.body, "", lines, top=True)
    return "\n".join(lines).rstrip("\n") + "\n"


def _statements(body: list[ast.stmt], indent: str, lines: list[str], *, top: bool) -> None:
    previous: ast.stmt | None = None
    for stmt in body:
        if previous is not None and _blank_before(previous, stmt, top):
            two = top and isinstance(stmt, (ast.ClassDef, ast.FunctionDef))
            lines.extend([""] * (2 if two else 1))
        _statement(stmt, indent, lines)
        previous = stmt


def _blank_before(previous: ast.stmt, stmt: ast.stmt, top: bool) -> bool:
    defs = (ast.ClassDef, ast.FunctionDef)
    if isinstance(stmt, defs) or isinstance(previous, defs):
        return True
    imports = (ast.Import, ast.ImportFrom)
    if isinstance(previous, imports) and not isinstance(stmt, imports):
        return True
    if isinstance(previous, ast.Expr) and isinstance(previous.value, ast.Constant):
        return True  # after a docstring
    # a standard-library import group, then the third-party group
    return (
        isinstance(previous, ast.Import)
        and isinstance(stmt, ast.Import)
        and _is_stdlib(previous) != _is_stdlib(stmt)
    ) or (
        isinstance(previous, ast.Import)
        and isinstance(stmt, ast.ImportFrom)
        and _is_stdlib(previous)
    )


def _is_stdlib(stmt: ast.Import) -> bool:
    return stmt.names[0].name in {"os"}


def _statement(stmt: ast.stmt, indent: str, lines: list[str]) -> None:
    if isinstance(stmt, ast.ClassDef):
        for decorator in stmt.decorator_list:
            lines.append(f"{indent}@{ast.unparse(decorator)}")
        bases = ", ".join(ast.unparse(b) for b in stmt.bases)
        lines.append(f"{indent}class {stmt.name}({bases}):")
        _statements(stmt.body, indent + INDENT, lines, top=False)
    elif isinstance(stmt, ast.FunctionDef):
        for decorator in stmt.decorator_list:
            lines.append(f"{indent}@{ast.unparse(decorator)}")
        signature = ast.unparse(stmt.args)
        lines.append(f"{indent}def {stmt.name}({signature}):")
        _statements(stmt.body, indent + INDENT, lines, top=False)
    elif isinstance(stmt, ast.For):
        lines.append(
            f"{indent}for {ast.unparse(stmt.target)} in {format_expression(stmt.iter, indent)}:"
        )
        _statements(stmt.body, indent + INDENT, lines, top=False)
    elif isinstance(stmt, ast.ImportFrom) and len(ast.unparse(stmt)) > LINE_LENGTH:
        names = [ast.unparse(alias) for alias in stmt.names]
        lines.append(_block(f"{indent}from {stmt.module} import (", names, ")", indent))
    elif isinstance(stmt, ast.Assign):
        targets = " = ".join(ast.unparse(t) for t in stmt.targets)
        lines.append(f"{indent}{targets} = {format_expression(stmt.value, indent)}")
    elif isinstance(stmt, ast.Return) and stmt.value is not None:
        lines.append(f"{indent}return {format_expression(stmt.value, indent)}")
    elif (
        isinstance(stmt, ast.Expr)
        and isinstance(stmt.value, ast.Constant)
        and isinstance(stmt.value.value, str)
    ):
        lines.append(f'{indent}"""{_docstring(stmt.value.value, indent)}"""')
    elif isinstance(stmt, ast.Expr):
        lines.append(f"{indent}{format_expression(stmt.value, indent)}")
    else:
        lines.append(f"{indent}{ast.unparse(stmt)}")


def _docstring(text: str, indent: str) -> str:
    # Docstrings quote spec paths, which are user text: escape each line the way JSON escapes
    # a string (quotes, backslashes, control characters), so nothing can end the literal.
    lines = [json.dumps(line, ensure_ascii=False)[1:-1] for line in text.split("\n")]
    return ("\n" + indent).join(lines).replace("\n" + indent + "\n", "\n\n")
