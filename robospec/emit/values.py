"""Python values as expressions of constants: names, calls, literals and poses.

Text from a spec only ever enters generated code through :func:`const`, as ``ast.Constant``
nodes (the layout writes them as escaped literals).
"""

from __future__ import annotations

import ast
import keyword
import math
import sys
from collections.abc import Callable, Sequence
from typing import Any

from robospec.emit.numbers import literal, number_expr, python_value
from robospec.resolve.resolved import FileRef

FileExpression = Callable[[FileRef], ast.expr]


class UnsafeIdentifier(ValueError):
    pass


# Python 3.12 added type parameters to function and class definitions (ast's type_params): the
# nodes are given none there, and nothing where the field does not exist
NO_TYPE_PARAMS: dict[str, Any] = {"type_params": []} if sys.version_info >= (3, 12) else {}


def safe_identifier(text: str) -> str:
    """``text`` if it is a plain ASCII Python identifier (no keyword), else
    :class:`UnsafeIdentifier`: every identifier taken from a spec passes here."""
    if not text.isidentifier() or keyword.iskeyword(text) or not text.isascii():
        raise UnsafeIdentifier(f"{text!r} is not a valid Python identifier")
    return text


def name(dotted: str) -> ast.expr:
    """``a.b.c`` as a name and attribute accesses."""
    head, *rest = dotted.split(".")
    node: ast.expr = ast.Name(head, ast.Load())
    for attribute in rest:
        node = ast.Attribute(node, attribute, ast.Load())
    return node


def call(func: str, args: list[ast.expr] | None = None, /, **kwargs: ast.expr) -> ast.Call:
    return ast.Call(name(func), args or [], [ast.keyword(k, v) for k, v in kwargs.items()])


def assign(target: str, value: ast.expr) -> ast.Assign:
    return ast.Assign([ast.Name(target, ast.Store())], value)


def const(value: Any, files: FileExpression | None = None) -> ast.expr:
    """A Python value as an expression of constants only; files through ``files``."""
    if isinstance(value, FileRef):
        assert files is not None
        return files(value)
    if value is None or isinstance(value, (bool, int, str)):
        return ast.Constant(value)
    if isinstance(value, float):
        if math.isnan(value):
            raise ValueError("NaN never reaches the emitter: the model refuses it")
        return number_expr(value)
    if isinstance(value, (list, tuple)):
        return ast.List([const(v, files) for v in value], ast.Load())
    if isinstance(value, dict):
        return ast.Dict([const(str(k)) for k in value], [const(v, files) for v in value.values()])
    raise TypeError(f"cannot emit {type(value).__name__}")


def float_array(values: Sequence[Any]) -> ast.List:
    """A list for ``np.array`` or a tensor, whose numbers the model holds as floats: written as
    the spec wrote them, unless every one would be an integer; numpy and torch would then make
    an integer array, so they are written as floats (``[0.0, 0.0]``), as before."""
    rows = [list(v) if isinstance(v, (list, tuple)) else None for v in values]
    cells = [cell for row in rows if row is not None for cell in row] or list(values)
    if cells and all(type(python_value(const(cell))) is int for cell in cells):
        if any(row is not None for row in rows):
            return ast.List([_plain_row(row or []) for row in rows], ast.Load())
        return _plain_row(list(values))
    return ast.List([const(v) for v in values], ast.Load())


def _plain_row(values: list[Any]) -> ast.List:
    return ast.List([literal(float(v)) for v in values], ast.Load())


def value_key(value: Any) -> tuple[type, str]:
    """Equal keys for values the generated code cannot tell apart: what it computes, by
    type and ``repr`` (which keeps -0.0 and 0.0 apart, as ``==`` does not)."""
    if isinstance(value, float):
        computed = python_value(const(value))
        return (type(computed), repr(computed))
    return (type(value), repr(value))


def _is_positive_zero(value: float) -> bool:
    return value == 0 and math.copysign(1.0, value) > 0


def is_origin(p: Sequence[float]) -> bool:
    return all(_is_positive_zero(v) for v in p)


def is_identity(q: Sequence[float]) -> bool:
    return q[0] == 1 and all(_is_positive_zero(v) for v in q[1:])


def sapien_pose(p: Sequence[float], q: Sequence[float]) -> ast.Call:
    """``sapien.Pose(p=..., q=...)``, leaving out what is the default: ``sapien.Pose()`` for
    the identity, as ManiSkill's agents write it."""
    kwargs: dict[str, ast.expr] = {}
    if not is_origin(p):
        kwargs["p"] = const(list(p))
    if not is_identity(q):
        kwargs["q"] = const(list(q))
    return call("sapien.Pose", **kwargs)
