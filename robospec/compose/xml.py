"""The XML side of composing, shared by the URDF and MJCF writers: parsing as robospec's
description parsers do, moving a part's elements into the combined tree, and writing the
combined text with the origin of every element (:class:`robospec.compose.Origins`)."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from lxml import etree

from robospec.compose.model import Origins


def parse(data: bytes) -> etree._Element | None:
    """The root element of ``data``, or None when it is not XML (its own parse says where)."""
    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, remove_blank_text=False
    )
    try:
        return etree.fromstring(data, parser)
    except etree.XMLSyntaxError:
        return None


class Provenance:
    """The file and line of each element that goes into the combined tree. lxml hands back the
    same proxy for an element as long as one is referenced, so the elements are kept here and
    looked up by identity after they have moved."""

    def __init__(self) -> None:
        self._kept: list[etree._Element] = []
        self._origin: dict[int, tuple[str, int]] = {}
        self.files: dict[str, str] = {}  # shown -> absolute

    def remember(
        self,
        elements: Iterable[etree._Element],
        file: str,
        line: int | None = None,
        path: str | None = None,
    ) -> None:
        """``elements`` come from ``file`` (as shown; ``path``: where it is): each at its own
        source line, or all at ``line``."""
        if path is not None:
            self.files.setdefault(file, path)
        for element in elements:
            self._kept.append(element)
            there = line if line is not None else element.sourceline
            self._origin[id(element)] = (file, there if isinstance(there, int) and there > 0 else 1)

    def of(self, element: etree._Element) -> tuple[str, int] | None:
        return self._origin.get(id(element))


def written(root: etree._Element, provenance: Provenance, first_line: int) -> tuple[str, Origins]:
    """The combined text, its root on ``first_line`` (the base's lines stay where they were),
    and where each of its elements came from."""
    text = "\n" * (max(first_line, 1) - 1) + etree.tostring(root, encoding="unicode") + "\n"
    sources = [provenance.of(e) for e in root.iter(etree.Element)]
    reparsed = parse(text.encode("utf-8"))
    entries: list[tuple[int, str, int]] = []
    if reparsed is not None:
        for element, source in zip(reparsed.iter(etree.Element), sources, strict=False):
            if source is not None and isinstance(element.sourceline, int):
                entries.append((element.sourceline, source[0], source[1]))
    entries.sort()
    return text, Origins(tuple(entries), tuple(provenance.files.items()))


def relative_file(found: str, base_folder: str) -> str:
    """``found`` as a path from ``base_folder``, with forward slashes (absolute when the two
    are on different drives)."""
    try:
        return Path(os.path.relpath(found, base_folder)).as_posix()
    except ValueError:
        return Path(found).as_posix()


def comment_text(text: str) -> str:
    """``text`` made safe inside an XML comment."""
    return " " + text.replace("--", "- -").strip() + " "


def append_lines(parent: etree._Element, elements: Iterable[etree._Element], indent: str) -> None:
    """Append ``elements`` to ``parent``, each on a line of its own at ``indent``, the closing
    tag of ``parent`` on the line after the last."""
    children = list(parent)
    closing = (children[-1].tail if children else parent.text) or "\n"
    closing = "\n" + closing.rsplit("\n", 1)[-1] if "\n" in closing else "\n"
    if children:
        children[-1].tail = "\n" + indent
    else:
        parent.text = "\n" + indent
    last = None
    for element in elements:
        parent.append(element)
        element.tail = "\n" + indent
        last = element
    if last is not None:
        last.tail = closing


def number(value: float) -> str:
    """``value`` as the shortest text that reads back as the same float (``1`` for 1.0)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text
