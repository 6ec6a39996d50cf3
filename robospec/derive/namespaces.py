"""Mend class ``namespaces: declare`` (RS701): namespace prefixes used but never declared.

A URDF that uses ``xacro:`` or ``gazebo:`` elements or attributes without an ``xmlns:``
declaration for the prefix is not XML that any namespace-aware parser reads: lxml and SAPIEN's
ElementTree both stop at the first use (RS051). Declaring the prefix on the root element (ROS's
URI for ``xacro``, a robospec URN otherwise) changes no element the loaders read.
"""

from __future__ import annotations

import re
from typing import Literal

from robospec.derive.document import Document
from robospec.diagnostics.codes import MALFORMED_XML, MENDED_NAMESPACES

NAME = "namespaces"
KINDS = frozenset({"urdf", "mjcf"})
STAGE: Literal["text", "tree"] = "text"
CODE = MENDED_NAMESPACES
FIXES = (MALFORMED_XML,)
WHY = "the file uses XML namespace prefixes it never declares"

_KNOWN = {
    "xacro": "http://www.ros.org/wiki/xacro",
    "gazebo": "http://gazebosim.org/schema",
}
_UNDEFINED = re.compile(r"Namespace prefix (\S+) (?:for \S+ )?on \S+ is not defined")
_ROOT_TAG = re.compile(rb"<([A-Za-z_][\w.\-]*)(?=[\s/>])")
_ROUNDS = 20  # prefixes declared one by one, as the parser meets them


def apply(document: Document, policy: str) -> None:
    from robospec.derive.xml_repair import _syntax_error

    declared: list[str] = []
    for _ in range(_ROUNDS):
        problem = _syntax_error(document.data)
        if problem is None:
            break
        match = _UNDEFINED.search(problem[0])
        root = _root_tag(document.data)
        if match is None or root is None or match.group(1) in declared:
            break
        prefix = match.group(1)
        uri = _KNOWN.get(prefix, f"urn:robospec:undeclared:{prefix}")
        insert = f' xmlns:{prefix}="{uri}"'.encode()
        document.data = document.data[: root.end()] + insert + document.data[root.end() :]
        declared.append(prefix)
        document.changed(
            _line_of(document.data, root.start()),
            f"prefix '{prefix}:' (first used on line {problem[1]})",
            "undeclared",
            f'xmlns:{prefix}="{uri}" on the root element',
        )


def suggest(document: Document) -> str | None:
    return "declare" if document.would_change(apply, "declare") else None


def _root_tag(data: bytes) -> re.Match[bytes] | None:
    """The root element's start tag name: the first tag that is not a declaration, comment,
    processing instruction or doctype."""
    position = 0
    while True:
        match = _ROOT_TAG.search(data, position)
        if match is None:
            return None
        if not _inside_markup(data, match.start()):
            return match
        position = match.end()


def _inside_markup(data: bytes, offset: int) -> bool:
    """Whether ``offset`` is inside a comment or processing instruction before the root."""
    for opening, closing in ((b"<!--", b"-->"), (b"<?", b"?>"), (b"<!", b">")):
        start = data.rfind(opening, 0, offset + 1)
        if start >= 0 and data.find(closing, start) >= offset:
            return True
    return False


def _line_of(data: bytes, offset: int) -> int:
    return data.count(b"\n", 0, offset) + 1
