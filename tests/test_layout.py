"""robospec's layout of Python code is ruff's, for every construct the emitter writes.

:mod:`robospec.emit.layout` re-implements the part of ``ruff format`` the generated modules
need. Property tests build random code from exactly those constructs (calls, attribute chains,
subscripts, collections, comprehensions, binary and unary operations, comparisons, f-strings,
strings that need escaping, numbers as specs write them; assignments, returns, loops, functions,
classes, imports), nested and with names long and short, lay it out, and check that the real
ruff would change nothing — not even with trailing commas ignored, so each layout choice is
ruff's own. The module then also compiles to the code that was laid out.
"""

from __future__ import annotations

import ast
import keyword
import string

import pytest
from conftest import SAME_ON_EVERY_MANISKILL
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_generated_code import FUZZ_SCALE, assert_formatted, ruff_findings

from robospec.emit.layout import format_module
from robospec.emit.layout.imports import sorted_imports

NAMES = st.one_of(
    st.sampled_from(["a", "x", "self", "np", "torch", "value", "links_map", "pose"]),
    st.text(string.ascii_lowercase + "_", min_size=1, max_size=40).filter(
        lambda s: s.isidentifier() and not keyword.iskeyword(s)
    ),
)
TEXT = st.one_of(
    st.text(string.ascii_letters + " _-./", max_size=70),
    st.text(max_size=12),  # anything: quotes, backslashes, line breaks, wide characters
)
# docstrings as the emitter writes them: words, no space at either end (ruff strips it)
DOCSTRINGS = (
    st.text(string.ascii_letters + " .,'-", min_size=1, max_size=60).map(str.strip).filter(bool)
)
NUMBER_TEXTS = st.sampled_from(
    ["0", "1", "100", "1e3", "1E-3", "0.04", ".5", "5.", "0x1f", "2.5e+2"]
)


def load(name: str) -> ast.Name:
    return ast.Name(name, ast.Load())


@st.composite
def numbers(draw: st.DrawFn) -> ast.expr:
    if draw(st.booleans()):
        node = ast.Constant(draw(st.floats(allow_nan=False, allow_infinity=False, min_value=0)))
        return node
    text = draw(NUMBER_TEXTS)
    node = ast.Constant(ast.literal_eval(text))
    node.text = text  # type: ignore[attr-defined]  # as a spec wrote it
    return node


def leaves() -> st.SearchStrategy[ast.expr]:
    return st.one_of(
        NAMES.map(load),
        TEXT.map(ast.Constant),
        numbers(),
        st.sampled_from([True, False, None]).map(ast.Constant),
        st.tuples(NAMES, TEXT).map(
            lambda p: ast.JoinedStr([ast.FormattedValue(load(p[0]), -1, None), ast.Constant(p[1])])
        ),
    )


def trailers(children: st.SearchStrategy[ast.expr]) -> st.SearchStrategy[tuple[str, object]]:
    """What follows a name in a chain: ``.attribute``, ``(arguments)`` or ``[index]``."""
    arguments = st.tuples(
        st.lists(children, max_size=4),
        st.lists(st.tuples(NAMES, children), max_size=3, unique_by=lambda kv: kv[0]),
    )
    return st.one_of(
        NAMES.map(lambda n: ("attribute", n)),
        arguments.map(lambda a: ("call", a)),
        indices(children).map(lambda i: ("subscript", i)),
    )


def chain(name: str, parts: list[tuple[str, object]]) -> ast.expr:
    node: ast.expr = load(name)
    for kind, part in parts:
        if kind == "attribute":
            node = ast.Attribute(node, part, ast.Load())
        elif kind == "call":
            args, keywords = part  # type: ignore[misc]
            node = ast.Call(node, args, [ast.keyword(k, v) for k, v in keywords])
        else:
            node = ast.Subscript(node, part, ast.Load())
    return node


def dotted(children: st.SearchStrategy[ast.expr]) -> st.SearchStrategy[ast.expr]:
    """Names, attribute chains, calls and subscripts: what calls and attributes hang from."""
    return st.tuples(NAMES, st.lists(trailers(children), max_size=4)).map(lambda p: chain(*p))


def indices(children: st.SearchStrategy[ast.expr]) -> st.SearchStrategy[ast.expr]:
    slices = st.one_of(
        st.just(ast.Constant(...)),
        st.tuples(st.none() | numbers(), st.none() | numbers()).map(
            lambda p: ast.Slice(p[0], p[1], None)
        ),
        numbers(),
        NAMES.map(load),
    )
    return st.one_of(
        children, st.lists(slices, min_size=2, max_size=3).map(lambda e: ast.Tuple(e, ast.Load()))
    )


BINARY = st.sampled_from([ast.Add(), ast.Sub(), ast.Mult(), ast.Div(), ast.Pow(), ast.BitAnd()])
COMPARE = st.sampled_from([ast.Lt(), ast.LtE(), ast.Gt(), ast.GtE(), ast.Eq()])


def _compound(children: st.SearchStrategy[ast.expr]) -> st.SearchStrategy[ast.expr]:
    return st.one_of(
        dotted(children),
        st.lists(children, max_size=5).map(lambda e: ast.List(e, ast.Load())),
        st.lists(st.tuples(TEXT.map(ast.Constant), children), max_size=4).map(
            lambda kv: ast.Dict([k for k, _ in kv], [v for _, v in kv])
        ),
        st.tuples(children, BINARY, children).map(lambda p: ast.BinOp(p[0], p[1], p[2])),
        st.tuples(children, COMPARE, children).map(lambda p: ast.Compare(p[0], [p[1]], [p[2]])),
        children.map(lambda e: ast.UnaryOp(ast.USub(), e)),
        st.tuples(children, NAMES, children).map(
            lambda p: ast.ListComp(
                p[0], [ast.comprehension(ast.Name(p[1], ast.Store()), p[2], [], 0)]
            )
        ),
        st.tuples(children, children, NAMES, children).map(
            lambda p: ast.DictComp(
                p[0], p[1], [ast.comprehension(ast.Name(p[2], ast.Store()), p[3], [], 0)]
            )
        ),
    )


EXPRESSIONS = st.recursive(leaves(), _compound, max_leaves=12)


def expressions() -> st.SearchStrategy[ast.expr]:
    return EXPRESSIONS


def targets() -> st.SearchStrategy[ast.expr]:
    return st.one_of(
        NAMES.map(lambda n: ast.Name(n, ast.Store())),
        st.tuples(NAMES, NAMES).map(lambda p: ast.Attribute(load(p[0]), p[1], ast.Store())),
    )


def statements(depth: int, *, functions_too: bool = False) -> st.SearchStrategy[ast.stmt]:
    """Statements nested ``depth`` deep; functions (methods) only where ``functions_too``:
    the emitter writes none inside a function or a loop."""
    simple = st.one_of(
        st.tuples(targets(), expressions()).map(lambda p: ast.Assign([p[0]], p[1])),
        dotted(expressions()).map(ast.Expr),
    )
    if depth == 0:
        return simple
    body = st.lists(statements(depth - 1), min_size=1, max_size=3)
    # a loop's target: a name, or names unpacked (`for name, value in ...items()`)
    loop_targets = st.one_of(
        NAMES.map(lambda n: ast.Name(n, ast.Store())),
        st.lists(NAMES, min_size=2, max_size=3).map(
            lambda names: ast.Tuple([ast.Name(n, ast.Store()) for n in names], ast.Store())
        ),
    )
    loops = st.tuples(loop_targets, expressions(), body).map(
        lambda p: ast.For(p[0], p[1], p[2], [])
    )
    return st.one_of(simple, loops, functions(body)) if functions_too else st.one_of(simple, loops)


@st.composite
def functions(draw: st.DrawFn, body: st.SearchStrategy[list[ast.stmt]]) -> ast.FunctionDef:
    names = draw(st.lists(NAMES, min_size=1, max_size=4, unique=True))
    defaults = draw(st.lists(numbers(), max_size=len(names) - 1))
    statements = draw(body)
    if draw(st.booleans()):
        statements = [ast.Expr(ast.Constant(draw(DOCSTRINGS))), *statements]
    statements.append(ast.Return(draw(expressions())))
    decorators = draw(st.lists(dotted(expressions()), max_size=1))
    return ast.FunctionDef(
        draw(NAMES),
        ast.arguments([], [ast.arg(n) for n in names], None, [], [], None, defaults),
        statements,
        decorators,
        None,
        type_params=[],
    )


@st.composite
def modules(draw: st.DrawFn) -> ast.Module:
    body: list[ast.stmt] = [ast.Expr(ast.Constant("A module.\n\nIts docstring.\n"))]
    imports = [
        ast.Import([ast.alias("numpy", "np")]),
        ast.Import([ast.alias("os")]),
        ast.ImportFrom(
            "mani_skill.agents.base_agent", [ast.alias("Keyframe"), ast.alias("BaseAgent")], 0
        ),
        ast.ImportFrom("mani_skill", [ast.alias("PACKAGE_ASSET_DIR"), ast.alias("ASSET_DIR")], 0),
    ]
    body += sorted_imports(draw(st.lists(st.sampled_from(imports), unique=True, max_size=4)))
    body += draw(st.lists(statements(2, functions_too=True), max_size=2))
    class_body: list[ast.stmt] = [ast.Expr(ast.Constant(draw(DOCSTRINGS)))]
    class_body += draw(st.lists(statements(2, functions_too=True), min_size=1, max_size=4))
    body.append(
        ast.ClassDef(
            draw(NAMES),
            draw(st.lists(dotted(expressions()), max_size=2)),
            [],
            class_body,
            draw(st.lists(dotted(expressions()), max_size=1)),
            type_params=[],
        )
    )
    return ast.fix_missing_locations(ast.Module(body, []))


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@SAME_ON_EVERY_MANISKILL
@settings(
    max_examples=max(int(200 * FUZZ_SCALE), 10),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(modules())
def test_the_layout_of_random_code_is_ruffs(module: ast.Module) -> None:
    source = format_module(module)
    assert ast.dump(ast.parse(source)) == ast.dump(ast.parse(ast.unparse(module)))
    assert_formatted(source)
    codes = {finding["code"] for finding in ruff_findings(source)}
    assert "I001" not in codes
