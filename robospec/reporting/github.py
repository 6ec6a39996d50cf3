"""GitHub Actions workflow commands: one ``::error``/``::warning`` annotation per diagnostic, shown
on the pull request's diff, then the summary line for the log.

Escaping follows the runner's rules (actions/toolkit ``command.ts``): in the message ``%``, CR
and LF are percent-encoded; in properties also ``:`` and ``,``, which would end a property."""

from __future__ import annotations

from collections.abc import Sequence

from robospec.diagnostics import Diagnostic
from robospec.reporting.summary import summary_line


def escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def annotation(d: Diagnostic) -> str:
    loc = d.location
    properties = {
        # GitHub matches annotations to files by repository-relative paths with forward slashes
        "file": loc.file.replace("\\", "/"),
        "line": str(loc.line),
        "col": str(loc.column),
        "title": d.code,
    }
    props = ",".join(f"{key}={escape_property(value)}" for key, value in properties.items())
    message = d.message if not d.hint else f"{d.message}\nhint: {d.hint}"
    return f"::{d.severity.value} {props}::{escape_data(message)}"


def render(diagnostics: Sequence[Diagnostic], files: int) -> str:
    return "\n".join([*(annotation(d) for d in diagnostics), summary_line(diagnostics, files)])
