"""Gripper drives stiff enough to hold what they close on.

The natural-frequency gains ``new`` gives every joint (:mod:`.joint_gains`: 20 rad/s about the
joint's inertia) are a few newtons per metre for a finger of a few grams: the Panda's, as
``new`` scaffolds it, closes on PickCube's 4 cm cube with 0.1 N, under the 0.5 N its
``is_grasping`` needs, and the cube slips. A gripper holds by the force its drive makes at the
object, so its stiffness is set from the force it may make instead: the joint's force limit
reached across its whole stroke (``force_limit / stroke``), never below the natural-frequency
gains, with a tenth of it as damping, the ratio of ManiSkill's own grippers (the Panda's 1e3 and
1e2). The fingers then squeeze with up to their rated force whatever they close on.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

from robospec.authoring.new.analysis import RobotAnalysis
from robospec.authoring.new.gains import JointGains

GRIPPING_KINDS = ("gripper", "mimic")  # the groups whose joints close on objects
DAMPING_RATIO = 0.1  # damping per unit of stiffness: ManiSkill's grippers' (1e2 / 1e3)


def grip_gains(analysis: RobotAnalysis, gains: Mapping[str, JointGains]) -> dict[str, JointGains]:
    """``gains`` with each gripper joint's drive stiffened to reach its force limit over its
    stroke (joints with no finite stroke or no force limit keep theirs)."""
    out = dict(gains)
    groups = analysis.groups
    for name, kind in groups.kinds.items():
        if kind not in GRIPPING_KINDS:
            continue
        for joint_name in groups.groups[name]:
            drive = out.get(joint_name)
            joint = analysis.description.joint(joint_name)
            if drive is None or joint is None or joint.lower is None or joint.upper is None:
                continue
            stroke = joint.upper - joint.lower
            if not stroke > 0 or not drive.force_limit > 0:
                continue
            stiffness = max(drive.stiffness, drive.force_limit / stroke)
            damping = max(drive.damping, stiffness * DAMPING_RATIO)
            out[joint_name] = dataclasses.replace(drive, stiffness=stiffness, damping=damping)
    return out
