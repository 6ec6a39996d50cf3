"""Mend class ``angles: radian`` (RS728, MJCF): a model written in radians that does not say so.

MJCF's angles are degrees unless ``<compiler angle="radian"/>`` says otherwise (RS086), and
MuJoCo and ManiSkill both read them so. A file that is a fragment of a larger model — robosuite's
Robotiq 2F-85 and 2F-140 grippers, which robosuite merges into robots whose compilers say
``radian`` — leaves the unit to the model it is merged into: read alone, its hinges turn a 57th
of what they were written for (the 2F-85's fingers close by 0.8°). The mend writes
``angle="radian"`` on the model's ``<compiler>`` (one is added where there is none; a model
that says its unit is left as it is): every
``range``, ``ref``, ``euler`` and ``axisangle`` is then read as written.

``robospec new`` writes it only where degrees cannot be meant: the model gives no unit, has
limited hinges, and every hinge's range stays within ±π — in degrees, no joint of the robot
would turn more than 3.2° either way.
"""

from __future__ import annotations

import math
from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import classes, effective, in_model, whole
from robospec.diagnostics.codes import MENDED_ANGLES, MJCF_DEGREES

NAME = "angles"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_ANGLES
FIXES = (MJCF_DEGREES,)
WHY = "its hinge ranges are radians, though the model does not say so (MJCF reads degrees)"

# the largest hinge range end (in the file's numbers) that says radians: as degrees, every
# joint would turn no further than this either way
RADIAN_BOUND = math.pi


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    compiler = root.find("compiler")
    if compiler is not None and compiler.get("angle") is not None:
        return  # the model says its unit: nothing to mend
    if compiler is None:
        # on the root's own line, every element after it kept on its line
        compiler = etree.Element("compiler")
        compiler.tail, root.text = root.text, ""
        root.insert(0, compiler)
    compiler.set("angle", policy)
    at = compiler if isinstance(compiler.sourceline, int) else root
    document.changed(
        at,
        "<compiler>",
        "no angle= (degrees)",
        f'angle="{policy}"',
    )


def suggest(document: Document) -> str | None:
    """``radian`` where the model gives no unit and every limited hinge's range is within
    ±π; else nothing."""
    root = whole(document)
    compiler = root.find("compiler")
    if compiler is not None and compiler.get("angle") is not None:
        return None
    table = classes(root, document.source.path)
    ends: list[float] = []
    for joint in root.iter("joint"):
        if not in_model(joint):
            continue
        attributes = effective(table, joint)
        if attributes.get("type", "hinge") != "hinge" or "range" not in attributes:
            continue
        try:
            ends += [abs(float(v)) for v in attributes["range"].split()]
        except ValueError:
            return None  # the model's parse says what is wrong with it
    if not ends or max(ends) > RADIAN_BOUND or max(ends) == 0:
        return None
    return "radian"
