"""Python values as expressions of constants: names, calls, literals and poses.

Text from a spec only ever enters generated code through :func:`const`, as ``ast.Constant``
nodes (the layout writes them as escaped literals).
"""

from __future__ import annotations

import ast
import keyword
import math
from collections.abc import Callable, Sequence
from typing import Any

from robospec.resolve.resolved import FileRef

FileExpression = Callable[[FileRef], ast.expr]


class UnsafeIdentifier(ValueError):
    pass


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


def call(func: str, args: list[ast.expr] | None = None, **kwargs: ast.expr) -> ast.Call:
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
        if not math.isfinite(value):
            raise ValueError("non-finite numbers never reach the emitter")
        if math.copysign(1.0, value) < 0:
            return ast.UnaryOp(ast.USub(), ast.Constant(-value))
        return ast.Constant(value)
    if isinstance(value, (list, tuple)):
        return ast.List([const(v, files) for v in value], ast.Load())
    if isinstance(value, dict):
        return ast.Dict([const(str(k)) for k in value], [const(v, files) for v in value.values()])
    raise TypeError(f"cannot emit {type(value).__name__}")


def value_key(value: Any) -> tuple[type, str]:
    """Equal keys for values the generated code cannot tell apart (``repr`` keeps -0.0 and
    0.0 apart, which ``==`` does not)."""
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
