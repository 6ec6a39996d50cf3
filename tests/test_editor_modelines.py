"""Every spec under specs/ opens in an editor with the schema attached: its first line is the
modeline that yaml-language-server (YAML) or taplo (TOML) reads, and the relative path in it
reaches schemas/robospec.schema.json from where the spec lives."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import SCHEMA, SPECS

MODELINE_PREFIX = {
    ".yaml": "# yaml-language-server: $schema=",
    ".yml": "# yaml-language-server: $schema=",
    ".toml": "#:schema ",
}
SPEC_FILES = sorted(p for p in SPECS.rglob("*") if p.suffix in MODELINE_PREFIX)


def test_specs_folder_has_yaml_and_toml_specs() -> None:
    # guards the parametrized test below against passing vacuously on an empty glob
    assert {p.suffix for p in SPEC_FILES} >= {".yaml", ".toml"}


@pytest.mark.parametrize("spec", SPEC_FILES, ids=lambda p: p.relative_to(SPECS).as_posix())
def test_spec_first_line_is_a_modeline_reaching_the_schema(spec: Path) -> None:
    first_line = spec.read_text().split("\n", 1)[0]
    prefix = MODELINE_PREFIX[spec.suffix]
    assert first_line.startswith(prefix), f"{spec.name}: first line {first_line!r}"
    target = first_line.removeprefix(prefix).strip()
    assert not Path(target).is_absolute() and "://" not in target, (
        f"{spec.name}: the schema path must be relative to the spec, got {target!r}"
    )
    assert (spec.parent / target).resolve() == SCHEMA, f"{spec.name}: {target!r}"
