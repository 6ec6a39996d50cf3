"""GitHub Actions workflow commands: one ``::error``/``::warning`` annotation per diagnostic, shown
on the pull request's diff, then the summary line for the log.

Escaping follows the runner's rules (actions/toolkit ``command.ts``): in the message ``%``, CR
and LF are percent-encoded; in properties also ``:`` and ``,``, which would end a property."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from robospec.diagnostics import Diagnostic, Severity
from robospec.reporting.summary import summary_line


def escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def annotation_path(file: str, root: Path | None = None) -> str:
    """GitHub matches annotations to files by their path in the checkout (the working directory
    of the step), with forward slashes: an absolute path inside it is made relative."""
    path = Path(file)
    if not path.is_absolute():
        return file.replace("\\", "/")
    try:
        return Path(os.path.normpath(path)).relative_to(root or Path.cwd().resolve()).as_posix()
    except ValueError:  # outside the checkout: GitHub cannot place it; keep the whole path
        return path.as_posix()


def annotation(d: Diagnostic) -> str:
    loc = d.location
    properties = {
        "file": annotation_path(loc.file),
        "line": str(loc.line),
        "col": str(loc.column),
        "title": d.code,
    }
    props = ",".join(f"{key}={escape_property(value)}" for key, value in properties.items())
    message = d.message if not d.hint else f"{d.message}\nhint: {d.hint}"
    # GitHub's workflow commands say "notice" where robospec says "note"
    command = "notice" if d.severity is Severity.NOTE else d.severity.value
    return f"::{command} {props}::{escape_data(message)}"


def render(diagnostics: Sequence[Diagnostic], files: int) -> str:
    return "\n".join([*(annotation(d) for d in diagnostics), summary_line(diagnostics, files)])
