"""Mend class ``xml: repair`` (RS700): text that lxml and SAPIEN refuse around a sound XML tree.

Descriptions exported by tools carry an XML declaration libxml2 does not support
(``<?xml version="0.0" ?>``: pybullet's Minitaur) or bytes after the root element (a NUL, a
second document: pybullet's DeepMimic humanoid). Both stop every XML parser before the robot
is read (RS051), though the tree itself is whole. The declaration is dropped (it states
nothing the parser needs: the text is UTF-8) and whatever follows the root element is cut.
"""

from __future__ import annotations

import re
from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.diagnostics.codes import MALFORMED_XML, MENDED_XML

NAME = "xml"
KINDS = frozenset({"urdf", "mjcf"})
STAGE: Literal["text", "tree"] = "text"
CODE = MENDED_XML
FIXES = (MALFORMED_XML,)
WHY = "the file has an XML declaration or trailing bytes no XML parser accepts"

_DECLARATION = re.compile(rb"^(\xef\xbb\xbf)?\s*<\?xml\b[^?]*\?>")
_EXTRA = "Extra content at the end of the document"
# how many times a repair may cut and try again: a declaration, then trailing content
_ROUNDS = 3


def apply(document: Document, policy: str) -> None:
    for _ in range(_ROUNDS):
        problem = _syntax_error(document.data)
        if problem is None:
            return
        message, line, column = problem
        declaration = _DECLARATION.match(document.data)
        if declaration is not None and line == 1 and "version" in message.lower():
            shown = declaration.group(0).decode("utf-8", "replace").strip()
            # the declaration's own line stays, empty: every element keeps its line
            document.data = (
                document.data[: declaration.start()] + document.data[declaration.end() :]
            )
            document.changed(1, "XML declaration", shown, "none (lxml: " + message + ")")
        elif message.startswith(_EXTRA):
            offset = _offset(document.data, line, column)
            extra = document.data[offset:]
            document.data = document.data[:offset].rstrip() + b"\n"
            document.changed(line, "content after the root element", _shown(extra), "none")
        else:
            return  # not what this mend repairs: the parse reports it


def suggest(document: Document) -> str | None:
    return "repair" if document.would_change(apply, "repair") else None


def _syntax_error(data: bytes) -> tuple[str, int, int] | None:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    try:
        etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        line, column = exc.position if exc.position else (exc.lineno or 1, 1)
        message = re.sub(r",\s*line \d+, column \d+\s*$", "", exc.msg or str(exc))
        return message, int(line or 1), int(column or 1)
    return None


def _offset(data: bytes, line: int, column: int) -> int:
    """The byte offset of 1-based ``line``:``column`` (libxml2 counts columns in bytes)."""
    start = 0
    for _ in range(line - 1):
        found = data.find(b"\n", start)
        if found < 0:
            return len(data)
        start = found + 1
    return min(start + max(column - 1, 0), len(data))


def _shown(extra: bytes) -> str:
    text = extra.decode("utf-8", "replace")
    printable = "".join(ch if ch.isprintable() else f"\\x{ord(ch):02x}" for ch in text.strip())
    if not printable:
        printable = "".join(f"\\x{b:02x}" for b in extra[:8])
    return "'" + printable[:40] + ("..." if len(printable) > 40 else "") + "'"
