"""RS315: a mobile-base controller drives at least three joints: x, y and yaw.

Passing::

    groups:
      base: [root_x_axis_joint, root_y_axis_joint, root_z_rotation_joint]
    controllers:
      base: {type: pd_base_vel, joints: base, lower: -1, upper: 1, damping: 1000}

Failing (RS315: two joints)::

    controllers:
      base: {type: pd_base_vel, joints: [root_x_axis_joint, root_y_axis_joint],
             lower: -1, upper: 1, damping: 1000}
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import JOINT_WRONG_FOR_CONTROLLER
from robospec.model.controller_kinds import controller_kind


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for name, config in context.spec.controllers.items():
        path = ("controllers", name, "joints")
        joints = context.joints_at(path)
        fewest = controller_kind(config.type).min_joints
        if joints is not None and len(joints) < fewest:
            yield error(
                context.value(path),
                JOINT_WRONG_FOR_CONTROLLER,
                f"{config.type} drives x, y and yaw joints: "
                f"needs at least {fewest} joints, got {len(joints)}",
            )
