"""Imports in isort's order, as ruff's ``I`` rules (default settings) want them.

Sections: ``__future__``, the standard library, third party, first party (none: robospec cannot
know a user's packages, so every other module counts as third party, as ruff decides for a
module it does not find in the project) and local (relative) imports, a blank line between
them. In a section ``import x`` statements come first, then ``from x import y``, each ordered by
module name (case-insensitive, numbers in natural order); a ``from`` import lists constants,
then classes, then everything else.
"""

from __future__ import annotations

import ast
import functools
import re
import sys
from collections.abc import Iterable

FUTURE, STANDARD_LIBRARY, THIRD_PARTY, LOCAL = 0, 1, 2, 4


def import_section(node: ast.stmt) -> int:
    if isinstance(node, ast.ImportFrom):
        if node.level:
            return LOCAL
        module = node.module or ""
    else:
        assert isinstance(node, ast.Import)
        module = node.names[0].name
    top = module.split(".")[0]
    if top == "__future__":
        return FUTURE
    return STANDARD_LIBRARY if top in sys.stdlib_module_names else THIRD_PARTY


def sorted_imports(nodes: Iterable[ast.Import | ast.ImportFrom]) -> list[ast.stmt]:
    """The import statements in isort's order; ``from`` imports list their names sorted."""
    ordered: list[ast.stmt] = []
    for node in nodes:
        if isinstance(node, ast.ImportFrom):
            node = ast.ImportFrom(node.module, sorted(node.names, key=_member_key), node.level)
        ordered.append(node)
    return sorted(ordered, key=_statement_key)


def _statement_key(node: ast.stmt) -> tuple[object, ...]:
    if isinstance(node, ast.Import):
        (alias,) = node.names
        module, first, style = alias.name, alias.asname or "", 0
    else:
        assert isinstance(node, ast.ImportFrom)
        module, first, style = node.module or "", node.names[0].name, 1
    return (
        import_section(node),
        style,
        getattr(node, "level", 0),
        _natural(module.lower()),
        _natural(module),
        _member_key(ast.alias(first)) if style else _natural(first),
    )


def _member_key(alias: ast.alias) -> tuple[object, ...]:
    name = alias.name
    if len(name) > 1 and name.upper() == name and name.lower() != name:
        kind = 0  # a constant
    elif name[:1].isupper():
        kind = 1  # a class
    else:
        kind = 2
    return (kind, _natural(name.lower()), _natural(name), alias.asname or "")


def _compare_natural(a: str, b: str) -> int:
    """Natural order as the ``natord`` crate ruff uses: runs of digits compare as numbers
    (``arm2`` < ``arm10``), anything else character by character."""
    a_parts, b_parts = _DIGITS.findall(a), _DIGITS.findall(b)
    for a_part, b_part in zip(a_parts, b_parts, strict=False):
        if a_part.isdigit() and b_part.isdigit():
            if a_part != b_part:
                fractional = a_part[0] == "0" or b_part[0] == "0"
                if fractional or len(a_part) == len(b_part):
                    return -1 if a_part < b_part else 1
                return -1 if len(a_part) < len(b_part) else 1
        elif a_part != b_part:
            return -1 if a_part < b_part else 1
    return (len(a_parts) > len(b_parts)) - (len(a_parts) < len(b_parts))


_DIGITS = re.compile(r"[0-9]+|[^0-9]")
_natural = functools.cmp_to_key(_compare_natural)
