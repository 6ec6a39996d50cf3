"""RS305: a ``pd_joint_pos_mimic`` controller's mimic map pairs its own joints, each once.

Passing::

    gripper: {type: pd_joint_pos_mimic, joints: gripper, lower: 0, upper: 0.04,
              stiffness: 1e3, damping: 1e2, mimic: {panda_finger_joint2: panda_finger_joint1}}

Failing (RS305: panda_joint1 is not one of the controller's joints)::

    gripper: {type: pd_joint_pos_mimic, joints: gripper, lower: 0, upper: 0.04,
              stiffness: 1e3, damping: 1e2, mimic: {panda_finger_joint2: panda_joint1}}

Also: a joint that mimics itself, a joint that both mimics and is mimicked, and a controller
joint the map leaves out. (A name that is no joint at all is RS201.)
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import INCONSISTENT_MIMIC


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for name, config in context.spec.controllers.items():
        mimic = getattr(config, "mimic", None)
        joints = context.joints_at(("controllers", name, "joints"))
        if not mimic or joints is None:
            continue
        path = ("controllers", name, "mimic")
        followers: set[str] = set()
        leaders: set[str] = set()
        for follower, target in mimic.items():
            leader = target if isinstance(target, str) else target.joint
            for joint in (follower, leader):
                if joint not in joints and context.description.joint(joint) is not None:
                    yield error(
                        context.value((*path, follower)),
                        INCONSISTENT_MIMIC,
                        f"mimic joint '{joint}' is not one of this controller's joints",
                    )
            if follower == leader:
                yield error(
                    context.value((*path, follower)),
                    INCONSISTENT_MIMIC,
                    f"joint '{follower}' mimics itself",
                )
            followers.add(follower)
            leaders.add(leader)
        if followers & leaders:
            both = ", ".join(sorted(followers & leaders))
            yield error(
                context.value(path),
                INCONSISTENT_MIMIC,
                f"joint(s) {both} both mimic and are mimicked",
            )
        uncovered = [j for j in joints if j not in followers | leaders]
        if uncovered:
            yield error(
                context.value(path),
                INCONSISTENT_MIMIC,
                "every joint of a mimic controller must appear in the mimic map; missing: "
                + ", ".join(uncovered),
            )
