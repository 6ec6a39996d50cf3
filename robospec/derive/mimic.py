"""Mend class ``mimic: controller`` (RS710): URDF ``<mimic>`` tags PhysX simulates badly.

SAPIEN turns a URDF ``<mimic>`` into a PhysX mimic joint, which goes NaN within a few CPU steps
(ManiSkill's inspire hands, xarm7_ability; RS309). The stable route is ManiSkill's
``pd_joint_pos_mimic`` controller, which drives the follower joints from their leader. This
mend removes the tags from the derived copy, so nothing but the controller couples the
joints; ``robospec new`` writes that controller with the description's mimic map.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.diagnostics.codes import MENDED_MIMIC

NAME = "mimic"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_MIMIC
FIXES: tuple[str, ...] = ()  # RS309 (a check) names this mend in its hint
WHY = "PhysX's mimic couplings go NaN or fight the drives: the mimic controller couples them"


def apply(document: Document, policy: str) -> None:
    for joint in document.tree.iterfind("joint"):
        mimic = joint.find("mimic")
        if mimic is None:
            continue
        follows = mimic.get("joint")
        ratio = mimic.get("multiplier", "1")
        document.changed(
            mimic,
            f"joint '{joint.get('name')}' <mimic>",
            f"follows '{follows}' x{ratio} in PhysX",
            "removed (its controller couples it)",
        )
        document.remove(mimic)


def suggest(document: Document) -> str | None:
    """Never by itself: the scaffold already drives every mimic pair with a
    ``pd_joint_pos_mimic`` controller, beside which PhysX's mimic joint holds (RS309 warns
    where none does); the mend is for specs that want PhysX out of it altogether. ``new``
    writes it itself for a linkage the URDF cuts open (robospec.authoring.new.scaffold), whose
    tendons and drives jam it, and for a gripper of closed loops (its analysis)."""
    return None
