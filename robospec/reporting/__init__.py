"""Diagnostics out, in the format a reader needs: a person at a terminal (:mod:`.text`), a tool
(:mod:`.as_json`, the JSON contract of DESIGN.md), GitHub Actions annotations (:mod:`.github`)
or code scanning (:mod:`.sarif`). Every format sorts the diagnostics the same way."""

from __future__ import annotations

import enum
from collections.abc import Sequence

from robospec.diagnostics import Diagnostic, sort_key
from robospec.reporting.summary import summary, summary_line


class Format(str, enum.Enum):
    text = "text"
    json = "json"
    github = "github"
    sarif = "sarif"


def render(diagnostics: Sequence[Diagnostic], files: int, fmt: str, *, color: bool = False) -> str:
    """The report of ``diagnostics`` over ``files`` checked files; ``color`` only affects text."""
    ordered = sorted(diagnostics, key=sort_key)
    # each format is imported when asked for: SARIF's package metadata alone costs more
    # than a whole `robospec validate` of a small spec
    kind = Format(fmt)
    if kind is Format.json:
        from robospec.reporting import as_json

        return as_json.render(ordered, files)
    if kind is Format.github:
        from robospec.reporting import github

        return github.render(ordered, files)
    if kind is Format.sarif:
        from robospec.reporting import sarif

        return sarif.render(ordered)
    from robospec.reporting import text

    return text.render(ordered, files, color=color)


__all__ = ["Format", "render", "summary", "summary_line"]
