"""JSON: ``{"diagnostics": [...], "summary": {...}}`` — the contract in DESIGN.md."""

from __future__ import annotations

import json
from collections.abc import Sequence

from robospec.diagnostics import Diagnostic
from robospec.reporting.summary import summary


def render(diagnostics: Sequence[Diagnostic], files: int) -> str:
    report = {
        "diagnostics": [d.to_json() for d in diagnostics],
        "summary": summary(diagnostics, files),
    }
    return json.dumps(report, indent=2)
