"""A uid given on the command line (``robospec import --uid``, ``robospec new --uid``), checked
against the spec model's own pattern before anything is written, and where such an argument
stands in the command line, for the diagnostics about it."""

from __future__ import annotations

import re
from collections.abc import Sequence

from robospec.diagnostics import Diagnostic, Location, error
from robospec.model.names import UID_PATTERN

COMMAND_LINE = "<command line>"
PROGRAM = "robospec"


def invalid_uid(uid: str, at: Location | None = None) -> Diagnostic | None:
    """RS105 when ``uid`` could not be a spec's uid, else None; reported at ``at`` (default:
    ``<uid>``)."""
    if re.match(UID_PATTERN, uid):
        return None
    return error(
        at or Location("<uid>"),
        "RS105",
        f"invalid uid {uid!r}",
        "use letters, digits, '_', '-' and '.', starting with a letter or digit",
    )


def argument_location(option: str, value: str, arguments: Sequence[str]) -> Location:
    """Where ``option``'s ``value`` stands in the command line ``robospec ARGUMENTS...`` (the
    arguments joined by single spaces): ``<command line>:1:COLUMN``, the column of the value's
    first character; column 1 when it is not found there."""
    column = len(PROGRAM) + 2
    found = 0
    for index, argument in enumerate(arguments):
        if argument == value and index > 0 and arguments[index - 1] == option:
            found = column
        elif argument == f"{option}={value}":
            found = column + len(option) + 1
        column += len(argument) + 1
    return Location(COMMAND_LINE, 1, found or 1)
