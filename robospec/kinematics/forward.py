"""Where a robot's links are at given joint values, and which way its joints move: computed by
the libraries that define the formats, never by robospec.

* a URDF: yourdfpy's forward kinematics (:mod:`.urdf_poses`);
* an MJCF: MuJoCo's compiler and ``mj_kinematics`` (:mod:`.mjcf_poses`);
* a robot loaded in ManiSkill: SAPIEN itself (:mod:`.simulated`), for the tools that run it.

The tree is the robot's facts' (``RobotDescription.tree_joints``): ManiSkill's links and joints,
named as a spec names them (an MJCF body with two joints is two links, the first
``{body}_dummy_0``; its root is ``dummy_root_{i}``), so every name agrees with the rest of
robospec. Each backend computes the poses of the file that the tool reads — the derived copy
when the description needs mends, a xacro file's expansion — which robospec's own parse has
already accepted (yourdfpy accepts broken files silently: robospec's parse stays the validator).

Poses are 4x4 numpy arrays in the root link's frame. numpy, yourdfpy and MuJoCo are imported
by the functions that need them: nothing here is on ``validate``'s path.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from robospec.description import Joint, RobotDescription
from robospec.kinematics.placement import Placement, Poser

if TYPE_CHECKING:
    import numpy as np


class KinematicModel:
    """A robot's kinematic tree and where its links are at any joint values."""

    def __init__(self, description: RobotDescription, poser: Poser) -> None:
        self.root = description.root_link
        self.joints: tuple[Joint, ...] = description.tree_joints  # parents before children
        self._by_name = {joint.name: joint for joint in self.joints if joint.name}
        self._poser = poser

    def at(self, qpos: Mapping[str, float] | None = None) -> Placement:
        """The links and axes with the joints at ``qpos`` (by name; 0 for those it leaves
        out, as ManiSkill starts a robot)."""
        return self._poser(qpos or {})

    def link(self, qpos: Mapping[str, float], name: str) -> np.ndarray:
        """One link's pose at ``qpos``: for a search that moves one chain and watches its end
        (new's ready pose), where placing every link of a large robot each step is the cost
        (TIAGo: 5 minutes). A backend that can place one link alone does (yourdfpy)."""
        one = getattr(self._poser, "link", None)
        if one is not None:
            return one(qpos, name)
        return self._poser(qpos).links[name]

    def joint(self, name: str) -> Joint | None:
        return self._by_name.get(name)


def kinematics_of(description: RobotDescription, text: bytes, path: str) -> KinematicModel | None:
    """The forward kinematics of the description read from ``text`` (the file at ``path``, or
    what stands in for it: a derived copy, an expansion); None where the library that computes
    them cannot read it (robospec's own parse says what is wrong, where it can)."""
    poser: Poser | None
    if description.kind == "mjcf":
        from robospec.kinematics.mjcf_poses import mjcf_poser

        poser = mjcf_poser(description, text, path)
    else:
        from robospec.kinematics.urdf_poses import urdf_poser

        poser = urdf_poser(description, text)
    return KinematicModel(description, poser) if poser is not None else None
