"""Reading the numbers of a URDF as SAPIEN's parser (urchin) needs them, located.

urchin turns attributes into numbers with ``float()`` or ``numpy.fromstring(sep=" ")`` and
stops the whole load at the first one that is not a number. Values are read here the same way,
and a value that fails is a located diagnostic: RS063 when it is a xacro or roslaunch
substitution left in a URDF nobody expanded (``$(optenv ...)``, ``${...}``), RS052 otherwise.
Non-finite numbers (``nan``, ``inf``, ``1e999``) are refused too: urchin accepts them and SAPIEN
turns them into NaN poses, limits and masses.
"""

from __future__ import annotations

import math
import re

from lxml import etree

from robospec.description.source_columns import element_at
from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import INVALID_STRUCTURE, LEFTOVER_SUBSTITUTION

# The URDF attributes urchin reads as a list of numbers (element tag -> attribute -> how many):
# where a stray comma stops the load, and the `separators` mend writes spaces.
NUMBER_LISTS: dict[str, dict[str, int]] = {
    "origin": {"xyz": 3, "rpy": 3},
    "axis": {"xyz": 3},
    "box": {"size": 3},
    "mesh": {"scale": 3},
    "color": {"rgba": 4},
}
# what the hint of a number list the mend reads names
SEPARATORS_MEND = "`description: {mend: {separators: spaces}}`"

# $(find ...), $(arg ...), $(optenv ...), ${expression}: xacro's and roslaunch's syntax
_SUBSTITUTION = re.compile(r"\$[({]")
_OPTENV = re.compile(r"^\s*\$\(optenv\s+\S+\s+([^)]*)\)\s*$")


def at(path: str, element: etree._Element) -> Location:
    return element_at(path, element)


def has_substitution(text: str) -> bool:
    return _SUBSTITUTION.search(text) is not None


def substitution_error(
    path: str, element: etree._Element, what: str, shown: str, raw: str
) -> Diagnostic:
    """RS063 for a substitution SAPIEN would read as text; ``shown`` is how the message quotes
    the value (``xyz="$(optenv ...)"``)."""
    default = _OPTENV.match(raw)
    hint = (
        f'write its value: "{default.group(1).strip()}" is its default'
        if default and default.group(1).strip()
        else "describe the robot with `description: {xacro: FILE}` (robospec expands it), "
        "or write the value"
    )
    return error(
        at(path, element),
        LEFTOVER_SUBSTITUTION,
        f"{what}: {shown} is a xacro/roslaunch substitution that nobody expanded; SAPIEN's "
        "URDF parser reads it as text",
        hint,
    )


def read_floats(
    element: etree._Element,
    attribute: str,
    count: int,
    path: str,
    diagnostics: list[Diagnostic],
    what: str,
) -> list[float] | None:
    """``count`` finite numbers from ``element``'s ``attribute``; None when it is absent (no
    diagnostic: callers decide whether it is needed) or bad (RS052 or RS063)."""
    raw = element.get(attribute)
    if raw is None:
        return None
    return _numbers(raw, count, element, path, diagnostics, what, f'{attribute}="{raw}"')


def read_text_float(
    element: etree._Element, path: str, diagnostics: list[Diagnostic], what: str
) -> float | None:
    """The number an element's text holds (``<mechanicalReduction>1</...>``), as urchin's
    ``float(element.text)`` reads it; an empty element is not a number either."""
    raw = element.text or ""
    values = _numbers(raw, 1, element, path, diagnostics, what, f"'{raw.strip()}'")
    return values[0] if values else None


def _numbers(
    raw: str,
    count: int,
    element: etree._Element,
    path: str,
    diagnostics: list[Diagnostic],
    what: str,
    shown: str,
) -> list[float] | None:
    if has_substitution(raw):
        diagnostics.append(substitution_error(path, element, what, shown, raw))
        return None
    try:
        values = [float(part) for part in raw.split()]
    except ValueError:
        values = []
    if len(values) == count and all(math.isfinite(v) for v in values):
        return values
    expected = "a number" if count == 1 else f"{count} numbers"
    # a number list the separators mend reads: the hint names it
    listed = NUMBER_LISTS.get(str(element.tag), {})
    mendable = comma_separated(raw, count) is not None and any(
        element.get(a) == raw for a in listed
    )
    hint = (
        f"separate the numbers by spaces only (urchin reads no commas); {SEPARATORS_MEND} "
        "does it in a copy of the description"
        if mendable
        else None
    )
    diagnostics.append(
        error(at(path, element), INVALID_STRUCTURE, f"{what}: {shown} is not {expected}", hint)
    )
    return None


def comma_separated(raw: str, count: int) -> list[float] | None:
    """The ``count`` finite numbers ``raw`` writes with commas among its separators
    (``"1.57, 1.31 1.57"``), which urchin's space-separated reading refuses; None when it has
    no comma, is not that list, or also reads as ``count`` numbers with decimal commas
    (``"0,5 1,5 2"`` could be either: nobody can tell which the author meant)."""
    if "," not in raw or has_substitution(raw):
        return None
    values = _finite(re.split(r"[\s,]+", raw.strip().strip(",")))
    # a comma between two digits might be a decimal comma; one beside a space cannot be
    decimal = _finite(re.sub(r"(?<=\d),(?=\d)", ".", raw).split())
    if values is None or len(values) != count:
        return None
    return None if decimal is not None and len(decimal) == count else values


def _finite(parts: list[str]) -> list[float] | None:
    try:
        values = [float(part) for part in parts if part]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


class Findings:
    """Diagnostics of one set of rules, some of them folded: the same problem met on many
    elements (PR2's 32 old-style transmissions, iCub's 28 empty textures) is one diagnostic at
    the first, whose message lists the lines of the others."""

    def __init__(self) -> None:
        self.plain: list[Diagnostic] = []
        self._repeated: dict[tuple[str, str], list[Diagnostic]] = {}

    def add(self, diagnostic: Diagnostic, *, fold_as: str | None = None) -> None:
        """Add ``diagnostic``; those added with the same ``fold_as`` (a plural noun: "more
        transmissions") and code become one."""
        if fold_as is None:
            self.plain.append(diagnostic)
        else:
            self._repeated.setdefault((diagnostic.code, fold_as), []).append(diagnostic)

    def result(self) -> list[Diagnostic]:
        """Every diagnostic, by line."""
        folded = [_fold(group, noun) for (_code, noun), group in self._repeated.items()]
        return sorted(self.plain + folded, key=lambda d: d.location.line)


# How many of the other lines a folded diagnostic names.
_LINES_SHOWN = 6


def _fold(group: list[Diagnostic], noun: str) -> Diagnostic:
    first, others = group[0], group[1:]
    if not others:
        return first
    lines = [str(d.location.line) for d in others[:_LINES_SHOWN]]
    rest = len(others) - len(lines)
    listed = ", ".join(lines) + (f" and {rest} more" if rest else "")
    return Diagnostic(
        first.location,
        first.code,
        first.severity,
        f"{first.message} (and {len(others)} {noun}: line{'s' if len(others) > 1 else ''} "
        f"{listed})",
        first.hint,
    )
