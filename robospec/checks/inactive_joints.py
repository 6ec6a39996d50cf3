"""RS311: joint selections name active joints only (revolute, continuous, prismatic).

Passing::

    arm: {type: pd_joint_pos, joints: arm, stiffness: 1e3, damping: 1e2}

Failing (RS311: panda_hand_joint is fixed)::

    arm: {type: pd_joint_pos, joints: [arm, panda_hand_joint], stiffness: 1e3, damping: 1e2}

A fixed joint has no position to set or drive: ManiSkill's qpos and controllers know only the
active ones.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import JOINT_NOT_ACTIVE


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for path, name in context.bindings.joint_names:
        joint = context.description.joint(name)
        if joint is not None and not joint.is_active:
            yield error(
                context.value(path),
                JOINT_NOT_ACTIVE,
                f"joint '{name}' is {joint.type}, not an active joint",
                "only revolute, continuous and prismatic joints can be selected",
            )
