"""One problem type for every stage: a located, coded diagnostic.

Every stage of the pipeline reports problems as :class:`Diagnostic` records and never raises
on bad input; the CLI and :func:`robospec.register` decide what to do with them.
"""

from __future__ import annotations

import enum
from collections.abc import Collection, Iterable
from dataclasses import dataclass


class Severity(str, enum.Enum):
    ERROR = "error"
    WARNING = "warning"
    # what robospec did on the user's behalf (a mend it applied to a derived description):
    # never a problem, always said where it happened
    NOTE = "note"


@dataclass(frozen=True, order=True)
class Location:
    """A 1-based position in a file (a spec, or a robot description)."""

    file: str
    line: int = 1
    column: int = 1


@dataclass(frozen=True)
class Diagnostic:
    location: Location
    code: str
    severity: Severity
    message: str
    hint: str | None = None

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    def format_text(self) -> str:
        loc = self.location
        text = (
            f"{loc.file}:{loc.line}:{loc.column}: {self.severity.value}[{self.code}] {self.message}"
        )
        if self.hint:
            text += f"\n    hint: {self.hint}"
        return text

    def to_json(self) -> dict[str, object]:
        loc = self.location
        return {
            "file": loc.file,
            "line": loc.line,
            "column": loc.column,
            "code": self.code,
            "severity": self.severity.value,
            "message": self.message,
            "hint": self.hint,
        }


def line_column(text: str, offset: int) -> tuple[int, int]:
    """The 1-based line and column of character ``offset`` in ``text``."""
    line_start = text.rfind("\n", 0, offset) + 1
    return text.count("\n", 0, offset) + 1, offset - line_start + 1


def error(location: Location, code: str, message: str, hint: str | None = None) -> Diagnostic:
    return Diagnostic(location, code, Severity.ERROR, message, hint)


def warning(location: Location, code: str, message: str, hint: str | None = None) -> Diagnostic:
    return Diagnostic(location, code, Severity.WARNING, message, hint)


def note(location: Location, code: str, message: str, hint: str | None = None) -> Diagnostic:
    return Diagnostic(location, code, Severity.NOTE, message, hint)


def has_errors(diagnostics: Iterable[Diagnostic]) -> bool:
    return any(d.is_error for d in diagnostics)


def without_codes(diagnostics: Iterable[Diagnostic], codes: Collection[str]) -> list[Diagnostic]:
    """``diagnostics`` less the warnings and notes whose codes are in ``codes``: an error is
    never left out."""
    return [d for d in diagnostics if d.is_error or d.code not in codes]


def sort_key(d: Diagnostic) -> tuple[str, int, int, str]:
    return (d.location.file, d.location.line, d.location.column, d.code)


class SpecError(Exception):
    """Raised by :func:`robospec.register` when a spec has errors; carries the diagnostics."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        self.diagnostics = diagnostics
        lines = [d.format_text() for d in diagnostics if d.is_error]
        super().__init__("\n".join(lines) or "spec has errors")
