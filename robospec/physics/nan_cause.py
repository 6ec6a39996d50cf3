"""Why a robot's state went NaN in a control mode, when robospec can tell: the same words for
``robospec check`` (RS502) and for ``scripts/demo``.

- URDF ``<mimic>`` joints that no ``pd_joint_pos_mimic`` controller drives in the mode: SAPIEN
  turns them into PhysX mimic joints, which alone go NaN within a few CPU steps (what ``validate``
  warns about, the description's ``<mimic>`` line included).
- Actions normalized to [-1, 1] over infinite bounds (a continuous joint's limits): the targets
  are infinite from the first step.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from robospec.checks.context import CheckContext
from robospec.checks.mimic_joints import physx_mimic_joints

if TYPE_CHECKING:
    from mani_skill.agents.controllers.base_controller import BaseController


@dataclass(frozen=True)
class NanCause:
    cause: str  # "the URDF <mimic> tags (...): SAPIEN turns them into ..."
    hint: str
    brief: str = ""  # the cause in fewer words (scripts/demo's note): the pairs counted

    def __post_init__(self) -> None:
        if not self.brief:
            object.__setattr__(self, "brief", self.cause)


def nan_cause(
    context: CheckContext, mode: str, controllers: Iterable[tuple[str, BaseController]]
) -> NanCause | None:
    """The cause for ``mode``, whose ``(group, ManiSkill controller)`` pairs are given, or
    None when it is none of the known ones."""
    mimics = [j for j in physx_mimic_joints(context, mode) if j.mimic is not None]
    if mimics:
        pairs = ", ".join(f"'{j.name}' mimics '{j.mimic.joint}'" for j in mimics if j.mimic)
        where = context.at_description(mimics[0].line)
        physx = "SAPIEN turns them into PhysX mimic joints, which alone go NaN on the CPU"
        return NanCause(
            f"the URDF <mimic> tags ({pairs}; {where.file}:{where.line}): {physx}",
            "remove the <mimic> tags from the URDF and drive each pair with a "
            "pd_joint_pos_mimic controller, e.g. mimic: {"
            + ", ".join(f"{j.name}: {j.mimic.joint}" for j in mimics if j.mimic)
            + "}",
            f"the URDF's {len(mimics)} <mimic> tags ({Path(where.file).name}:{where.line}): "
            f"{physx}",
        )
    unbounded = [f"group '{name}'" for name, c in controllers if _normalized_over_infinity(c)]
    if unbounded:
        return NanCause(
            f"{', '.join(unbounded)}: actions normalized to [-1, 1] over infinite joint limits "
            "scale to infinite targets",
            "give the controller finite lower/upper, or set normalize_action: false",
        )
    return None


def _normalized_over_infinity(controller: BaseController) -> bool:
    if not getattr(controller.config, "normalize_action", False):
        return False
    low = controller.action_space_low.cpu().numpy()
    high = controller.action_space_high.cpu().numpy()
    return not (np.isfinite(low).all() and np.isfinite(high).all())
