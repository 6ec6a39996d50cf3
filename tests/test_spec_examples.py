"""Acceptance tests driven by example files.

The failing examples are the catalogue behind the docs' per-code pages, docs/examples/codes/
(robospec.docgen.code_examples): ``RSxxx/fail.<ext>`` and ``RSxxx/fail_*.<ext>``. Each reports
exactly the diagnostics that docs/examples/codes/expected.toml lists for it, in order: code,
file, line and column, and words of the message or hint. tests/specs/positive/ holds specs that
must validate cleanly and that no shipped robot covers (hooks, helpers, never_collide, ...).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import NamedTuple

import pytest
import tomllib
from conftest import CODE_EXAMPLES, DOCS, POSITIVE_SPECS, SPECS, spec_params

from robospec.diagnostics import Diagnostic, has_errors
from robospec.docgen.code_examples import EXPECTED_FILE, failing_example_paths, run_example
from robospec.pipeline import compile_all, compile_spec

FAILING = failing_example_paths(DOCS)
EXPECTED: dict[str, dict[str, list[str]]] = tomllib.loads(
    (CODE_EXAMPLES / EXPECTED_FILE).read_text(encoding="utf-8")
)
ENTRY = re.compile(
    r"(?P<code>RS\d{3}) at (?:(?P<file>\S+):)?(?P<line>\d+):(?P<column>\d+)(?: (?P<words>.+))?"
)


class Expected(NamedTuple):
    code: str
    file: str  # relative to the example's folder
    line: int
    column: int
    words: str

    @classmethod
    def parse(cls, entry: str, example: Path) -> Expected:
        match = ENTRY.fullmatch(entry)
        assert match, f"{EXPECTED_FILE}: {entry!r} is not 'CODE at [FILE:]LINE:COLUMN [words]'"
        return cls(
            match["code"],
            match["file"] or example.name,
            int(match["line"]),
            int(match["column"]),
            match["words"] or "",
        )

    def found_in(self, diagnostic: Diagnostic) -> bool:
        location = diagnostic.location
        return (diagnostic.code, location.file, location.line, location.column) == self[:4] and (
            self.words in f"{diagnostic.message} {diagnostic.hint or ''}"
        )


def _name(path: Path) -> str:
    return f"{path.parent.name}/{path.name}"


def test_every_failing_example_has_its_expectations_and_each_expectation_its_example() -> None:
    listed = {f"{code}/{name}" for code, names in EXPECTED.items() for name in names}
    assert listed == {_name(path) for path in FAILING}
    assert len(FAILING) >= 60


@pytest.mark.parametrize("path", FAILING, ids=_name)
def test_failing_example_reports_exactly_the_expected_diagnostics_where_expected(
    path: Path,
) -> None:
    expected = [Expected.parse(entry, path) for entry in EXPECTED[path.parent.name][path.name]]
    found = run_example(path).diagnostics
    shown = [d.format_text() for d in found]
    assert len(found) == len(expected), shown
    for want, diagnostic in zip(expected, found, strict=True):
        assert want.found_in(diagnostic), (want, shown)
    assert path.parent.name in {d.code for d in found}, "an example reports its folder's code"


@pytest.mark.parametrize("path", spec_params(sorted(POSITIVE_SPECS.iterdir())))
def test_positive_example_validates_without_errors(path: Path) -> None:
    result = compile_spec(path)
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    assert result.robot is not None


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_every_shipped_spec_validates() -> None:
    compiled, diagnostics = compile_all([SPECS])
    assert len(compiled) >= 4
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    assert not has_errors(diagnostics), [d.format_text() for d in diagnostics]
