"""Mend class ``mass: bound`` (RS707): masses SAPIEN would replace, ignore or barely feel.

PhysX replaces a mass that is not positive with 1 kg (RS060), SAPIEN ignores an inertial whose
mass is 0 beside an inertia (RS061), and a link of a fraction of a gram beside kilogram links
makes the articulation stiff to solve. ``bound`` raises every such mass to 1 g, scaling a
positive mass's inertia with it (the radius of gyration is kept), as MuJoCo's ``boundmass``
does. A link with mass 0 and an all-zero inertia is the usual massless frame: SAPIEN computes
its mass from its shapes, and it is left alone.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.description.inertia import INERTIA_ATTRIBUTES
from robospec.description.sanity import TINY
from robospec.diagnostics.codes import IGNORED_INERTIAL, MENDED_MASSES, NEGATIVE_MASS

NAME = "mass"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_MASSES
FIXES = (NEGATIVE_MASS, IGNORED_INERTIAL)
WHY = "links have masses PhysX replaces or SAPIEN ignores"

MINIMUM = TINY  # kg: a gram, under which robospec validate calls a mass tiny (RS090)


def apply(document: Document, policy: str) -> None:
    for link in document.tree.iterfind("link"):
        element = link.find("inertial/mass")
        inertia = link.find("inertial/inertia")
        try:
            mass = float(element.get("value", "")) if element is not None else None
            values = (
                [float(inertia.get(a, "")) for a in INERTIA_ATTRIBUTES]
                if inertia is not None
                else []
            )
        except ValueError:
            continue  # not a number: its own error says so
        if element is None or mass is None or mass >= MINIMUM:
            continue
        if mass == 0 and not any(values):
            continue  # a massless frame, as URDFs write one
        element.set("value", f"{MINIMUM:g}")
        if mass > 0 and inertia is not None and any(values):
            for attribute, value in zip(INERTIA_ATTRIBUTES, values, strict=True):
                inertia.set(attribute, f"{value * MINIMUM / mass:.12g}")
        scaled = " (its inertia scaled with it)" if mass > 0 and any(values) else ""
        document.changed(
            element, f"link '{link.get('name')}' <mass>", f"{mass:g} kg", f"{MINIMUM:g} kg{scaled}"
        )


def suggest(document: Document) -> str | None:
    """Only for a negative mass (an error): a zero or tiny one loads (the warnings say so)."""
    for element in document.tree.iterfind("link/inertial/mass"):
        try:
            if float(element.get("value", "")) < 0:
                return "bound"
        except ValueError:
            continue
    return None
