"""The description being derived: its text, then its XML tree, and what was done to it.

A mend edits the document in place and records each change (:meth:`Document.changed`) at the
element of the user's file it changed. Edits keep every element on the line it had: text
mends rewrite within a line, a removed element leaves its lines blank, and the tree is written
back with its own whitespace (:meth:`Document.text`). So the derived text, parsed again, is
located in the user's file by the same lines: every later diagnostic points at the original.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

from lxml import etree

from robospec.diagnostics import Diagnostic, Location, error

Kind = Literal["urdf", "mjcf"]


@dataclass(frozen=True)
class Source:
    """The description a spec names, as read (a xacro file's expansion already expanded)."""

    path: str  # the file, absolute: its folder is where its meshes and includes are found
    shown: str  # how diagnostics name it (as the spec wrote it)
    kind: Kind
    data: bytes
    packages: Mapping[str, str] = field(default_factory=dict)  # ROS package -> folder


@dataclass(frozen=True)
class Change:
    """One element a mend changed: where, what it is, and its value before and after."""

    line: int
    subject: str  # "link 'base' <inertia>"
    before: str
    after: str
    tag: str = ""  # the element's tag: the note's caret goes under its start tag
    file: str = ""  # where the element was written, when not the description itself (shown)

    def text(self) -> str:
        return f"{self.subject}: {self.before} -> {self.after}"


class Document:
    """One description while mends run: bytes first (text mends), then the parsed tree."""

    def __init__(self, source: Source) -> None:
        self.source = source
        self.data = source.data
        self.root: etree._Element | None = None
        self.changes: list[Change] = []
        self.refusals: list[Diagnostic] = []
        # elements brought in from other files (an inlined <include>): where each was written
        self.origins: dict[etree._Element, tuple[str, int]] = {}
        # derived line -> (file, line) where it was written, when elements moved (see text())
        self.line_map: dict[int, tuple[str, int]] = {}

    # -- reading ----------------------------------------------------------------------------

    def parse(self) -> bool:
        """Parse the (text-mended) bytes as robospec's parser does; False when they are not
        XML (the description's own parse then reports where)."""
        parser = etree.XMLParser(
            resolve_entities=False, no_network=True, load_dtd=False, remove_blank_text=False
        )
        try:
            self.root = etree.fromstring(self.data, parser)
        except etree.XMLSyntaxError:
            self.root = None
        return self.root is not None

    @property
    def tree(self) -> etree._Element:
        assert self.root is not None, "parse() the document before its tree mends"
        return self.root

    def trial(self) -> Document:
        """A copy to try a policy on (what ``suggest`` asks: would it change anything?)."""
        import copy

        other = Document(self.source)
        other.data = self.data
        other.root = copy.deepcopy(self.root) if self.root is not None else None
        if self.origins and self.root is not None and other.root is not None:
            pairs = zip(self.root.iter(), other.root.iter(), strict=True)
            other.origins = {new: self.origins[old] for old, new in pairs if old in self.origins}
        return other

    def would_change(self, apply: Callable[[Document, Any], None], policy: Any) -> bool:
        """Whether ``apply`` with ``policy`` changes this document, leaving it as it is, and
        mends everything it meets (a policy that leaves an element unmended is no answer)."""
        trial = self.trial()
        apply(trial, policy)
        return bool(trial.changes) and not trial.refusals

    # -- recording --------------------------------------------------------------------------

    def changed(self, at: etree._Element | int, subject: str, before: str, after: str) -> None:
        tag = at.tag if isinstance(at, etree._Element) and isinstance(at.tag, str) else ""
        if tag and isinstance(at, etree._Element):
            file, line = self.origins.get(at, ("", _line(at)))
        else:
            file, line = "", _line(at)
        self.changes.append(Change(line, subject, before, after, tag, file))

    def refuse(self, at: etree._Element | int, code: str, message: str, hint: str) -> None:
        """An element this mend cannot mend as asked: a located error in the description."""
        self.refusals.append(error(self.location(at), code, message, hint))

    def location(self, at: etree._Element | int, tag: str = "") -> Location:
        """Where ``at`` (an element, or a line) stands in the user's file: its start tag."""
        from robospec.description.source_columns import tag_column

        line = _line(at)
        if isinstance(at, etree._Element) and isinstance(at.tag, str):
            tag = at.tag
            if at in self.origins:  # written in an included file: located there
                return self.location_in(*self.origins[at], tag)
        column = tag_column(self.source.path, line, tag) if tag else 1
        return Location(self.source.shown, line, column)

    def location_in(self, shown: str, line: int, tag: str) -> Location:
        """Where line ``line`` of the file diagnostics call ``shown`` stands: the description
        itself, or a file it includes (named relative to the description's folder)."""
        from robospec.description.source_columns import tag_column

        if not shown or shown == self.source.shown:
            return self.location(line, tag)
        folder = os.path.dirname(self.source.shown)
        relative = os.path.relpath(shown, folder) if folder else shown
        path = os.path.join(os.path.dirname(os.path.abspath(self.source.path)), relative)
        return Location(shown, line, tag_column(path, line, tag) if tag else 1)

    # -- editing ----------------------------------------------------------------------------

    def track_lines(self) -> None:
        """Record where every element was written, before a mend moves elements to other
        lines: the derived text then maps each of its lines back (see :meth:`text`)."""
        for element in self.tree.iter():
            if isinstance(element.tag, str) and element not in self.origins:
                self.origins[element] = (self.source.shown, _line(element))

    def remove(self, element: etree._Element) -> None:
        """Remove ``element``, its lines left blank before whatever followed it."""
        parent = element.getparent()
        if parent is None:
            return
        kept = "\n" * etree.tostring(element, with_tail=False).count(b"\n") + (element.tail or "")
        previous = element.getprevious()
        if previous is not None:
            previous.tail = (previous.tail or "") + kept
        else:
            parent.text = (parent.text or "") + kept
        parent.remove(element)

    def text(self) -> str:
        """The derived description: the tree as written, each element on its original line
        (what stood before the root — the XML declaration, comments — as blank lines)."""
        if self.root is None:
            return self.data.decode("utf-8", "replace")
        body = etree.tostring(self.root, encoding="unicode")
        line = self.root.sourceline if isinstance(self.root.sourceline, int) else 1
        text = "\n" * (max(line, 1) - 1) + body + "\n"
        if self.origins:
            self.line_map = self._lines_of(text)
        return text

    def _lines_of(self, text: str) -> dict[int, tuple[str, int]]:
        """Where each line of ``text`` that starts an element was written, when elements came
        from other files and the lines no longer match: derived line -> (file, line)."""
        assert self.root is not None
        written = etree.fromstring(text.encode("utf-8"))
        mapping: dict[int, tuple[str, int]] = {}
        for old, new in zip(self.root.iter(), written.iter(), strict=False):
            line = new.sourceline
            if not isinstance(line, int) or line in mapping:
                continue
            mapping[line] = self.origins.get(old, (self.source.shown, _line(old)))
        return mapping


def insert_after(anchor: etree._Element, added: Sequence[etree._Element]) -> None:
    """``added`` after ``anchor``, on its last line: every later element keeps its line (so
    the diagnostics of the derived copy still point at the description's lines)."""
    tail = anchor.tail
    previous = anchor
    for element in added:
        previous.addnext(element)
        previous.tail = " "
        previous = element
    previous.tail = tail


def _line(at: etree._Element | int) -> int:
    if isinstance(at, int):
        return max(at, 1)
    line = at.sourceline
    return line if isinstance(line, int) and line > 0 else 1


def fold_changes(changes: list[Change], shown: int = 6) -> str:
    """The first change, and how many more of the kind where (one note per mend and file)."""
    first, others = changes[0], changes[1:]
    if not others:
        return first.text()
    lines = sorted({c.line for c in others})
    listed = ", ".join(str(n) for n in lines[:shown])
    more = f" and {len(lines) - shown} more" if len(lines) > shown else ""
    plural = "s" if len(lines) > 1 else ""
    return f"{first.text()} (and {len(others)} more: line{plural} {listed}{more})"
