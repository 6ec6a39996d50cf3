"""RS304: a keyframe's joint positions lie within the joints' limits.

Passing::

    keyframes:
      rest: {qpos: {arm: [0, pi/8, 0, -5*pi/8, 0, 3*pi/4, pi/4], gripper: 0.04}}

Failing (RS304: panda_joint4 must stay in [-3.0718, -0.0698])::

    keyframes:
      rest: {qpos: {arm: [0, pi/8, 0, 0, 0, 3*pi/4, pi/4], gripper: 0.04}}

Each value is checked where it is written, within a tolerance of 1e-6.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import KEYFRAME_OUTSIDE_LIMITS
from robospec.load.source_map import KeyPath
from robospec.model.thresholds import LIMIT_TOLERANCE


def check(context: CheckContext) -> Iterator[Diagnostic]:
    if context.description.assumed:  # no limits are known
        return
    for name, frame in context.spec.keyframes.items():
        for value_path, joint_name, number in _written(
            context, frame.qpos, ("keyframes", name, "qpos")
        ):
            joint = context.description.joint(joint_name)
            assert joint is not None
            low = -math.inf if joint.lower is None else joint.lower
            high = math.inf if joint.upper is None else joint.upper
            if not low - LIMIT_TOLERANCE <= number <= high + LIMIT_TOLERANCE:
                yield error(
                    context.value(value_path),
                    KEYFRAME_OUTSIDE_LIMITS,
                    f"{number:g} is outside the limits of '{joint.name}' [{low:g}, {high:g}]",
                )


def _written(
    context: CheckContext, values: object, path: KeyPath
) -> Iterator[tuple[KeyPath, str, float]]:
    """(where, joint, value) for each value that bound to a joint, in the order written."""
    active = context.description.active_joint_names
    if isinstance(values, list):
        if len(values) == len(active):
            for index, (joint, number) in enumerate(zip(active, values, strict=True)):
                yield (*path, index), joint, number
    elif isinstance(values, dict):
        for key, item in values.items():
            joints = context.joints_at((*path, key))
            if joints is None:
                continue
            if not isinstance(item, list):
                for joint in joints:
                    yield (*path, key), joint, item
            elif len(item) == len(joints):
                for index, (joint, number) in enumerate(zip(joints, item, strict=True)):
                    yield (*path, key, index), joint, number
