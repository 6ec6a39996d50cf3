"""``robospec schema --for SPEC``: compile SPEC, then narrow the spec schema to its robot."""

from __future__ import annotations

from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error, has_errors
from robospec.diagnostics.codes import INTERNAL_ERROR


def narrowed_schema_text(spec_path: Path) -> tuple[str | None, list[Diagnostic]]:
    """The narrowed schema's text, or None and the diagnostics that stopped it.
    ``spec_path`` is one spec file (the caller rejects folders as a usage error)."""
    from robospec.pipeline import compile_all
    from robospec.schema import schema_text, spec_schema
    from robospec.schema.narrow import narrow_schema, robot_names

    compiled, diagnostics = compile_all([spec_path])
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    if has_errors(diagnostics):
        return None, diagnostics
    if len(compiled) != 1 or not compiled[0].ok:
        # every failed compile reports an error; reaching here is a bug of ours
        message = f"internal error: {spec_path} compiled to no robot and no error"
        diagnostics.append(error(Location(str(spec_path)), INTERNAL_ERROR, message))
        return None, diagnostics
    narrowed = narrow_schema(spec_schema(), robot_names(compiled[0]))
    return schema_text(narrowed), diagnostics
