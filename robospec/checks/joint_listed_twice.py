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
from robospec.diagnostics.codes import JOINT_LISTED_TWICE


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for name in context.spec.controllers:
        path = ("controllers", name, "joints")
        seen: set[str] = set()
        twice: list[str] = []
        for joint in context.joints_at(path) or ():
            if joint in seen and joint not in twice:
                twice.append(joint)
            seen.add(joint)
        if twice:
            # one mistake (a group and a joint of it, say), one diagnostic naming every joint
            named = ", ".join(f"'{j}'" for j in twice)
            yield error(
                context.value(path),
                JOINT_LISTED_TWICE,
                f"joint{'s' if len(twice) > 1 else ''} {named} "
                f"{'are' if len(twice) > 1 else 'is'} listed twice",
                "list each joint once: a group already holds its joints",
            )
