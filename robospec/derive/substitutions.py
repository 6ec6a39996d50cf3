"""Mend class ``substitutions: defaults`` (RS702): xacro/roslaunch substitutions nobody expanded.

A URDF written out of a ROS launch file keeps ``$(optenv NAME default)`` or ``$(find NAME)``
where a value belongs (pybullet's Husky); SAPIEN reads the words as numbers and stops (RS063).
Each is written as the value it would have had with nothing set: an ``optenv`` as its default,
``$(find NAME)`` as ``package://NAME`` (which robospec resolves like any package URI). One
without a default (``$(arg x)``, ``$(env X)``, ``${expression}``) cannot be mended from the file
alone: describe the robot with ``description: {xacro: ...}`` so robospec expands it.
"""

from __future__ import annotations

import re
from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.diagnostics.codes import CANNOT_MEND, LEFTOVER_SUBSTITUTION, MENDED_SUBSTITUTIONS

NAME = "substitutions"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_SUBSTITUTIONS
FIXES = (LEFTOVER_SUBSTITUTION,)
WHY = "the file holds $(...) substitutions nobody expanded, which have defaults"

_OPTENV = re.compile(r"\$\(optenv\s+\S+\s+([^)]*?)\s*\)")
_FIND = re.compile(r"\$\(find\s+([^)\s]+)\s*\)/?")
_ANY = re.compile(r"\$[({]")


def _subject(element: etree._Element, attribute: str | None) -> str:
    owner: etree._Element | None = element
    while owner is not None and owner.get("name") is None:
        owner = owner.getparent()
    named = f"{owner.tag!s} '{owner.get('name')}' " if owner is not None else ""
    where = f"{attribute}=" if attribute else "text"
    return f"{named}<{element.tag!s}> {where}"


def _expanded(raw: str) -> str | None:
    """``raw`` with every substitution written as its value; None when one has none."""
    text = _OPTENV.sub(lambda m: m.group(1), raw)
    text = _FIND.sub(lambda m: f"package://{m.group(1)}/", text)
    return None if _ANY.search(text) else text


def apply(document: Document, policy: str) -> None:
    for element in document.tree.iter():
        if not isinstance(element.tag, str):
            continue  # a comment or processing instruction
        for attribute, raw in element.attrib.items():
            if _ANY.search(raw):
                _mend(document, element, attribute, raw)
        if element.text and _ANY.search(element.text) and len(element) == 0:
            _mend(document, element, None, element.text)


def _mend(document: Document, element: etree._Element, attribute: str | None, raw: str) -> None:
    value = _expanded(raw)
    subject = _subject(element, attribute)
    if value is None:
        document.refuse(
            element,
            CANNOT_MEND,
            f"mend 'substitutions' cannot write {subject}\"{raw.strip()}\": it has no default",
            "describe the robot with `description: {xacro: FILE}` (robospec expands it), or "
            "write the value",
        )
        return
    if attribute is None:
        element.text = value
    else:
        element.set(attribute, value)
    document.changed(element, subject, f'"{raw.strip()}"', f'"{value.strip()}"')


def suggest(document: Document) -> str | None:
    return "defaults" if document.would_change(apply, "defaults") else None
