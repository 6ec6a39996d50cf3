"""The counts every format ends with: errors, warnings and files checked."""

from __future__ import annotations

from collections.abc import Sequence

from robospec.diagnostics import Diagnostic, Severity


def summary(diagnostics: Sequence[Diagnostic], files: int) -> dict[str, int]:
    return {
        "errors": sum(d.severity is Severity.ERROR for d in diagnostics),
        "warnings": sum(d.severity is Severity.WARNING for d in diagnostics),
        "notes": sum(d.severity is Severity.NOTE for d in diagnostics),
        "files": files,
    }


def summary_line(diagnostics: Sequence[Diagnostic], files: int) -> str:
    counts = summary(diagnostics, files)
    notes = f", {counts['notes']} note(s)" if counts["notes"] else ""
    return (
        f"{counts['files']} file(s) checked: {counts['errors']} error(s), "
        f"{counts['warnings']} warning(s){notes}"
    )
