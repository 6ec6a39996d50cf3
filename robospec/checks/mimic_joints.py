"""RS309: a URDF ``<mimic>`` joint becomes a PhysX mimic joint, which goes NaN within a few
CPU steps. Warn, at the ``<mimic>`` element, and point to the stable route.

Passing: a two-finger gripper without ``<mimic>`` tags, driven by a ``pd_joint_pos_mimic``
controller. Failing: a URDF joint carrying ``<mimic joint="finger_joint1"/>``.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, Location, warning


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for joint in context.description.joints:
        if joint.mimic is None or not joint.is_active:
            continue
        yield warning(
            Location(context.description_file, joint.line, 1),
            "RS309",
            f"joint '{joint.name}' mimics '{joint.mimic.joint}': SAPIEN turns URDF <mimic> into "
            "a PhysX mimic joint, which is unstable on the CPU (NaN within a few steps)",
            "remove the <mimic> tag and drive both joints with a pd_joint_pos_mimic controller",
        )
