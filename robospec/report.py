"""Diagnostics out: text (one line per problem) or JSON, per DESIGN's contract."""

from __future__ import annotations

import json
from collections.abc import Sequence

from robospec.diagnostics import Diagnostic, Severity, sort_key


def summary(diagnostics: Sequence[Diagnostic], files: int) -> dict[str, int]:
    return {
        "errors": sum(d.severity is Severity.ERROR for d in diagnostics),
        "warnings": sum(d.severity is Severity.WARNING for d in diagnostics),
        "files": files,
    }


def render(diagnostics: Sequence[Diagnostic], files: int, fmt: str) -> str:
    ordered = sorted(diagnostics, key=sort_key)
    counts = summary(ordered, files)
    if fmt == "json":
        return json.dumps(
            {"diagnostics": [d.to_json() for d in ordered], "summary": counts}, indent=2
        )
    lines = [d.format_text() for d in ordered]
    lines.append(
        f"{counts['files']} file(s) checked: {counts['errors']} error(s), "
        f"{counts['warnings']} warning(s)"
    )
    return "\n".join(lines)
