"""Derived descriptions: the user's robot description and a list of transformations in, a
description robospec writes out, with the files it names.

Design. A spec's description may declare mends (``description.mend``); later, other
transformations (composing two descriptions into one) write descriptions too. Whatever the
transformation, the result is the same thing, a :class:`Derived`: the text of a URDF or MJCF
that robospec wrote, the kind, and the located notes of what changed. The resolve stage parses
that text, located in the user's file (transformations keep every element on its line, see
:mod:`robospec.derive.document`), and hands it on in the ``FileRef`` of the robot
(``generated_text``): ``register`` writes it into its cache entry and ``build`` into the
package, with copies of the meshes it names (robospec.output.modules), so everything
downstream — check, tune, optimize, the language server, inspect, doc — loads the derived copy
and never the user's file, which is never written.

How a new transformation plugs in:

1. one module here, declaring what :mod:`robospec.derive.mend` lists (``NAME``, ``KINDS``,
   ``STAGE``, ``CODE``, ``FIXES``, ``WHY``, ``apply``, ``suggest``), editing a
   :class:`~robospec.derive.document.Document` and recording each change at its element;
2. its name in :data:`robospec.derive.registry.MENDS` (the order they run in), a field of the
   same name in :class:`robospec.model.mends.Mends` (schema, completion and docs follow; a test
   holds the two together), and its note code in robospec/diagnostics/codes.py with a docs
   example.

A transformation that is not a mend (one that writes a description from several) makes a
:class:`Derived` itself and hands it to the same resolve step
(:func:`robospec.resolve.description_files.load_spec_description`).

Only lxml and the standard library are imported here: deriving runs on the validate path.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from robospec.derive.document import Change, Document, Source, fold_changes
from robospec.derive.mend import MendClass, Policy
from robospec.derive.registry import MENDS, ORDER, SECTIONS, mend_class
from robospec.diagnostics import Diagnostic, Location, note

__all__ = [
    "MENDS",
    "SECTIONS",
    "Derived",
    "Outcome",
    "Source",
    "derive",
    "mend_class",
    "suggest_mends",
]


@dataclass(frozen=True)
class Outcome:
    """What one declared mend did: ``applied`` (its note says what), ``stale`` (nothing to
    mend), ``not_for_kind`` (it mends the other kind of description)."""

    name: str
    status: str
    changes: tuple[Change, ...] = ()


@dataclass(frozen=True)
class Derived:
    """A description robospec wrote: its text, located in the user's file line for line."""

    text: str
    kind: str
    notes: tuple[Diagnostic, ...] = ()  # one per applied mend, at the first element it changed
    refusals: tuple[Diagnostic, ...] = ()  # elements a mend could not mend as asked
    outcomes: tuple[Outcome, ...] = field(default=())
    # (line, code): problems the description's parse reports that a refusal already explains
    # at that line (the refusal says what it is and why the mend cannot help)
    explained: frozenset[tuple[int, str]] = frozenset()
    # derived line -> (file, line) it was written on, where elements moved (inlined includes);
    # empty when every element kept its line
    line_map: tuple[tuple[int, tuple[str, int]], ...] = ()

    def unexplained(self, diagnostics: list[Diagnostic]) -> list[Diagnostic]:
        """``diagnostics`` of the derived text without those a refusal already says."""
        return [d for d in diagnostics if (d.location.line, d.code) not in self.explained]

    def located(self, diagnostics: list[Diagnostic], parsed_as: str) -> list[Diagnostic]:
        """``diagnostics`` of parsing the derived text (as the file ``parsed_as``), each at the
        line of the user's file it stands for: unexplained by a refusal, and where elements
        moved, at the file and line each was written on."""
        if not self.line_map:
            return self.unexplained(diagnostics)
        import bisect

        lines = [line for line, _ in self.line_map]
        out = []
        for d in diagnostics:
            if d.location.file == parsed_as and lines:
                index = max(bisect.bisect_right(lines, d.location.line) - 1, 0)
                derived_line, (file, line) = self.line_map[index]
                shifted = line + max(d.location.line - derived_line, 0)
                d = Diagnostic(
                    Location(file, shifted, d.location.column),
                    d.code,
                    d.severity,
                    d.message,
                    d.hint,
                )
            out.append(d)
        return self.unexplained(out)


def mended_bytes(source: Source, mends: Mapping[str, Policy]) -> bytes | None:
    """``source``'s bytes with ``mends`` applied (the file MuJoCo compiles where a spec mends
    an MJCF); None where a mend refuses an element."""
    derived = derive(source, mends)
    return None if derived.refusals else derived.text.encode("utf-8")


def derive(
    source: Source, requested: Mapping[str, Policy], sections: Mapping[str, Policy] | None = None
) -> Derived:
    """Apply the ``requested`` mends (class name -> policy) and the transformations the spec's
    ``sections`` ask for (section -> its settings: :data:`~robospec.derive.registry.SECTIONS`)
    to ``source``, in the order of :data:`~robospec.derive.registry.ORDER`."""
    document = Document(source)
    outcomes: list[Outcome] = []
    notes: list[Diagnostic] = []
    explained: set[tuple[int, str]] = set()
    parsed = False
    asked = {**requested, **{SECTIONS[k].NAME: v for k, v in (sections or {}).items()}}
    for mend in ORDER:
        if mend.NAME not in asked:
            continue
        if source.kind not in mend.KINDS:
            outcomes.append(Outcome(mend.NAME, "not_for_kind"))
            continue
        if mend.STAGE == "tree" and not parsed:
            parsed = True
            if not document.parse():
                break  # still not XML: the description's own parse says where
        before_changes, before_refusals = len(document.changes), len(document.refusals)
        mend.apply(document, asked[mend.NAME])
        changes = tuple(document.changes[before_changes:])
        refused = len(document.refusals) > before_refusals
        for refusal in document.refusals[before_refusals:]:
            explained.update((refusal.location.line, code) for code in mend.FIXES)
        if changes:
            notes.append(_note(document, mend, list(changes)))
        status = "applied" if changes else ("refused" if refused else "stale")
        if mend.NAME in requested:  # a section's transformation is judged by its checks
            outcomes.append(Outcome(mend.NAME, status, changes))
    if not parsed and any(o.status == "applied" for o in outcomes):
        document.parse()  # text mends only: written back as the tree, like every derived text
    text = (
        document.text() if document.root is not None else document.data.decode("utf-8", "replace")
    )
    return Derived(
        text,
        source.kind,
        tuple(notes),
        tuple(document.refusals),
        tuple(outcomes),
        frozenset(explained),
        tuple(sorted(document.line_map.items())),
    )


def _note(document: Document, mend: MendClass, changes: list[Change]) -> Diagnostic:
    first = min(changes, key=lambda c: c.line)
    ordered = [first, *(c for c in changes if c is not first)]
    section = next((key for key, m in SECTIONS.items() if m is mend), None)
    label = f"{section}:" if section is not None else f"mend '{mend.NAME}':"
    return note(
        document.location_in(first.file, first.line, first.tag),
        mend.CODE,
        f"{label} {fold_changes(ordered)}",
    )


def suggest_mends(source: Source) -> tuple[dict[str, Policy], Derived]:
    """The mends ``source`` needs for ManiSkill to load it (what ``robospec new`` writes),
    each class asked in turn on the description the earlier ones mended; and the result."""
    document = Document(source)
    chosen: dict[str, Policy] = {}
    parsed = False
    for mend in MENDS:
        if source.kind not in mend.KINDS:
            continue
        if mend.STAGE == "tree" and not parsed:
            parsed = True
            if not document.parse():
                break
        policy = mend.suggest(document)
        if policy is not None:
            chosen[mend.NAME] = policy
            mend.apply(document, policy)  # the next classes judge the mended description
    return chosen, derive(source, chosen)
