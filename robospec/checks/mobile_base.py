"""RS341, RS342: a planar base (``mobile_base``) drives a robot that has a base to drive.

The derived copy puts an x slide, a y slide and a z hinge above the base link. That makes
sense for a robot on wheels or casters, for a platform with no joint at all, and for a base
the description hangs from a ``planar``, ``floating`` or ``fixed`` joint; on an arm that the
description roots at its own base, with nothing that touches the floor, it mounts the arm on a
moving pedestal that no one asked for (RS341). The chain starts from a fixed root, so the
robot's root cannot also float (RS342).

Passing (Husky's wheels roll on nothing: the base slides)::

    mobile_base: {wheels: "*_wheel_link"}

Failing (RS341: the KUKA arm has no wheel, caster or planar root)::

    mobile_base: {}
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import PLANAR_BASE_NOTHING_DRIVES, PLANAR_BASE_ON_FLOATING_ROOT


def check(context: CheckContext) -> Iterator[Diagnostic]:
    base = context.robot.mobile_base
    if base is None:
        return
    # here, not above: validate of a spec without a planar base loads neither
    from robospec.derive.planar_base import ADDED_ROOT
    from robospec.kinematics.morphology import WHEEL_WORDS

    description = context.description
    if not context.robot.fix_root_link:
        yield error(
            context.value(("loader", "fix_root_link"))
            if "loader" in context.spec.model_fields_set
            else context.key(("mobile_base",)),
            PLANAR_BASE_ON_FLOATING_ROOT,
            "a planar base starts from a fixed root, and loader.fix_root_link is false",
            "set loader.fix_root_link to true (the base's slides and hinge move the robot)",
        )
    x_joint = description.joint(base.joints[0])
    rooted = x_joint is not None and x_joint.parent.startswith(ADDED_ROOT)
    own = [
        j
        for j in description.active_joint_names
        if j not in base.joints and j not in base.wheel_joints
    ]
    touches_floor = bool(base.wheels) or any(WHEEL_WORDS.search(n) for n in description.link_names)
    if rooted and own and not touches_floor:
        yield error(
            context.key(("mobile_base",)),
            PLANAR_BASE_NOTHING_DRIVES,
            f"a planar base under '{base.link}', a robot with no wheel or caster and "
            f"{len(own)} joint(s) of its own: the description fixes it where it stands (an "
            "arm), and nothing of it would drive",
            "name the links that touch the floor in mobile_base.wheels, or mount the robot "
            "on a mobile base (parts:); a fixed arm needs no mobile_base",
        )
