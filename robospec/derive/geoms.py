"""Mend class ``geoms: drop`` (RS713, MJCF): geoms of types ManiSkill's loader raises on.

ManiSkill's MJCF loader parses every geom of the model, robot or not, and raises
``NotImplementedError`` on a height field or an SDF (RS079): dm_control's quadruped stands on an
``hfield`` terrain, and cannot be loaded at all. ManiSkill's scenes bring their own ground, so
the geoms are removed (the assets they name are left: unused, they change nothing).
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.diagnostics.codes import MENDED_GEOMS, MJCF_GEOM_TYPE

NAME = "geoms"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_GEOMS
FIXES = (MJCF_GEOM_TYPE,)
WHY = "ManiSkill's loader raises on hfield and sdf geoms (its scenes have their own ground)"

UNLOADABLE = frozenset({"hfield", "sdf"})


def apply(document: Document, policy: str) -> None:
    types = _geom_types(document)
    for geom in list(document.tree.iter("geom")):
        parent = geom.getparent()
        if parent is None or parent.tag == "default" or str(parent.tag).startswith("{"):
            continue
        kind = geom.get("type") or types.get(geom.get("class") or "", "sphere")
        if kind in UNLOADABLE:
            where = geom.get("name") or geom.get("hfield") or ""
            document.changed(geom, f"<geom> '{where}'", f'type="{kind}"', "removed")
            document.remove(geom)


def _geom_types(document: Document) -> dict[str, str]:
    """The geom type each default class sets (a geom may take its type from its class)."""
    types: dict[str, str] = {}
    for default in document.tree.iter("default"):
        geom = default.find("geom")
        if geom is not None and geom.get("type") and default.get("class"):
            types[default.get("class", "")] = geom.get("type", "")
    return types


def suggest(document: Document) -> str | None:
    return "drop" if document.would_change(apply, "drop") else None
