"""Mend class ``limits`` (RS709): revolute and prismatic joints without a lower or upper limit.

SAPIEN's URDF parser leaves a missing ``lower``/``upper`` as None and turns it into a NaN limit;
a revolute or prismatic joint without any ``<limit>`` stops the load (RS052). Exporters write
such joints for wheels and free spinners. ``continuous`` makes each such revolute joint
continuous (what a joint without limits is); a range ``[lower, upper]`` writes it where a
bound is missing, for revolute and prismatic joints alike. A prismatic joint has no
continuous form: with ``continuous`` it is refused, with the range to write in the hint.
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.diagnostics.codes import CANNOT_MEND, INVALID_STRUCTURE, MENDED_LIMITS

NAME = "limits"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_LIMITS
FIXES = (INVALID_STRUCTURE,)
WHY = "revolute joints have no lower/upper limit (SAPIEN would make the limit NaN)"


def apply(document: Document, policy: str | list[float]) -> None:
    for joint in document.tree.iterfind("joint"):
        kind = joint.get("type")
        if kind not in ("revolute", "prismatic"):
            continue
        limit = joint.find("limit")
        missing = [a for a in ("lower", "upper") if limit is None or limit.get(a) is None]
        if not missing:
            continue
        subject = f"joint '{joint.get('name')}'"
        if isinstance(policy, str):
            if kind == "prismatic":
                document.refuse(
                    limit if limit is not None else joint,
                    CANNOT_MEND,
                    f"mend 'limits: continuous' cannot mend prismatic {subject}: it has no "
                    f"{' or '.join(missing)} limit, and a prismatic joint cannot be continuous",
                    "give the range instead: limits: [lower, upper] (metres)",
                )
                continue
            joint.set("type", "continuous")
            document.changed(joint, subject, f"revolute without {'/'.join(missing)}", "continuous")
            continue
        if limit is None:
            limit = etree.SubElement(joint, "limit")
            if len(joint) > 1:  # on the last element's line: every element keeps its line
                limit.tail, joint[-2].tail = joint[-2].tail, " "
            # urchin reads effort and velocity from every <limit>
            limit.set("effort", "0")
            limit.set("velocity", "0")
        for attribute, value in zip(("lower", "upper"), policy, strict=True):
            if attribute in missing:
                limit.set(attribute, f"{float(value):.12g}")
        written = ", ".join(f"{a}={limit.get(a)}" for a in missing)
        document.changed(joint, subject, f"{kind} without {'/'.join(missing)}", written)


def suggest(document: Document) -> str | None:
    """``continuous`` when only revolute joints lack limits; a prismatic one needs a range
    only the user knows (the refusal says so)."""
    return "continuous" if document.would_change(apply, "continuous") else None
