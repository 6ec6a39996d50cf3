"""Mend class ``integers: round`` (RS708): whole numbers written as decimals where SAPIEN reads
an integer.

SAPIEN's URDF loader reads a camera sensor's image ``width`` and ``height`` with ``int()``, which
refuses ``"640.0"`` (RS052). A decimal that is a whole number is written as that integer.
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.diagnostics.codes import INVALID_STRUCTURE, MENDED_INTEGERS

NAME = "integers"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_INTEGERS
FIXES = (INVALID_STRUCTURE,)
WHY = "sizes SAPIEN reads as integers are written as decimals"


def apply(document: Document, policy: str) -> None:
    for image in document.tree.iter("image"):
        camera = image.getparent()
        if camera is None or camera.tag != "camera":
            continue
        for size in ("width", "height"):
            element = image.find(size)
            if element is not None:
                _round_text(document, element, f"camera <image> <{size}>")
            elif image.get(size) is not None:
                whole = _whole(image.get(size, ""))
                if whole is not None:
                    document.changed(image, f"camera <image> {size}=", image.get(size, ""), whole)
                    image.set(size, whole)


def _round_text(document: Document, element: etree._Element, subject: str) -> None:
    whole = _whole(element.text or "")
    if whole is not None:
        document.changed(element, subject, (element.text or "").strip(), whole)
        element.text = whole


def _whole(raw: str) -> str | None:
    """The integer a decimal such as ``640.0`` writes; None when it is one already or none."""
    text = raw.strip()
    if not text or text.lstrip("+-").isdigit():
        return None
    try:
        value = float(text)
    except ValueError:
        return None
    return str(int(value)) if value.is_integer() else None


def suggest(document: Document) -> str | None:
    return "round" if document.would_change(apply, "round") else None
