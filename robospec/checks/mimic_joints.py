"""RS309: a URDF ``<mimic>`` joint becomes a PhysX mimic joint, which on its own goes NaN within
a few CPU steps. It is stable when a ``pd_joint_pos_mimic`` controller drives the pair too (as
ManiSkill's Panda does), so warn — at the ``<mimic>`` element — for each control mode that
leaves a URDF mimic joint to PhysX alone.

Passing: the Panda's ``panda_finger_joint2`` carries ``<mimic>``, and every mode drives both
fingers with a ``pd_joint_pos_mimic`` controller. Failing: a hand whose finger joints carry
``<mimic>`` tags and which no controller drives (``passive_joints`` or left out).
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.description.facts import Joint
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import URDF_MIMIC_SIMULATED


def unguarded_modes(context: CheckContext, joint: Joint) -> list[str]:
    """The control modes in which no ``pd_joint_pos_mimic`` controller drives ``joint``."""
    controllers = {c.name: c for c in context.robot.controllers}
    unguarded = []
    for mode in context.robot.modes:
        names = [n for _, n in mode.groups] if mode.groups is not None else [mode.controller]
        guarded = any(
            controllers[n].kind.mimic and joint.name in controllers[n].joint_names
            for n in names
            if n in controllers
        )
        if not guarded:
            unguarded.append(mode.name)
    return unguarded


def physx_mimic_joints(context: CheckContext, mode: str | None = None) -> list[Joint]:
    """Active joints whose URDF ``<mimic>`` PhysX simulates alone: in ``mode``, or in any mode."""
    return [
        joint
        for joint in context.description.joints
        if joint.mimic is not None
        and joint.is_active
        and (
            mode in unguarded_modes(context, joint)
            if mode is not None
            else bool(unguarded_modes(context, joint)) or not context.robot.modes
        )
    ]


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for joint in physx_mimic_joints(context):
        assert joint.mimic is not None
        modes = unguarded_modes(context, joint)
        where = f"in mode(s) {', '.join(modes)}" if modes else "(the spec has no control modes)"
        yield warning(
            context.at_description(joint.line),
            URDF_MIMIC_SIMULATED,
            f"joint '{joint.name}' mimics '{joint.mimic.joint}' and no pd_joint_pos_mimic "
            f"controller drives it {where}: "
            "SAPIEN turns URDF <mimic> into a PhysX mimic joint, which alone is unstable on the "
            "CPU (NaN within a few steps)",
            "drive the pair with a pd_joint_pos_mimic controller in every mode, and leave "
            "PhysX out of it with `description: {mend: {mimic: controller}}` (docs/mends.md)",
        )
