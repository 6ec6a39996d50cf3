from __future__ import annotations

from pathlib import Path

from robospec.codes import CODES
from robospec.docgen import diagnostics_markdown

ROOT = Path(__file__).resolve().parent.parent


def test_the_diagnostics_reference_is_generated_from_the_code() -> None:
    committed = (ROOT / "docs/diagnostics.md").read_text(encoding="utf-8")
    assert committed == diagnostics_markdown(), (
        "run: python -m robospec.docgen > docs/diagnostics.md"
    )


def test_every_code_is_documented_and_codes_are_well_formed() -> None:
    text = (ROOT / "docs/diagnostics.md").read_text(encoding="utf-8")
    for code in CODES:
        assert f"| {code} |" in text
        assert len(code) == 5 and code.startswith("RS") and code[2:].isdigit()


def test_every_example_spec_carries_the_schema_modeline() -> None:
    for spec in (ROOT / "specs").rglob("*"):
        if spec.suffix in (".yaml", ".yml"):
            assert spec.read_text().startswith("# yaml-language-server: $schema="), spec
        elif spec.suffix == ".toml":
            assert spec.read_text().startswith("#:schema "), spec
