"""RS319: a joint controller normalizes actions over joint limits that are infinite.

With ``lower``/``upper`` left to the joint limits and ``normalize_action: true``, ManiSkill maps
actions in [-1, 1] onto [lower, upper]; a continuous joint has no limits, so every action becomes
NaN and so does the simulation (fetch's ``pd_joint_pos_vel`` upstream).

Passing: ``{type: pd_joint_pos, lower: null, upper: null, normalize_action: false}`` on a
continuous joint. Failing: the same with ``normalize_action: true``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import UNBOUNDED_NORMALIZATION


def check(context: CheckContext) -> Iterator[Diagnostic]:
    if context.description.assumed:  # no limits known before the download
        return
    for controller in context.robot.controllers:
        kind, kwargs = controller.kind, dict(controller.kwargs)
        # a mimic controller's actions span only its control joints' limits: not judged here
        if not kind.joint_position_targets or kind.mimic:
            continue
        if not kwargs.get("normalize_action", kind.defaults["normalize_action"]):
            continue
        if kwargs.get("use_delta"):
            continue
        if kwargs.get("lower") is not None and kwargs.get("upper") is not None:
            continue
        unbounded = [
            joint.name
            for name in controller.joint_names
            if (joint := context.description.joint(name)) is not None
            and (
                joint.lower is None
                or joint.upper is None
                or not (math.isfinite(joint.lower) and math.isfinite(joint.upper))
            )
        ]
        if unbounded:
            yield warning(
                context.key(("controllers", controller.name)),
                UNBOUNDED_NORMALIZATION,
                f"controller '{controller.name}' normalizes actions over the limits of "
                f"{', '.join(unbounded)}, which are unbounded: every action becomes NaN",
                "set normalize_action: false, or give lower and upper",
            )
