"""Mend class ``textures: drop`` (RS704): ``<texture/>`` elements without a file.

SAPIEN's URDF parser stops at a material's ``<texture>`` that names no file (RS052; iCub has
28). A texture with no image draws nothing: removing the element changes no picture.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.diagnostics.codes import INVALID_STRUCTURE, MENDED_TEXTURES

NAME = "textures"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_TEXTURES
FIXES = (INVALID_STRUCTURE,)
WHY = "materials hold empty <texture/> elements, at which SAPIEN's parser stops"


def apply(document: Document, policy: str) -> None:
    root = document.tree
    for texture in [
        *root.iterfind("link/visual/material/texture"),
        *root.iterfind("material/texture"),
    ]:
        if texture.get("filename") is not None:
            continue
        material = texture.getparent()
        name = material.get("name") if material is not None else None
        subject = f"material '{name}' <texture>" if name else "<material> <texture>"
        document.changed(texture, subject, "<texture/> without filename", "removed")
        document.remove(texture)


def suggest(document: Document) -> str | None:
    return "drop" if document.would_change(apply, "drop") else None
