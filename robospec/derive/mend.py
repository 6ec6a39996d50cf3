"""What every mend module declares: the interface of one class of transformation.

A module of :mod:`robospec.derive` is one mend class (the key under ``description.mend``). It
declares, at module level:

- ``NAME``: the key, as :class:`robospec.model.mends.Mends` spells it;
- ``KINDS``: the description kinds it applies to (``urdf``, ``mjcf``);
- ``STAGE``: ``"text"`` (it edits the bytes, before they can be parsed) or ``"tree"``;
- ``CODE``: the code of the note that says what it changed;
- ``FIXES``: the codes of the problems it mends (the docs link their pages to it);
- ``WHY``: one line for the comment ``robospec new`` writes beside it;
- ``apply(document, policy)``: mend the document as the policy says, recording every change
  and every element it cannot mend (:class:`robospec.derive.document.Document`);
- ``suggest(document)``: the policy this description needs to load, or None.
"""

from __future__ import annotations

from typing import Any, Literal, Protocol

from robospec.derive.document import Document

Policy = Any  # a string, a list of strings, or numbers: as the spec model validated it


class MendClass(Protocol):
    NAME: str
    KINDS: frozenset[str]
    STAGE: Literal["text", "tree"]
    CODE: str
    FIXES: tuple[str, ...]
    WHY: str

    def apply(self, document: Document, policy: Policy) -> None: ...

    def suggest(self, document: Document) -> Policy | None: ...


# codes shared by every mend class: said of the spec's `description.mend` entry
