"""A keyframe's ``pose`` as ManiSkill sets it on the robot's root link.

For a URDF robot the pose is the root link's, as written. For an MJCF robot it means what
MuJoCo means: the world pose of the robot's root body — the ``<worldbody>`` body, whose free
joint's ``qpos`` in a ``<key>`` is exactly that pose — and a keyframe without one leaves the
body where the file puts it (MuJoCo's ``qpos0``: the body's pos and orientation). ManiSkill's
loader hangs that body below a dummy root link at its file pose (or, for a wrapper body it
skips, makes the root link play its part), so the root link's pose is the wanted body pose
times the inverse of that offset. A keyframe pose of ``{p: [0, 0, 1.3]}`` thus puts the body at
1.3 m, as ``<key qpos="0 0 1.3 1 0 0 0 ...">`` does in MuJoCo.
"""

from __future__ import annotations

from robospec.description.facts import RobotDescription
from robospec.geometry import IDENTITY_POSE, Pose, compose, inverse


def root_link_pose(description: RobotDescription, pose: Pose | None) -> Pose:
    """The root link's pose for a keyframe ``pose`` (None: the keyframe gives none)."""
    offset = description.root_body_offset
    if offset is None or description.root_body_pose is None:
        return pose if pose is not None else IDENTITY_POSE
    wanted = pose if pose is not None else description.root_body_pose
    if offset == IDENTITY_POSE:
        return wanted
    return compose(wanted, inverse(offset))


def root_body_pose(description: RobotDescription, root_link: Pose) -> Pose:
    """The inverse: the keyframe pose (as a spec writes it) of a root link pose."""
    offset = description.root_body_offset
    if offset is None or offset == IDENTITY_POSE:
        return root_link
    return compose(root_link, offset)
