"""Mend class ``transmissions: drop`` (RS705): ``<transmission>``s SAPIEN's parser cannot read.

SAPIEN's copy of urchin reads every transmission strictly (a ``<type>`` element, named joints
and actuators, a number in ``<mechanicalReduction>``) and stops the load at the first it cannot
read (RS064: PR2's old-style ones, xArm's words for reductions); once read, SAPIEN never uses
a transmission. So removing the ones it cannot read changes nothing that is simulated.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.description.urdf_loader_rules import unreadable_transmissions
from robospec.diagnostics.codes import BAD_TRANSMISSION, MENDED_TRANSMISSIONS

NAME = "transmissions"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_TRANSMISSIONS
FIXES = (BAD_TRANSMISSION,)
WHY = "SAPIEN's parser stops at transmissions it cannot read, and never uses one it can"


def apply(document: Document, policy: str) -> None:
    for transmission, reason in unreadable_transmissions(document.tree, document.source.shown):
        name = transmission.get("name")
        subject = f"transmission '{name}'" if name else "<transmission>"
        reason = reason.removeprefix(subject).lstrip(":").strip()
        document.changed(transmission, subject, reason, "removed")
        document.remove(transmission)


def suggest(document: Document) -> str | None:
    return "drop" if document.would_change(apply, "drop") else None
