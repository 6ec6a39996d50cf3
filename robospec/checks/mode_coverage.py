"""RS301, RS302: each control mode drives every active joint exactly once.

Passing::

    control_modes:
      pd_joint_pos: {arm: arm_pos, gripper: gripper}   # arm + gripper = all active joints

Failing (RS302: the gripper joints are not driven)::

    control_modes:
      pd_joint_pos: {arm: arm_pos}

Joints listed in ``passive_joints``, and joints the description itself makes mimic joints, need
no controller.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import JOINT_DRIVEN_TWICE, JOINT_NOT_DRIVEN


def check(context: CheckContext) -> Iterator[Diagnostic]:
    controllers = {c.name: c for c in context.robot.controllers}
    exempt = set(context.passive_joints) | {
        j.name for j in context.description.joints if j.mimic is not None
    }
    for mode in context.robot.modes:
        path = ("control_modes", mode.name)
        members = mode.groups if mode.groups is not None else (("", mode.controller or ""),)
        driven: dict[str, str] = {}
        for group, name in members:
            controller = controllers.get(name)
            if controller is None:
                continue  # unknown controller: reported by resolve
            # one diagnostic per pair of controllers, naming every joint they share
            shared: dict[str, list[str]] = {}
            for joint in controller.joint_names:
                if joint in driven and driven[joint] != name:
                    shared.setdefault(driven[joint], []).append(joint)
                driven.setdefault(joint, name)
            where = (*path, group) if group else path
            for other, joints in shared.items():
                named = ", ".join(f"'{j}'" for j in joints)
                yield error(
                    context.value(where),
                    JOINT_DRIVEN_TWICE,
                    f"joint{'s' if len(joints) > 1 else ''} {named} "
                    f"{'are' if len(joints) > 1 else 'is'} driven by both '{other}' and "
                    f"'{name}' in mode '{mode.name}'",
                    f"a mode drives each joint once: leave {named} out of the joints of "
                    f"'{name}' or of '{other}' (a group can say {{all_but: ...}})",
                )
        missing = [
            j for j in context.description.active_joint_names if j not in driven and j not in exempt
        ]
        if missing:
            yield error(
                context.key(path),
                JOINT_NOT_DRIVEN,
                f"control mode '{mode.name}' drives no controller for "
                + ", ".join(f"'{j}'" for j in missing),
                "add a controller for them, or list them in passive_joints",
            )
