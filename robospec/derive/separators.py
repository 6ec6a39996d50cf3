"""Mend class ``separators: spaces`` (RS722): number lists written with commas.

urchin, SAPIEN's URDF parser, reads a list of numbers (an ``<origin>``'s ``xyz`` and ``rpy``,
an ``<axis>``, a box's ``size``, a mesh's ``scale``, a colour's ``rgba``) as numbers separated
by spaces, and stops the whole load at a comma (RS052): ``rpy="1.5707963, 1.3089969
1.5707963"`` is a hand edit or an exporter's habit, and its numbers are plain. They are written
as they stand, separated by spaces. A list that would read as as many numbers with decimal
commas (``"0,5 1 2"``) is left alone: which the author meant cannot be told, and the parse
still reports it.
"""

from __future__ import annotations

import re
from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.description.urdf_values import NUMBER_LISTS, comma_separated
from robospec.diagnostics.codes import INVALID_STRUCTURE, MENDED_SEPARATORS

NAME = "separators"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_SEPARATORS
FIXES = (INVALID_STRUCTURE,)
WHY = "number lists are written with commas, which SAPIEN's URDF parser refuses"


def apply(document: Document, policy: str) -> None:
    for element in document.tree.iter(*NUMBER_LISTS):
        for attribute, count in NUMBER_LISTS[str(element.tag)].items():
            raw = element.get(attribute)
            values = comma_separated(raw, count) if raw is not None else None
            if raw is None or values is None:
                continue
            # the numbers as the file writes them (never a float's repr): only separators change
            written = " ".join(part for part in re.split(r"[\s,]+", raw.strip()) if part)
            document.changed(element, f"{_owner(element)} {attribute}=", f'"{raw}"', f'"{written}"')
            element.set(attribute, written)


def suggest(document: Document) -> str | None:
    return "spaces" if document.would_change(apply, "spaces") else None


def _owner(element: etree._Element) -> str:
    """``joint 'shoulder' <origin>``: the element and the link, joint or material it is in."""
    owner = element.getparent()
    while owner is not None and owner.tag not in ("link", "joint", "material"):
        owner = owner.getparent()
    where = f"{owner.tag!s} '{owner.get('name')}' " if owner is not None else ""
    return f"{where}<{element.tag!s}>"
