"""Mend class ``contype: conaffinity`` (RS717, MJCF): collision geoms ManiSkill gives no shape.

MuJoCo collides two geoms when the contype of either shares a bit with the conaffinity of the
other: a geom with ``contype="0"`` and ``conaffinity="1"`` is touched by every geom of contype
1 (the floor, the objects of a scene), though it touches none itself. ManiSkill's loader reads
contype only and gives such a geom no collision shape at all (RS073): feet fall through the
floor, and the link's mass (computed from its collision shapes) is lost with it. Each such geom
gets its conaffinity bits as its contype, so that ManiSkill builds its shape; geoms MuJoCo never
collides (contype and conaffinity 0: visual geoms) are left as they are.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import classes, effective, in_model, whole
from robospec.diagnostics.codes import MENDED_CONTYPE, MJCF_COLLISION_FILTER, MJCF_NO_MASS

NAME = "contype"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_CONTYPE
FIXES = (MJCF_COLLISION_FILTER, MJCF_NO_MASS)
WHY = "geoms with contype 0 collide in MuJoCo but get no collision shape in ManiSkill"


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    table = classes(root, document.source.path)
    geoms = [(g, effective(table, g)) for g in root.iter("geom") if in_model(g)]
    contypes = {_bits(attrs.get("contype"), 1) for _, attrs in geoms}
    for geom, attrs in geoms:
        contype, conaffinity = _bits(attrs.get("contype"), 1), _bits(attrs.get("conaffinity"), 1)
        if contype != 0 or conaffinity == 0 or not any(c & conaffinity for c in contypes):
            continue
        geom.set("contype", str(conaffinity))
        body = geom.getparent()
        owner = body.get("name") if body is not None and body.tag == "body" else None
        subject = f"geom '{geom.get('name')}'" if geom.get("name") else "<geom>"
        document.changed(
            geom,
            subject + (f" of body '{owner}'" if owner else ""),
            f'contype="0" conaffinity="{conaffinity}" (no collision shape in ManiSkill)',
            f'contype="{conaffinity}"',
        )


def _bits(text: str | None, default: int) -> int:
    try:
        return int(text) if text is not None else default
    except ValueError:
        return default


def suggest(document: Document) -> str | None:
    return "conaffinity" if document.would_change(apply, "conaffinity") else None
