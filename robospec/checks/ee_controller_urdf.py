"""RS325: an end-effector controller on an MJCF robot names a URDF for its IK.

``pd_ee_pos`` and ``pd_ee_pose`` solve inverse kinematics with ManiSkill's ``Kinematics``,
which reads the robot from ``urdf_path``; ManiSkill's own agents pass their URDF. An MJCF
robot has none, so the controller needs ``urdf_path`` naming a URDF of the same robot, or
``gym.make`` fails when the controller is built.

Passing::

    description: {mjcf: arm.xml}
    controllers:
      arm_ee: {type: pd_ee_pose, joints: arm, urdf_path: arm.urdf, ee_link: hand,
               pos_lower: -0.1, pos_upper: 0.1, rot_lower: -0.1, rot_upper: 0.1,
               stiffness: 1e3, damping: 1e2}

Failing (RS325: no urdf_path)::

    description: {mjcf: arm.xml}
    controllers:
      arm_ee: {type: pd_ee_pose, joints: arm, ee_link: hand,
               pos_lower: -0.1, pos_upper: 0.1, rot_lower: -0.1, rot_upper: 0.1,
               stiffness: 1e3, damping: 1e2}
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import EE_CONTROLLER_WITHOUT_URDF
from robospec.model.controller_kinds import controller_kind


def check(context: CheckContext) -> Iterator[Diagnostic]:
    if context.robot.description_kind != "mjcf":
        return
    for name, config in context.spec.controllers.items():
        if not controller_kind(config.type).end_effector:
            continue
        # an end-effector kind's config (the kinds' registry says which): it has urdf_path
        if (
            "urdf_path" in config.model_fields_set
            and getattr(config, "urdf_path", None) is not None
        ):
            continue
        yield error(
            context.value(("controllers", name, "type")),
            EE_CONTROLLER_WITHOUT_URDF,
            f"{config.type} solves its IK from a URDF (urdf_path), and an MJCF robot has "
            "none: ManiSkill fails to build this controller",
            "add urdf_path: naming a URDF of the same robot, or drive the joints with "
            "pd_joint_pos/pd_joint_delta_pos",
        )
