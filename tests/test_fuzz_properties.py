"""Property-based tests over the loader, the model and the CLI (issue 6 item 2).

Whatever the input — arbitrary bytes named .yaml or .toml, YAML-ish token soup, or a real spec
from specs/ and tests/specs/positive, in YAML and in TOML, mutated (keys deleted, renamed or
reordered, values swapped for other types, huge, negative, NaN, unicode or empty; lines
deleted, duplicated, swapped or cut) — robospec answers with diagnostics that have a known
code, a line and a column >= 1 and a line the named file has, never an internal error (RS900,
a bug of ours caught by compile_spec's last-resort handler) nor an exception; the CLI exits 0 or 1.

The budget is fixed, so CI time is bounded; the examples are new each run, drawn from the
run's seed (tests/conftest.py prints it: ``ROBOSPEC_HYPOTHESIS_SEED=N`` draws a run's examples
again). Every seed spec is also mutated as TOML (its data written as TOML; TOML has no null, so
a spec with ``lower: null`` starts out with an error there), so both readers see every robot.
Specs that extend a Python class are no seeds: compiling them imports ManiSkill, and a mutated
``extends`` would import whatever module it came to name. ``ROBOSPEC_FUZZ_SCALE=N`` multiplies
the example counts: the long-running fuzz target (fuzz/fuzz_validate.py; docs/hardening.md)
sets 5 or more, the fast loop (scripts/test --fast) 0.2.
"""

from __future__ import annotations

import copy
import functools
import json
import math
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import tomllib
from conftest import FUZZ_SCALE, ROOT, extends_python, invoke_robospec
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robospec.diagnostics import Diagnostic
from robospec.diagnostics.codes import CODES
from robospec.load.reader import SPEC_SUFFIXES, parse_spec_bytes, read_spec
from robospec.pipeline import compile_spec


def budget(examples: int) -> settings:
    """A fixed budget in CI, ``FUZZ_SCALE`` times more when fuzzing; the examples come from the
    run's seed (conftest.py), so they differ from run to run and a run can be repeated."""
    return settings(
        max_examples=max(round(examples * FUZZ_SCALE), 1),
        deadline=None,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


@dataclass(frozen=True)
class Seed:
    """A spec to mutate: a file of the repository, or its data written as TOML (``raw``),
    standing where the file stands so that its relative paths resolve."""

    path: Path
    suffix: str  # of the file it stands for: ".yaml" or ".toml"

    @property
    def name(self) -> str:
        return self.path.stem + self.suffix

    @property
    def converted(self) -> bool:
        """Whether this seed is a YAML file's data written as TOML."""
        return self.suffix != self.path.suffix

    @property
    def raw(self) -> bytes:
        return _seed_bytes(self.path, self.suffix)

    def __repr__(self) -> str:  # shown in a falsifying example
        return f"Seed({self.path.relative_to(ROOT)} as {self.suffix[1:]})"


@functools.cache
def _seed_bytes(path: Path, suffix: str) -> bytes:
    # made when a test first draws the seed, not at collection: parsing every YAML spec costs
    # seconds, in each worker
    if suffix == path.suffix:
        return path.read_bytes()
    loaded, _ = read_spec(path)
    assert loaded is not None, path
    return _dump_toml(loaded.data)


def _seed_specs() -> list[Seed]:
    found = [*sorted((ROOT / "specs").glob("*.toml")), *sorted((ROOT / "specs").rglob("*.yaml"))]
    found += sorted((ROOT / "tests/specs/positive").glob("*.yaml"))
    seeds = []
    for path in found:
        if b"robospec" not in path.read_bytes()[:400] or extends_python(path):
            continue
        seeds.append(Seed(path, path.suffix))
        if path.suffix != ".toml":
            seeds.append(Seed(path, ".toml"))
    return seeds


# -- checking diagnostics -------------------------------------------------------------------


def _line_count(raw: bytes) -> int:
    return max(len(raw.decode("utf-8", "replace").splitlines()), 1)


def assert_well_formed(diagnostics: list[Diagnostic], files: dict[str, bytes]) -> None:
    """Every diagnostic: a known code other than RS900, line and column >= 1, and — in a file
    whose bytes we know — a line that file has."""
    for d in diagnostics:
        assert d.code in CODES, d.format_text()
        assert d.code != "RS900", d.format_text()
        assert d.location.line >= 1 and d.location.column >= 1, d.format_text()
        raw = files.get(d.location.file)
        if raw is not None:
            assert d.location.line <= _line_count(raw), d.format_text()


def _assert_json_well_formed(output: str, files: dict[str, bytes]) -> None:
    for d in json.loads(output)["diagnostics"]:
        assert d["code"] in CODES and d["code"] != "RS900", d
        assert d["line"] >= 1 and d["column"] >= 1, d
        if d["file"] in files:
            assert d["line"] <= _line_count(files[d["file"]]), d


# -- a scratch copy of a seed's folder --------------------------------------------------------


class Scratch:
    """A temporary folder standing in for a seed spec's own: its sub-folders (robots/...) are
    linked in, so relative description paths resolve as they do beside the seed."""

    def __init__(self, seed: Seed, suffix: str | None = None) -> None:
        self._dir = tempfile.TemporaryDirectory(prefix="robospec-fuzz-")
        self.folder = Path(self._dir.name)
        for child in seed.path.parent.iterdir():
            if child.is_dir():
                (self.folder / child.name).symlink_to(child, target_is_directory=True)
        self.path = self.folder / Path(seed.name).with_suffix(suffix or seed.suffix)

    def write(self, raw: bytes) -> Path:
        self.path.write_bytes(raw)
        return self.path

    def __enter__(self) -> Scratch:
        return self

    def __exit__(self, *_: object) -> None:
        self._dir.cleanup()


# -- strategies -------------------------------------------------------------------------------

_TEXT = st.text(st.characters(blacklist_categories=("Cs",)), max_size=12)
HOSTILE_VALUES: st.SearchStrategy[Any] = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.sampled_from([-1, 0, 10**300, -(10**300)]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -0.0, 5e-324]),
    _TEXT,
    st.sampled_from(["", " ", "x" * 5000, "pi/0", "1e999", "ünïcødé ✓", "\u202e", "*", "[", "{"]),
    st.lists(st.integers(min_value=-3, max_value=3), max_size=4),
    st.dictionaries(_TEXT, st.integers(min_value=-3, max_value=3), max_size=3),
)

# Pieces that, concatenated, make text a YAML or TOML parser finds interesting.
_TOKENS = [
    *"abc:=-[]{}&*!|>'\"#,?. \n\t\r019",
    "robospec",
    "uid",
    "description",
    "controllers",
    "joints",
    "\ufeff",
    "\x00",
    "\x85",
    "\u2028",
    "<<",
    "---",
    "...",
    "&a ",
    "*a",
    "!!str ",
    "!!binary ",
    "!tag ",
    "{x: [1]}: ",
    "[[",
    "]]",
    '"""',
    "'''",
    "1979-05-27",
    "1e999",
    "0x1F",
    "9" * 40,
]
SOUP = st.lists(st.sampled_from(_TOKENS), max_size=120).map("".join)


def _containers(node: Any, path: tuple[Any, ...] = ()) -> Iterator[tuple[Any, ...]]:
    """Paths of every dict and list in ``node``, outermost first."""
    if isinstance(node, (dict, list)):
        yield path
        items = node.items() if isinstance(node, dict) else enumerate(node)
        for key, child in items:
            yield from _containers(child, (*path, key))


def _at(node: Any, path: tuple[Any, ...]) -> Any:
    for key in path:
        node = node[key]
    return node


@st.composite
def mutated_data(draw: st.DrawFn, data: dict[str, Any]) -> dict[str, Any]:
    """``data`` after one to three mutations: delete, rename, replace or reorder."""
    data = copy.deepcopy(data)
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        container = _at(data, draw(st.sampled_from(list(_containers(data)))))
        if not container:
            continue
        keys = list(container) if isinstance(container, dict) else list(range(len(container)))
        key = draw(st.sampled_from(keys))
        operation = draw(st.sampled_from(["delete", "rename", "replace", "reorder", "wrap"]))
        if operation == "delete":
            del container[key]
        elif operation == "rename" and isinstance(container, dict):
            new = draw(st.one_of(_TEXT, st.just(str(key) + "s"), st.just(str(key).upper())))
            container[new] = container.pop(key)
        elif operation == "replace":
            container[key] = draw(HOSTILE_VALUES)
        elif operation == "reorder":
            if isinstance(container, dict):
                order = draw(st.permutations(keys))
                items = {k: container[k] for k in order}
                container.clear()
                container.update(items)
            else:
                container[:] = draw(st.permutations(container))
        else:  # wrap the value one level deeper: a list where a scalar was, and so on
            container[key] = draw(st.sampled_from([[container[key]], {"value": container[key]}]))
    return data


def _dump_toml(data: dict[str, Any]) -> bytes:
    """``data`` as TOML: a key per top-level entry, inline tables below. TOML has no null: a
    None is left out, as a key that is not given."""

    def value(node: Any) -> str:
        if isinstance(node, bool):
            return "true" if node else "false"
        if isinstance(node, int):
            return str(node)
        if isinstance(node, float):
            if math.isnan(node):
                return "nan"
            return ("-inf" if node < 0 else "inf") if math.isinf(node) else repr(node)
        if isinstance(node, str):
            return string(node)
        if isinstance(node, list):
            return "[" + ", ".join(value(item) for item in node if item is not None) + "]"
        items = (f"{string(str(k))} = {value(v)}" for k, v in node.items() if v is not None)
        return "{" + ", ".join(items) + "}"

    def string(text: str) -> str:
        # a basic string: JSON's escapes, less what TOML lacks (DEL is a control character)
        return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")

    lines = [f"{string(str(k))} = {value(v)}" for k, v in data.items() if v is not None]
    return ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")


def _dump_yaml(data: Any) -> bytes:
    import io

    from ruamel.yaml import YAML

    yaml = YAML(typ="safe", pure=True)
    yaml.allow_unicode = True
    stream = io.StringIO()
    yaml.dump(data, stream)
    return stream.getvalue().encode("utf-8", "surrogatepass")


@st.composite
def mutated_text(draw: st.DrawFn, raw: bytes) -> bytes:
    """``raw`` after one to three line-level edits: delete, duplicate, swap, cut or insert."""
    lines = raw.split(b"\n")
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        if not lines:
            break
        index = draw(st.integers(min_value=0, max_value=len(lines) - 1))
        operation = draw(st.sampled_from(["delete", "duplicate", "swap", "cut", "insert"]))
        if operation == "delete":
            del lines[index]
        elif operation == "duplicate":
            lines.insert(index, lines[index])
        elif operation == "swap":
            other = draw(st.integers(min_value=0, max_value=len(lines) - 1))
            lines[index], lines[other] = lines[other], lines[index]
        elif operation == "cut":
            at = draw(st.integers(min_value=0, max_value=len(lines[index])))
            lines[index] = lines[index][:at]
            del lines[index + 1 :]
        else:
            at = draw(st.integers(min_value=0, max_value=len(lines[index])))
            token = draw(st.sampled_from(_TOKENS)).encode("utf-8")
            lines[index] = lines[index][:at] + token + lines[index][at:]
    return b"\n".join(lines)


SEEDS = _seed_specs()


# -- the loader ---------------------------------------------------------------------------


@budget(300)
@given(raw=st.binary(max_size=600), fmt=st.sampled_from(["yaml", "toml"]))
def test_arbitrary_bytes_load_into_data_or_located_diagnostics(raw: bytes, fmt: str) -> None:
    loaded, diagnostics = parse_spec_bytes(raw, "spec." + fmt, fmt)
    assert (loaded is None) == bool(diagnostics)
    assert_well_formed(diagnostics, {"spec." + fmt: raw})


@budget(400)
@given(text=SOUP, fmt=st.sampled_from(["yaml", "toml"]))
def test_token_soup_loads_into_data_or_located_diagnostics(text: str, fmt: str) -> None:
    raw = text.encode("utf-8", "surrogatepass")
    loaded, diagnostics = parse_spec_bytes(raw, "spec." + fmt, fmt)
    assert (loaded is None) == bool(diagnostics)
    assert_well_formed(diagnostics, {"spec." + fmt: raw})
    if loaded is not None:
        assert isinstance(loaded.data, dict)
        for path in loaded.source.keys:
            line, column = loaded.source.keys[path]
            assert 1 <= line <= _line_count(raw) and column >= 1, path


# -- the model (the whole pipeline behind it) ----------------------------------------------


def _compile(seed: Seed, raw: bytes, suffix: str | None = None) -> None:
    with Scratch(seed, suffix) as scratch:
        path = scratch.write(raw)
        result = compile_spec(path)
        assert_well_formed(result.diagnostics, {str(path): raw})


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@budget(150)
@given(data=st.data(), seed=st.sampled_from(SEEDS), fmt=st.sampled_from([".yaml", ".toml"]))
def test_mutated_spec_data_gives_located_diagnostics(
    data: st.DataObject, seed: Seed, fmt: str
) -> None:
    loaded, diagnostics = parse_spec_bytes(seed.raw, seed.name, seed.suffix[1:])
    assert loaded is not None, diagnostics
    mutated = data.draw(mutated_data(_plain(loaded.data)))
    _compile(seed, _dump_yaml(mutated) if fmt == ".yaml" else _dump_toml(mutated), fmt)


@budget(150)
@given(data=st.data(), seed=st.sampled_from(SEEDS))
def test_mutated_spec_text_gives_located_diagnostics(data: st.DataObject, seed: Seed) -> None:
    raw = data.draw(mutated_text(seed.raw))
    _compile(seed, raw)


def test_the_seeds_cover_both_formats_and_the_shipped_specs() -> None:
    assert {s.suffix for s in SEEDS} == {".yaml", ".toml"}
    assert all(s.suffix in SPEC_SUFFIXES for s in SEEDS)
    assert len(SEEDS) >= 40
    assert sum(s.suffix == ".toml" for s in SEEDS) >= 20  # every robot, in TOML too


def _plain(node: Any) -> Any:
    """Loaded data as plain dicts, lists, strings and numbers (the loaders keep subclasses that
    carry where each value was, which the YAML writer cannot represent)."""
    if isinstance(node, dict):
        return {str(k): _plain(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_plain(v) for v in node]
    for kind in (bool, int, float, str):
        if isinstance(node, kind):
            return kind(node)
    return node


def _without_none(node: Any) -> Any:
    if isinstance(node, dict):
        return {k: _without_none(v) for k, v in node.items() if v is not None}
    if isinstance(node, list):
        return [_without_none(v) for v in node if v is not None]
    return node


@pytest.mark.parametrize("seed", [s for s in SEEDS if s.converted], ids=repr)
def test_a_toml_seed_reads_back_as_its_yaml_data_without_nulls(seed: Seed) -> None:
    loaded, _ = read_spec(seed.path)
    assert loaded is not None
    assert tomllib.loads(seed.raw.decode("utf-8")) == _without_none(loaded.data)


# -- the command line ---------------------------------------------------------------------


def _run(arguments: list[str]) -> Any:
    return invoke_robospec(*arguments)


@budget(12)
@given(data=st.data(), seed=st.sampled_from(SEEDS), command=st.sampled_from(["validate", "build"]))
def test_the_cli_exits_0_or_1_with_a_well_formed_report(
    data: st.DataObject, seed: Seed, command: str
) -> None:
    raw = data.draw(mutated_text(seed.raw))
    with Scratch(seed) as scratch:
        path = scratch.write(raw)
        arguments: list[str] = [command, str(path), "--format", "json"]
        out = scratch.folder / "pkg"
        if command == "build":
            arguments += ["-o", str(out)]
        result = _run(arguments)
        assert result.exit_code in (0, 1), (result.exit_code, result.output)
        assert result.exception is None or isinstance(result.exception, SystemExit)
        _assert_json_well_formed(result.stdout, {str(path): raw})
        if command == "build":
            assert out.exists() == (result.exit_code == 0)
