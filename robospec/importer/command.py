"""What `robospec import` does, apart from argument parsing: import, then write the spec."""

from __future__ import annotations

from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import IMPORT_OUTPUT_EXISTS
from robospec.files import write_atomically


def run_import(
    target: str, uid: str | None, out: Path | None, force: bool
) -> tuple[str | None, list[Diagnostic]]:
    """The spec text (also written to ``out`` when given) and the diagnostics."""
    from robospec.model.uid import invalid_uid

    problem = invalid_uid(uid) if uid is not None else None
    if problem is not None:
        return None, [problem]
    if out is not None and out.exists() and not force:
        return None, [
            error(
                Location(str(out)),
                IMPORT_OUTPUT_EXISTS,
                f"{out} already exists; robospec import does not overwrite it",
                "pass --force to replace it",
            )
        ]
    from robospec.importer import import_agent

    out_dir = out.parent if out is not None else Path.cwd()
    result = import_agent(target, uid, out_dir)
    if result.text is not None and out is not None:
        write_atomically(out, result.text)
    return result.text, result.diagnostics
