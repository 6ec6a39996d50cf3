"""Acceptance tests driven by example files: tests/specs/positive/ must validate cleanly, and
each file in tests/specs/negative/ must produce the diagnostic its first line announces:
``# expect: CODE at LINE:COLUMN [text the message or hint contains]``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from robospec.diagnostics import has_errors
from robospec.pipeline import compile_all, compile_spec

HERE = Path(__file__).parent / "specs"
EXPECT = re.compile(r"# expect: (RS\d{3}) at (\d+):(\d+)\s*(.*)")


@pytest.mark.parametrize("path", sorted((HERE / "positive").iterdir()), ids=lambda p: p.name)
def test_positive_example_validates_without_errors(path: Path) -> None:
    result = compile_spec(path)
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    assert result.robot is not None


@pytest.mark.parametrize("path", sorted((HERE / "negative").iterdir()), ids=lambda p: p.name)
def test_negative_example_reports_the_announced_diagnostic(path: Path) -> None:
    match = EXPECT.match(path.read_text().splitlines()[0])
    assert match, f"{path.name} needs an '# expect:' first line"
    code, line, column, text = match.group(1), int(match.group(2)), int(match.group(3)), match[4]
    result = compile_spec(path)
    found = [(d.code, d.location.line, d.location.column) for d in result.diagnostics]
    assert (code, line, column) in found, [d.format_text() for d in result.diagnostics]
    diagnostic = next(d for d in result.diagnostics if d.code == code)
    assert text in diagnostic.message + " " + (diagnostic.hint or "")
    assert diagnostic.location.file == str(path)


def test_every_shipped_spec_validates() -> None:
    compiled, diagnostics = compile_all([Path(__file__).parent.parent / "specs"])
    assert len(compiled) >= 4
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    assert not has_errors(diagnostics), [d.format_text() for d in diagnostics]


def test_a_field_missing_from_an_extended_controller_is_reported_once_at_the_base() -> None:
    # arm_delta extends arm_pos, which lacks stiffness: the child's copy of the gap is not news
    result = compile_spec(HERE / "negative" / "extends_missing_field.yaml")
    assert [(d.code, d.location.line) for d in result.diagnostics] == [("RS103", 8)]
