"""Mend class ``orientations: quat`` (RS721, MJCF): frames ManiSkill's loader turns otherwise.

ManiSkill's MJCF loader reads ``euler`` with its second angle negated and ``<compiler
eulerseq>`` ignored, takes ``xyaxes``' y axis for the frame's z axis, turns ``zaxis`` frames
about their z axis, and divides by zero on a ``zaxis`` along ±z (RS080;
:mod:`robospec.description.mjcf_frames` measured each against MuJoCo). ``quat`` it reads as
MuJoCo does. Each body and geom whose rotation the loader reads otherwise is written with the
``quat`` MuJoCo computes for it: nothing MuJoCo reads changes.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import classes, degrees, effective, in_model, whole
from robospec.description.mjcf_frames import (
    ORIENTATION_ATTRIBUTES,
    Unparsable,
    maniskill_rotation,
    mujoco_rotation,
    orientation_attribute,
    same_rotation,
)
from robospec.diagnostics.codes import MENDED_ORIENTATIONS, MJCF_ORIENTATION

NAME = "orientations"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_ORIENTATIONS
FIXES = (MJCF_ORIENTATION,)
WHY = "ManiSkill's loader reads euler, xyaxes or zaxis frames turned otherwise than MuJoCo"


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    table = classes(root, document.source.path)
    use_degrees, eulerseq = degrees(root)
    compiler = root.find("compiler")
    unsaid = compiler is None or compiler.get("angle") is None
    for element in root.iter("body", "geom"):
        if not in_model(element):
            continue
        attributes = effective(table, element) if element.tag == "geom" else dict(element.attrib)
        name = orientation_attribute(attributes)
        if name is None or name in ("quat", "axisangle") or "fromto" in attributes:
            continue
        try:
            meant = mujoco_rotation(attributes, use_degrees, eulerseq)
            theirs = maniskill_rotation(attributes, use_degrees)
        except Unparsable:
            continue  # the model's parse says what is wrong with it
        if theirs is not None and same_rotation(theirs, meant, 1e-9):
            continue
        for attribute in ORIENTATION_ATTRIBUTES:
            element.attrib.pop(attribute, None)
        written = " ".join(f"{0.0 if abs(v) < 1e-15 else v:.12g}" for v in meant)
        element.set("quat", written)
        label = element.get("name")
        # the angles leave the model with this mend, and RS086 with them: say how they were read
        read_as = " (degrees: no <compiler angle>)" if unsaid and name == "euler" else ""
        document.changed(
            element,
            f"{element.tag!s} '{label}'" if label else f"<{element.tag!s}>",
            f'{name}="{attributes[name]}"{read_as}'
            + (" (ManiSkill's loader fails on it)" if theirs is None else ""),
            f'quat="{written}"',
        )


def suggest(document: Document) -> str | None:
    return "quat" if document.would_change(apply, "quat") else None
