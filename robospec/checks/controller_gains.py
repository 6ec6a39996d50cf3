"""RS318: an end-effector controller with a stiffness far below any arm's needs (< 1).

ManiSkill's ``PDEEPoseControllerConfig`` takes ``joint_names, pos_lower, pos_upper, stiffness,
damping, force_limit, friction, ...`` positionally, with the rotation bounds further down;
arguments passed by position in another order (as xarm7_ability does upstream) silently land a
bound in ``stiffness``: 0.1 N·m/rad, and the arm sags instead of tracking. A warning, since
the numbers may be meant.

Passing: ``{type: pd_ee_pose, stiffness: 1e3, ...}``. Failing: ``{type: pd_ee_pose,
pos_lower: -0.1, pos_upper: 0.1, stiffness: 0.1, ...}``.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import EE_CONTROLLER_TOO_WEAK
from robospec.model.thresholds import MIN_EE_STIFFNESS


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for controller in context.robot.controllers:
        if not controller.kind.end_effector:
            continue
        stiffness = dict(controller.kwargs).get("stiffness")
        values = stiffness if isinstance(stiffness, list) else [stiffness]
        low = [v for v in values if isinstance(v, (int, float)) and v < MIN_EE_STIFFNESS]
        if not low:
            continue
        yield warning(
            context.value(("controllers", controller.name, "stiffness")),
            EE_CONTROLLER_TOO_WEAK,
            f"controller '{controller.name}' has stiffness {min(low)}: too weak for an arm to "
            "track an end-effector target",
            "if this came from Python, check the config's positional arguments: "
            "PDEEPoseControllerConfig takes joint_names, pos_lower, pos_upper, stiffness, "
            "damping, ... in that order",
        )
