"""RS313: values written by joint or group name set each joint once.

Passing::

    keyframes:
      rest: {qpos: {arm: [0, 0, 0, -2, 0, 2, 0.8], gripper: 0.04}}

Failing (RS313: panda_finger_joint1 is in the gripper group and named again)::

    keyframes:
      rest: {qpos: {arm: [0, 0, 0, -2, 0, 2, 0.8], gripper: 0.04, panda_finger_joint1: 0.02}}

The same holds for a controller's per-joint values (``stiffness: {arm: 1e3, ...}``).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import KEYFRAME_SETS_JOINT_TWICE
from robospec.load.source_map import KeyPath
from robospec.model.controller_kinds import controller_kind


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for name, frame in context.spec.keyframes.items():
        for field in ("qpos", "qvel"):
            values = getattr(frame, field)
            if isinstance(values, dict):
                path = ("keyframes", name, field)
                yield from _twice(context, values, path, None, "is set twice")
    for name, config in context.spec.controllers.items():
        driven = context.joints_at(("controllers", name, "joints"))
        if driven is None:
            continue
        # (not the bounds of a base's forward speed and turn rate: they are by axis)
        for field in controller_kind(config.type).per_joint:
            value = getattr(config, field, None)
            if isinstance(value, dict):
                path = ("controllers", name, field)
                yield from _twice(context, value, path, driven, "is given a value twice")


def _twice(
    context: CheckContext,
    values: dict[str, Any],
    path: KeyPath,
    driven: Iterable[str] | None,
    says: str,
) -> Iterator[Diagnostic]:
    """Each joint set again after an earlier key set it; ``driven``: the joints that may be
    set at all (another joint is RS201, reported by resolve)."""
    seen: set[str] = set()
    for key, item in values.items():
        joints = context.joints_at((*path, key))
        if joints is None or (isinstance(item, list) and len(item) != len(joints)):
            continue
        for joint in joints:
            if joint in seen and (driven is None or joint in driven):
                yield error(
                    context.value((*path, key)),
                    KEYFRAME_SETS_JOINT_TWICE,
                    f"joint '{joint}' {says}",
                )
            seen.add(joint)
