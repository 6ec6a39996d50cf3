"""Laying out the generated modules: robospec's own layout (robospec/emit/layout/) against black
and ruff, side by side in one run.

The trees are the ones `robospec build specs/` lays out: every shipped spec's agent module, taken
as the emitter hands it to ``format_module`` (recorded by wrapping it while the package is
planned), and random modules built from the constructs the emitter writes (the strategy of
tests/test_layout.py, drawn the same way every run). A formatter reads source, not a tree: each
tree is written out by ``ast.unparse`` with what the layout decides from the tree and a
formatter cannot (``formatter_input``: literals as robospec escapes them, numbers as the spec
wrote them, docstrings wrapped to the line length, a blank line before each paragraph and
between import sections) and handed to ``black.format_str`` (line length 100, its magic
trailing comma on) and to ``ruff format --line-length 100 -``.

Measured: (a) how many modules each formatter writes exactly as the layout does, and the first
difference; the oldest ruff the dev extra allows and an older black beside the newest, since
a generated module's text would then depend on the formatter's version; (b) the time to lay
out each shipped module, the formatter's import cost on top of what `build` has imported by
then, `robospec build specs/`'s own time for scale, and whether a warm `robospec.register`
imports a formatter at all; (c) what each adds to the core install. black and the older ruff are
installed by pip into folders of their own in the temporary folder, once; the ruff is the dev
extra's. The layout's own target: every shipped module and random module as the dev extra's ruff
writes it (tests/test_layout.py and tests/test_generated_code.py prove the same).
"""

from __future__ import annotations

import ast
import copy
import difflib
import importlib.metadata
import json
import pickle
import re
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from collections.abc import Callable, Collection
from dataclasses import dataclass
from pathlib import Path

from measure import PYTHON, ROOT, child_env, sample
from section import Section

TITLE = "Laying out generated modules: robospec's layout, black and ruff"
BLACK = "26.10.1"  # the newest black when this was written
OLDER_BLACK = "24.1.0"  # the first release of black's 2024 stable style
OLDER_RUFF = "0.5.0"  # the oldest ruff the dev extra allows (ruff>=0.5)
LINE_LENGTH = 100
RUFF = Path(PYTHON).parent / "ruff"
LAYOUT = ROOT / "robospec" / "emit" / "layout"

_BLANK_LINE = "__robospec_blank_line__"
# a child that imports what `robospec build` has imported before it lays out its first module,
# then the formatter, and prints how long that second import took
_IMPORT_COST = """
import time, robospec.pipeline, robospec.emit.values
started = time.perf_counter()
import {module}
print(time.perf_counter() - started)
"""
# a child that formats the sources it reads (JSON) with the black on its path
_BLACK_CHILD = """
import json, statistics, sys, time
import black
sources, repeat = json.load(sys.stdin)
mode = black.Mode(line_length=int(sys.argv[1]))
outputs, seconds = [], []
for source in sources:
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        text = black.format_str(source, mode=mode)
        times.append(time.perf_counter() - started)
    outputs.append(text)
    seconds.append(statistics.median(times))
json.dump([outputs, seconds], sys.stdout)
"""
_WARM_REGISTER = """
import sys, mani_skill.envs, robospec
robospec.register("specs/")
print(sorted(m for m in sys.modules if m.startswith("robospec.emit") or m in ("black", "ruff")))
"""


@dataclass(frozen=True)
class Module:
    name: str
    tree: ast.Module
    paragraphs: Collection[int]
    layout: str  # what format_module writes
    source: str  # formatter_input: what black and ruff are given


@dataclass(frozen=True)
class Formatted:
    """One formatter's texts for the modules, and its time per module (None: not timed)."""

    label: str
    texts: list[str]
    seconds: list[float] | None = None


def formatter_input(module: ast.Module, paragraphs: Collection[int] = ()) -> str:
    """``module`` as source for an outside formatter, with what ``format_module`` decides from
    the tree and a formatter cannot: literals as robospec writes them (escaped strings, numbers
    as the spec wrote them: ``1e3``, not ``1000.0``), docstrings wrapped to the line length, and
    a blank line before each statement in ``paragraphs`` (their ``id()``) and between import
    sections. ``ast.unparse`` writes the rest; a name node carries each literal's text."""
    memo: dict[int, object] = {}
    tree = copy.deepcopy(module, memo)
    marked = {id(memo[key]) for key in paragraphs if key in memo}
    _ForFormatter(marked).visit(tree)
    text = ast.unparse(ast.fix_missing_locations(tree))
    lines = ("" if line.strip() == _BLANK_LINE else line for line in text.splitlines())
    return "\n".join(lines) + "\n"


class _ForFormatter(ast.NodeTransformer):
    def __init__(self, paragraphs: set[int]) -> None:
        self.paragraphs = paragraphs
        self.depth = 0  # of the suite being visited

    def visit_Module(self, node: ast.Module) -> ast.AST:
        return self._suite(node, 0)

    def visit_ClassDef(self, node: ast.ClassDef) -> ast.AST:
        return self._suite(node, 1)

    def visit_FunctionDef(self, node: ast.FunctionDef) -> ast.AST:
        return self._suite(node, 1)

    def visit_For(self, node: ast.For) -> ast.AST:
        return self._suite(node, 1)

    def _suite(self, node: ast.Module | ast.ClassDef | ast.FunctionDef | ast.For, indent: int):
        from robospec.emit.layout.imports import import_section

        self.depth += indent
        first = node.body[0]
        if not isinstance(node, ast.For) and _is_docstring(first):
            assert isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
            node.body[0] = ast.Expr(_text(_docstring(first.value.value, self.depth)))
        self.generic_visit(node)
        self.depth -= indent
        body: list[ast.stmt] = []
        imports = (ast.Import, ast.ImportFrom)
        for statement in node.body:
            previous = body[-1] if body else None
            new_section = (
                isinstance(statement, imports)
                and isinstance(previous, imports)
                and import_section(statement) != import_section(previous)
            )
            if id(statement) in self.paragraphs or new_section:
                body.append(ast.Expr(_text(_BLANK_LINE)))
            body.append(statement)
        node.body = body
        return node

    def visit_Constant(self, node: ast.Constant) -> ast.AST:
        from robospec.emit.layout.literals import string_literal

        if isinstance(node.value, str):
            return _text(string_literal(node.value))
        written = getattr(node, "text", None)
        return node if written is None else _text(written)

    def visit_JoinedStr(self, node: ast.JoinedStr) -> ast.AST:
        from robospec.emit.layout.literals import fstring_literal

        parts: list[str | tuple[str]] = []
        for value in node.values:
            if isinstance(value, ast.Constant):
                parts.append(value.value)
            else:
                assert isinstance(value, ast.FormattedValue) and isinstance(value.value, ast.Name)
                parts.append((value.value.id,))
        return _text(fstring_literal(parts))


def _text(source: str) -> ast.Name:
    return ast.Name(source, ast.Load())


def _is_docstring(node: ast.stmt) -> bool:
    return (
        isinstance(node, ast.Expr)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
    )


def _docstring(value: str, depth: int) -> str:
    """The docstring as the layout writes it: escaped, long lines wrapped between words."""
    from robospec.emit.layout.literals import docstring_lines

    lines = docstring_lines(value)
    width = LINE_LENGTH - 4 * depth
    wrapped: list[str] = []
    for index, line in enumerate(lines):
        room = width - (3 if index == 0 or len(lines) == 1 else 0)
        if len(line) <= room:
            wrapped.append(line)
        else:
            wrapped += textwrap.wrap(line, room, break_long_words=False, break_on_hyphens=False)
    return '"""' + "\n".join(wrapped) + '"""'


def shipped_modules(scratch: Path) -> list[Module]:
    """Every shipped spec's agent module, as `robospec build specs/` lays it out."""
    from robospec.emit import generate
    from robospec.load.discovery import discover
    from robospec.output.package import plan_package
    from robospec.pipeline import compile_spec

    paths, problems = discover([ROOT / "specs"])
    assert paths and not problems, problems
    compiled = [compile_spec(path) for path in paths]
    recorded: list[tuple[ast.Module, Collection[int]]] = []
    format_module = generate.format_module

    def record(module: ast.Module, paragraphs: Collection[int] = ()) -> str:
        recorded.append((module, paragraphs))
        return format_module(module, paragraphs)

    generate.format_module = record
    try:
        plan_package(compiled, scratch / "robospec_agents")
    finally:
        generate.format_module = format_module
    uids = [item.robot.uid for item in compiled if item.robot is not None]
    assert len(uids) == len(recorded) == len(paths)
    return [
        _module(uid, tree, paragraphs, format_module)
        for uid, (tree, paragraphs) in zip(uids, recorded, strict=True)
    ]


def random_modules(count: int) -> list[Module]:
    """``count`` modules of tests/test_layout.py's strategy, the same ones every run: drawn in a
    fresh process, because Hypothesis also draws from the constants of the modules loaded (in
    this one, whatever ran before)."""
    from robospec.emit.layout import format_module

    done = subprocess.run(
        [PYTHON, "-c", f"import formatter; formatter._draw({count})"],
        capture_output=True,
        check=True,
        cwd=Path(__file__).parent,
        env=child_env(),
    )
    drawn: list[ast.Module] = pickle.loads(done.stdout)
    return [_module(f"random {i}", tree, (), format_module) for i, tree in enumerate(drawn)]


def _draw(count: int) -> None:
    """Pickle ``count`` modules of the strategy, derandomized, to stdout."""
    from hypothesis import HealthCheck, Phase, given, settings

    sys.path.insert(0, str(ROOT / "tests"))
    from test_layout import modules

    drawn: list[ast.Module] = []
    configured = settings(
        max_examples=count,
        derandomize=True,
        database=None,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )

    @configured
    @given(modules())
    def draw(module: ast.Module) -> None:
        drawn.append(module)

    draw()
    sys.stdout.buffer.write(pickle.dumps(drawn))


def _module(
    name: str, tree: ast.Module, paragraphs: Collection[int], layout: Callable[..., str]
) -> Module:
    return Module(
        name, tree, paragraphs, layout(tree, paragraphs), formatter_input(tree, paragraphs)
    )


def laid_out(modules: list[Module], repeat: int) -> Formatted:
    from robospec.emit.layout import format_module

    seconds = [
        _median_time(lambda m=m: format_module(m.tree, m.paragraphs), repeat) for m in modules
    ]
    return Formatted("robospec/emit/layout", [m.layout for m in modules], seconds)


def ruff_formatted(ruff: Path, label: str, modules: list[Module], repeat: int) -> Formatted:
    """``ruff format -`` over each module's source: one process per module, as emitting one
    module at a time would run it."""
    args = [str(ruff), "format", "--isolated", "--line-length", str(LINE_LENGTH), "-"]

    def format_one(source: str) -> str:
        done = subprocess.run(args, input=source, capture_output=True, text=True, check=True)
        return done.stdout

    texts = [format_one(m.source) for m in modules]
    if not repeat:
        return Formatted(label, texts)
    seconds = [_median_time(lambda m=m: format_one(m.source), repeat) for m in modules]
    return Formatted(label, texts, seconds)


def black_formatted(folder: Path, label: str, modules: list[Module], repeat: int) -> Formatted:
    """``black.format_str`` over each module's source, in a child with that black on its path."""
    done = subprocess.run(
        [PYTHON, "-c", _BLACK_CHILD, str(LINE_LENGTH)],
        input=json.dumps([[m.source for m in modules], max(repeat, 1)]),
        capture_output=True,
        text=True,
        check=True,
        env=child_env(PYTHONPATH=str(folder)),
    )
    texts, seconds = json.loads(done.stdout)
    return Formatted(label, texts, seconds if repeat else None)


def _median_time(work: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(max(repeat, 1)):
        started = time.perf_counter()
        work()
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def installed(package: str, version: str) -> tuple[Path | None, str]:
    """A folder holding ``package==version`` and what it needs (pip's ``--target``), made on
    first use, and ``""``; or None and why it could not be made (offline, say)."""
    folder = Path(tempfile.gettempdir()) / f"robospec-bench-{package}-{version}"
    stamp = folder / "robospec-installed.txt"
    if stamp.exists():
        return folder, ""
    step = [PYTHON, "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    step += ["--target", str(folder), "--upgrade", f"{package}=={version}"]
    try:
        done = subprocess.run(step, capture_output=True, text=True, timeout=900)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return None, f"pip install {package}=={version} failed: {exc}"
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["(no message)"])[-1]
        return None, f"pip install {package}=={version} failed: {last}"
    stamp.write_text(version)
    return folder, ""


def import_cost(module: str, repeat: int, path: Path | None = None) -> float:
    """The median time to import ``module`` in a fresh process that has imported what
    `robospec build` has by the time it lays out its first module."""
    env = child_env(PYTHONPATH=str(path)) if path else child_env()
    times = []
    for _ in range(max(repeat, 1) + 1):  # the first writes the bytecode caches: not counted
        done = subprocess.run(
            [PYTHON, "-c", _IMPORT_COST.format(module=module)],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
            env=env,
        )
        times.append(float(done.stdout))
    return statistics.median(times[1:])


def core_install_bytes() -> tuple[int, set[str]]:
    """The size of robospec's core install (its dependencies, recursively, as installed here;
    no extras) and the normalized names of those distributions."""
    from packaging.requirements import Requirement

    seen: dict[str, importlib.metadata.Distribution] = {}
    pending = [
        Requirement(r).name
        for r in importlib.metadata.distribution("robospec").requires or []
        if "extra" not in r
    ]
    while pending:
        name = _normalized(pending.pop())
        if name in seen:
            continue
        try:
            seen[name] = importlib.metadata.distribution(name)
        except importlib.metadata.PackageNotFoundError:
            continue
        for text in seen[name].requires or []:
            requirement = Requirement(text)
            if requirement.marker is None or requirement.marker.evaluate({"extra": ""}):
                pending.append(requirement.name)
    return sum(_distribution_bytes(d) for d in seen.values()), set(seen)


def _distribution_bytes(distribution: importlib.metadata.Distribution) -> int:
    total = 0
    for file in distribution.files or []:
        try:
            total += Path(str(file.locate())).stat().st_size
        except OSError:
            pass
    return total


def _normalized(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def added_bytes(folder: Path, core: set[str]) -> tuple[int, list[str]]:
    """What the distributions pip put in ``folder`` would add to the core install: their size,
    less those the core already has, and their names."""
    distributions = importlib.metadata.distributions(path=[str(folder)])
    new = [d for d in distributions if _normalized(d.metadata["Name"]) not in core]
    names = sorted(f"{d.metadata['Name']} {d.version}" for d in new)
    return sum(_distribution_bytes(d) for d in new), names


def first_difference(expected: str, got: str, lines: int = 8) -> str:
    diff = difflib.unified_diff(
        expected.splitlines(), got.splitlines(), "layout", "formatter", lineterm="", n=1
    )
    return "\n".join(list(diff)[2 : 2 + lines])


def measure(repeat: int = 5, random_count: int = 200) -> Section:
    with tempfile.TemporaryDirectory(prefix="robospec-bench-formatter-") as scratch:
        return _measure(repeat, random_count, Path(scratch))


@dataclass(frozen=True)
class _Formatters:
    """The formatters measured: black and the older ones as pip installed them (None: not)."""

    black: Path | None
    older_black: Path | None
    older_ruff: Path | None
    ruff_version: str  # the dev extra's, beside this Python
    skipped: list[str]  # why one is missing

    @property
    def dev_ruff(self) -> str:
        return f"ruff {self.ruff_version}"


def _formatters() -> _Formatters:
    black, black_why = installed("black", BLACK)
    older_black, older_black_why = installed("black", OLDER_BLACK)
    older_ruff, older_ruff_why = installed("ruff", OLDER_RUFF)
    skipped = [why for why in (black_why, older_black_why, older_ruff_why) if why]
    version = importlib.metadata.version("ruff")
    return _Formatters(black, older_black, older_ruff, version, skipped)


def _each(tools: _Formatters, modules: list[Module], timed: int) -> list[Formatted]:
    """Every formatter's texts for ``modules``; the layout's too, and times, when ``timed``
    (the number of runs per module); the older formatters are never timed."""
    results = [laid_out(modules, timed)] if timed else []
    if tools.black:
        results.append(black_formatted(tools.black, f"black {BLACK}", modules, timed))
    results.append(ruff_formatted(RUFF, tools.dev_ruff, modules, timed))
    if tools.older_black:
        results.append(black_formatted(tools.older_black, f"black {OLDER_BLACK}", modules, 0))
    if tools.older_ruff:
        older = tools.older_ruff / "bin" / "ruff"
        results.append(ruff_formatted(older, f"ruff {OLDER_RUFF}", modules, 0))
    return results


def _measure(repeat: int, random_count: int, scratch: Path) -> Section:
    shipped = shipped_modules(scratch)
    drawn = random_modules(random_count)
    tools = _formatters()
    on_shipped = _each(tools, shipped, repeat)
    on_random = _each(tools, drawn, 0)
    agreement, meets = _agreement(on_shipped[1:], on_random, shipped, drawn, tools.dev_ruff)
    body = f"""`benchmarks/formatter.py`: the {len(shipped)} agent modules `robospec build specs/`
writes, and {len(drawn)} random modules of the constructs the emitter writes
(tests/test_layout.py's strategy, the same every run), laid out by robospec/emit/layout and,
from the same trees, by black (`black.format_str`, line length 100) and by `ruff format
--line-length 100 -`. A formatter reads source: the benchmark's `formatter_input`
({_adapter_lines()} lines over `ast.unparse`, robospec's literals and its import order) writes
each tree with what the layout decides and a formatter cannot know (strings escaped as robospec
escapes them, numbers as the spec wrote them, docstrings wrapped, paragraphs and import
sections set off by blank lines).

{agreement}

{_speed(on_shipped, tools, repeat, scratch)}

{_size(tools)}
"""
    if tools.skipped:
        body += "\nNot measured: " + "; ".join(tools.skipped) + ".\n"
    body += f"\nTarget: the layout writes every module as {tools.dev_ruff} does: "
    body += "met.\n" if meets else "**missed**.\n"
    return Section(TITLE, body, meets)


def _agreement(
    on_shipped: list[Formatted],
    on_random: list[Formatted],
    shipped: list[Module],
    drawn: list[Module],
    dev_ruff: str,
) -> tuple[str, bool]:
    """How many modules each formatter writes as the layout does, each one's first difference,
    and whether the dev extra's ruff agrees on every one."""
    rows: list[str] = []
    differences: list[tuple[str, str]] = []
    described: list[str] = []
    meets = True
    for on_one, on_other in zip(on_shipped, on_random, strict=True):
        pairs = list(zip(shipped + drawn, on_one.texts + on_other.texts, strict=True))
        same_shipped = sum(text == m.layout for m, text in pairs[: len(shipped)])
        same_random = sum(text == m.layout for m, text in pairs[len(shipped) :])
        rows.append(
            f"| {on_one.label} | {same_shipped}/{len(shipped)} | {same_random}/{len(drawn)} |"
        )
        misses = [(m, text) for m, text in pairs if text != m.layout]
        if on_one.label == dev_ruff:
            meets = not misses
        if not misses:
            continue
        module, text = misses[0]
        diff = first_difference(module.layout, text)
        seen = next((label for label, earlier in differences if earlier == diff), None)
        differences.append((on_one.label, diff))
        described.append(
            f"{on_one.label}: the same first difference as {seen}."
            if seen
            else f"{on_one.label}, first difference ({module.name}):\n\n```diff\n{diff}\n```"
        )
    table = "\n".join(
        [
            "| formatter | shipped modules as the layout writes them | random modules |",
            "| --- | ---: | ---: |",
            *rows,
        ]
    )
    return table + "\n\n" + ("\n\n".join(described) or "No difference."), meets


def _speed(on_shipped: list[Formatted], tools: _Formatters, repeat: int, scratch: Path) -> str:
    """The time per module and the import of each formatter; `build`'s time; a warm register."""
    imports = {"robospec/emit/layout": import_cost("robospec.emit.layout", repeat)}
    if tools.black:
        imports[f"black {BLACK}"] = import_cost("black", repeat, tools.black)
    rows = []
    for result in on_shipped:
        if result.seconds is None:
            continue
        seconds = result.seconds
        imported = imports.get(result.label)
        import_ms = f"{imported * 1e3:.0f}" if imported is not None else "— (a process per module)"
        rows.append(
            f"| {result.label} | {statistics.median(seconds) * 1e3:.1f} | "
            f"{max(seconds) * 1e3:.1f} | {sum(seconds) * 1e3:.0f} | {import_ms} |"
        )
    build = sample(
        [PYTHON, "-m", "robospec", "build", "specs/", "-o", str(scratch / "built")],
        child_env(),
        repeat,
    )
    assert build.returncode == 0, build.output
    warm_cache = child_env(ROBOSPEC_CACHE_DIR=str(scratch / "register-cache"))
    register = sample([PYTHON, "-c", _WARM_REGISTER], warm_cache, 1)  # the warm-up fills it
    assert register.returncode == 0, register.output
    warm_imports = ast.literal_eval(register.output.strip().splitlines()[-1])
    warm = ", ".join(warm_imports) or "none"
    layout_share = sum(on_shipped[0].seconds or []) / build.median
    count = len(on_shipped[0].texts)
    return f"""Time to lay out one shipped module (median of {repeat} in this process; ruff: a
process per module, as it would run), and the import on top of what `build` has imported by
then (a fresh process, median of {repeat}):

| formatter | median ms | slowest ms | all {count} ms | import ms |
| --- | ---: | ---: | ---: | ---: |
{chr(10).join(rows)}

`robospec build specs/` ({count} modules) takes {build.median:.2f} s (median of {repeat},
spread {build.spread}); laying the modules out is {layout_share * 100:.0f}% of it. A warm
`robospec.register('specs/')` lays nothing out (the modules of robospec.emit, black and ruff
it imports: {warm})."""


def _size(tools: _Formatters) -> str:
    """What the layout is, and what ruff and black would add to the core install."""
    core_bytes, core_names = core_install_bytes()
    layout_files = sorted(LAYOUT.glob("*.py"))
    layout_lines = sum(len(f.read_text(encoding="utf-8").splitlines()) for f in layout_files)
    layout_bytes = sum(f.stat().st_size for f in layout_files)
    ruff_bytes = _distribution_bytes(importlib.metadata.distribution("ruff"))
    rows = [
        f"| robospec/emit/layout ({len(layout_files)} modules, {layout_lines} lines) | "
        f"{layout_bytes / 1e6:.2f} | — |",
        f"| {tools.dev_ruff} | {ruff_bytes / 1e6:.1f} | ruff |",
    ]
    if tools.black:
        black_bytes, black_names = added_bytes(tools.black, core_names)
        rows.append(f"| black {BLACK} | {black_bytes / 1e6:.1f} | {', '.join(black_names)} |")
    return f"""What each would add to the core install (robospec's dependencies as installed
here: {core_bytes / 1e6:.1f} MB):

| what | MB | distributions the core does not have |
| --- | ---: | --- |
{chr(10).join(rows)}"""


def _adapter_lines() -> int:
    """The lines of this file's ``formatter_input`` and the helpers only it uses."""
    source = Path(__file__).read_text(encoding="utf-8")
    start = source.index("def formatter_input")
    end = source.index("def shipped_modules")
    return len([line for line in source[start:end].splitlines() if line.strip()])


if __name__ == "__main__":
    section = measure(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
    print(section.markdown())
    sys.exit(0 if section.meets_target else 1)
