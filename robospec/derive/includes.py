"""Mend class ``includes: inline`` (RS712, MJCF): ``<include>``s ManiSkill's loader does not read.

ManiSkill's MJCF loader reads an ``<include>`` only directly under ``<mujoco>``, one level
deep; one inside ``<worldbody>`` or ``<asset>`` (gymnasium-robotics' Shadow hand keeps the whole
hand in one) is dropped without a word, and with it the robot (RS082). MuJoCo reads them all,
wherever they stand. ``inline`` writes the contents of every ``<include>``, at any depth, in its
place, as MuJoCo does; each element inlined keeps the file and line it was written on, so every
later diagnostic points into the included file.

An included file may bring a ``<worldbody>`` of its own (a scene's table and lights, before the
file's robots): MuJoCo merges every ``<worldbody>`` into one, in the order written, where
ManiSkill's loader reads only the first. Written in place, they are merged into the first, so
that the copy means to ManiSkill what the file means to MuJoCo (gym-aloha's scene would
otherwise leave the loader a table and no robot).
"""

from __future__ import annotations

import os
from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.diagnostics.codes import (
    CANNOT_MEND,
    DESCRIPTION_NOT_FOUND,
    INVALID_STRUCTURE,
    MENDED_INCLUDES,
    MJCF_UNREAD_INCLUDE,
)

NAME = "includes"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_INCLUDES
FIXES = (MJCF_UNREAD_INCLUDE,)
WHY = "ManiSkill's loader reads an <include> only directly under <mujoco>"

# carrying the model elsewhere (MuJoCo compiling it), as the description's own reading says it
_DEPTH = 16  # nested includes followed this deep (a cycle stops there, refused)


def apply(document: Document, policy: str) -> None:
    inline_all(document, note=True)


def inline_all(document: Document, *, note: bool) -> None:
    """Write every ``<include>`` in place (also what carrying an MJCF elsewhere needs)."""
    folder = os.path.dirname(os.path.abspath(document.source.path))
    shown_folder = os.path.dirname(document.source.shown)
    for _ in range(_DEPTH):
        includes = list(document.tree.iter("include"))
        if not includes:
            _merge_worldbodies(document)
            return
        for include in includes:
            _inline(document, include, folder, shown_folder, note)
    for include in document.tree.iter("include"):
        if note:
            document.refuse(
                include, CANNOT_MEND, "mend 'includes' stopped: the includes nest in a cycle", ""
            )
        else:
            document.refuse(include, INVALID_STRUCTURE, "the includes nest in a cycle", "")


def _inline(
    document: Document, include: etree._Element, folder: str, shown_folder: str, note: bool
) -> None:
    file = include.get("file")
    parent = include.getparent()
    if not file or parent is None:
        return  # an <include> without a file: the model's parse says so
    path = os.path.join(folder, file)
    try:
        with open(path, "rb") as handle:
            included = etree.fromstring(
                handle.read(),
                etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False),
            )
    except (OSError, etree.XMLSyntaxError) as exc:
        if note:  # the mend
            document.refuse(
                include,
                CANNOT_MEND,
                f"mend 'includes' cannot read '{file}': {exc}",
                "the file must be beside the model, as MuJoCo looks for it",
            )
        else:  # carrying the model elsewhere (MuJoCo compiling it): the file itself is missing
            document.refuse(
                include,
                DESCRIPTION_NOT_FOUND,
                f"cannot read included file '{file}': {exc}",
                "the file must be beside the model, as MuJoCo looks for it",
            )
        parent.remove(include)
        return
    shown = os.path.join(shown_folder, file) if shown_folder else file
    where = document.origins.get(include)
    children = [c for c in included if isinstance(c.tag, str)]
    for element in included.iter():
        if isinstance(element.tag, str) and element.sourceline:
            document.origins[element] = (shown, element.sourceline)
    if note:
        read = parent is document.tree  # ManiSkill reads these, from beside the model only
        merged = read and any(child.tag == "worldbody" for child in children)
        document.changed(
            where[1] if where else include,
            f'<include file="{file}"> in <{parent.tag!s}>',
            "read from beside the model" if read else "not read by ManiSkill",
            f"its {len(children)} element(s) written in place"
            + (", its <worldbody> merged with the model's, as MuJoCo reads them" if merged else ""),
        )
    anchor_tail = include.tail
    for child in children:
        child.tail = None
        include.addprevious(child)
    previous = include.getprevious()
    if previous is not None:
        previous.tail = (previous.tail or "") + (anchor_tail or "")
    parent.remove(include)


def _merge_worldbodies(document: Document) -> None:
    """Every ``<worldbody>`` of the model's top level merged into the first, as MuJoCo reads
    them: their bodies, geoms, sites and lights in the order written."""
    worldbodies = document.tree.findall("worldbody")
    if len(worldbodies) < 2:
        return
    first, *others = worldbodies
    for other in others:
        for child in list(other):
            first.append(child)  # (an element keeps its identity: its origin stays)
        document.tree.remove(other)


def suggest(document: Document) -> str | None:
    """Only for includes ManiSkill drops (not directly under ``<mujoco>``): those it reads
    need no mend (robospec inlines them itself when it carries a model elsewhere)."""
    if not any(i.getparent() is not document.tree for i in document.tree.iter("include")):
        return None
    return "inline" if document.would_change(apply, "inline") else None
