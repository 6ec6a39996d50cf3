"""Where a value given on the command line stands in it (``robospec new --uid X``), so that a
diagnostic about it points at the argument as one about a spec points at its key."""

from __future__ import annotations

from collections.abc import Sequence

from robospec.diagnostics import Location

COMMAND_LINE = "<command line>"
PROGRAM = "robospec"


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
