"""RS310: a controller lists each of its joints once.

Passing::

    arm: {type: pd_joint_pos, joints: arm, stiffness: 1e3, damping: 1e2}

Failing (RS310: panda_joint1 is in the arm group already)::

    arm: {type: pd_joint_pos, joints: [arm, panda_joint1], stiffness: 1e3, damping: 1e2}
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for name in context.spec.controllers:
        path = ("controllers", name, "joints")
        seen: set[str] = set()
        for joint in context.joints_at(path) or ():
            if joint in seen:
                yield error(context.value(path), "RS310", f"joint '{joint}' is listed twice")
            seen.add(joint)
