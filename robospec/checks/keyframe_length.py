"""RS303: a keyframe gives every active joint exactly one value.

Passing::

    keyframes:
      rest: {qpos: {arm: [0, pi/8, 0, -5*pi/8, 0, 3*pi/4, pi/4], gripper: 0.04}}

Failing (RS303: the panda has 9 active joints)::

    keyframes:
      rest: {qpos: [0, 0.39, 0, -1.96, 0, 2.36, 0.79, 0.04]}

``qpos`` and ``qvel`` are checked alike. A joint or group name that did not bind is reported
where it is written (RS201) and not again as joints left without a value.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import KEYFRAME_LENGTH


def check(context: CheckContext) -> Iterator[Diagnostic]:
    if context.description.assumed:  # the joints are not known; resolve says what that needs
        return
    active = context.description.active_joint_names
    for name, frame in context.spec.keyframes.items():
        for field in ("qpos", "qvel"):
            values = getattr(frame, field)
            path = ("keyframes", name, field)
            if isinstance(values, list):
                if len(values) != len(active):
                    yield error(
                        context.value(path),
                        KEYFRAME_LENGTH,
                        f"expected {len(active)} values, one per active joint "
                        f"({', '.join(active)}), got {len(values)}",
                    )
            elif values is not None:
                yield from _by_name(context, values, path, active)


def _by_name(
    context: CheckContext, values: dict, path: tuple, active: tuple[str, ...]
) -> Iterator[Diagnostic]:
    covered: set[str] = set()
    whole = True
    for key, item in values.items():
        joints = context.joints_at((*path, key))
        if joints is None:
            whole = False
            continue
        if isinstance(item, list) and len(item) != len(joints):
            yield error(
                context.value((*path, key)),
                KEYFRAME_LENGTH,
                f"'{key}' has {len(joints)} joints but {len(item)} values",
            )
            whole = False
            continue
        covered.update(joints)
    # joints of mounted parts take their values from the parts' keyframes (merged by joint)
    missing = [j for j in active if j not in covered and j not in context.filled_by_parts]
    if missing and whole:
        yield error(
            context.value(path),
            KEYFRAME_LENGTH,
            "no value for active joint(s) " + ", ".join(missing),
        )
