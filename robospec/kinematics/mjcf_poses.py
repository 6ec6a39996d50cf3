"""An MJCF's link poses from MuJoCo: its compiler reads the file (defaults, orientations,
``<include>``s, ``ref``) and ``mj_kinematics`` places the bodies.

ManiSkill's links are MuJoCo's bodies, named as robospec's facts name them
(:mod:`robospec.description.mjcf`):

* a body with one joint (or none) is the link of its name, at MuJoCo's body frame;
* a body with ``n`` joints is a chain of ``n`` links, ``{body}_dummy_0`` … and the body last;
  link ``k`` is where the body is with only its first ``k + 1`` joints moved (ManiSkill turns
  joint ``k`` about the same axis MuJoCo does: ``xaxis``/``xanchor``, which MuJoCo computes
  with the joints before it moved);
* the root link ``dummy_root_{i}`` is the frame the robot's first body hangs from: the world,
  or the wrapper body ManiSkill's loader skips (it puts the root link where the wrapper is).

A joint's value is counted from its ``ref``, as ManiSkill's zero is the pose as written (MuJoCo's
``qpos0``); a free joint stays at ``qpos0``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from robospec.derive.mjcf_files import compiled_model
from robospec.description import RobotDescription
from robospec.kinematics.placement import Axis, Placement, motion

if TYPE_CHECKING:
    import numpy as np

_DUMMY = re.compile(r"(.+)_dummy_(\d+)")


def mjcf_poser(description: RobotDescription, text: bytes, path: str) -> MjcfPoser | None:
    """Poses of the MJCF ``text`` (already accepted by robospec's parse as ``description``);
    None where MuJoCo cannot compile it or names its bodies otherwise."""
    try:
        model = compiled_model(text, path)
    except ValueError:
        return None
    return MjcfPoser.of(description, model)


class MjcfPoser:
    """MuJoCo's model of the robot, placed at the joint values it is called with."""

    def __init__(
        self,
        description: RobotDescription,
        model: Any,
        bodies: dict[str, tuple[int, int | None]],
    ) -> None:
        import mujoco

        self._mujoco = mujoco
        self.model = model
        self.data = mujoco.MjData(model)
        self.root = description.root_link
        self.bodies = bodies  # link -> (its body, k of {body}_dummy_{k} or None)
        first = next((j.child for j in description.tree_joints if j.parent == self.root), None)
        # the frame the robot's first body hangs from (the world, or a skipped wrapper)
        self.holder = int(model.body_parentid[bodies[first][0]]) if first in bodies else 0
        self._kinds = {
            int(mujoco.mjtJoint.mjJNT_HINGE): "revolute",
            int(mujoco.mjtJoint.mjJNT_SLIDE): "prismatic",
        }
        # each body's moving joints, in MuJoCo's (and ManiSkill's) order
        self._chains = {
            body: [j for j in range(start, start + count) if int(model.jnt_type[j]) in self._kinds]
            for body, start, count in zip(
                range(model.nbody), model.body_jntadr, model.body_jntnum, strict=True
            )
        }
        self._joints = {
            joint.name: index
            for joint in description.joints
            if (index := mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name)) >= 0
            and int(model.jnt_type[index]) in self._kinds
        }
        self._to_root: np.ndarray | None = None

    @classmethod
    def of(cls, description: RobotDescription, model: Any) -> MjcfPoser | None:
        """None when a link of ``description`` names no body of ``model``."""
        import mujoco

        bodies = _link_bodies(mujoco, model, description)
        return cls(description, model, bodies) if bodies is not None else None

    def __call__(self, qpos: Mapping[str, float]) -> Placement:
        import numpy as np

        model, data = self.model, self.data
        data.qpos[:] = model.qpos0
        values = {index: float(qpos.get(name, 0.0)) for name, index in self._joints.items()}
        for index, value in values.items():
            data.qpos[model.jnt_qposadr[index]] += value
        self._mujoco.mj_kinematics(model, data)
        to_root = self._to_root = np.linalg.inv(
            _pose(data.xmat[self.holder], data.xpos[self.holder])
        )

        def axis(index: int) -> Axis:
            turn, shift = to_root[:3, :3], to_root[:3, 3]
            return Axis(turn @ data.xaxis[index], turn @ data.xanchor[index] + shift)

        links = {self.root: np.eye(4)}
        for link, (body, step) in self.bodies.items():
            pose = to_root @ _pose(data.xmat[body], data.xpos[body])
            # a dummy link: the body with the joints after this link's undone, last first
            for later in reversed(self._chains[body][step + 1 :] if step is not None else []):
                kind = self._kinds[int(model.jnt_type[later])]
                pose = np.linalg.inv(motion(kind, axis(later), values.get(later, 0.0))) @ pose
            links[link] = pose
        return Placement(links, {name: axis(index) for name, index in self._joints.items()})

    def geom_pose(self, geom: int) -> np.ndarray:
        """Where geom ``geom`` is, in the root frame, as the last call placed the robot."""
        assert self._to_root is not None, "place the robot first"
        return self._to_root @ _pose(self.data.geom_xmat[geom], self.data.geom_xpos[geom])


def _link_bodies(
    mujoco: Any, model: Any, description: RobotDescription
) -> dict[str, tuple[int, int | None]] | None:
    """Each link but the root -> its MuJoCo body and, for ``{body}_dummy_{k}``, ``k``; None
    when a link names no body (MuJoCo and robospec read the file differently)."""
    found: dict[str, tuple[int, int | None]] = {}
    for link in description.link_names:
        if link == description.root_link:
            continue
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, link)
        if body >= 0:
            found[link] = (body, None)
            continue
        dummy = _DUMMY.fullmatch(link)
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, dummy[1]) if dummy else -1
        if dummy is None or body < 0:
            return None
        found[link] = (body, int(dummy[2]))
    return found


def _pose(rotation: Any, position: Any) -> np.ndarray:
    import numpy as np

    pose = np.eye(4)
    pose[:3, :3] = np.asarray(rotation).reshape(3, 3)
    pose[:3, 3] = position
    return pose
