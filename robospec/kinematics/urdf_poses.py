"""A URDF's link poses from yourdfpy's forward kinematics.

yourdfpy reads only the kinematic skeleton here — each ``<link>``'s name and every
``<joint>`` — so that a geometry it does not know (SAPIEN's ``<capsule>``, which pybullet's
humanoid uses) or a mesh it cannot find does not stop it, and no mesh is read. Two of its
readings are brought to SAPIEN's before it computes anything:

* a ``<mimic>`` joint follows its leader in yourdfpy; SAPIEN's ``set_qpos`` sets every joint,
  the followers too: here each joint takes its own value;
* a joint axis is a direction: SAPIEN slides a prismatic joint along the unit vector; yourdfpy
  would slide it by ``value`` times the vector as written.

yourdfpy imports trimesh (about a second): it is imported when a URDF's poses are first asked
for, never on ``validate``'s path.
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from typing import TYPE_CHECKING

from lxml import etree

from robospec.description import RobotDescription
from robospec.description.urdf import parse_xml
from robospec.kinematics.placement import MOVING, Axis, Placement, Poser

if TYPE_CHECKING:
    import numpy as np
    from yourdfpy import URDF


def urdf_poser(description: RobotDescription, text: bytes) -> Poser | None:
    """Poses of the URDF ``text`` (already accepted by robospec's parse as ``description``);
    None where yourdfpy cannot read its skeleton."""
    model = _yourdfpy_model(text)
    if model is None:
        return None
    return _UrdfPoser(description, model)


class _UrdfPoser:
    """yourdfpy's model of the robot, placed at the joint values it is called with."""

    def __init__(self, description: RobotDescription, model: URDF) -> None:
        import numpy as np

        self.model = model
        self.root = description.root_link
        self.links = description.link_names
        self.moving = [
            j for j in description.joints if j.type in MOVING and j.name in model.joint_map
        ]
        self.axes = {
            j.name: np.asarray(model.joint_map[j.name].axis, dtype=np.float64) for j in self.moving
        }
        # the joint values the model is at: yourdfpy keeps a joint it is not given where it
        # was, so a search that moves one joint at a time (new's ready pose: a finite-difference
        # Jacobian) updates that joint's edge of the scene graph, not every joint's
        self._configured: dict[str, float] = {}

    def __call__(self, qpos: Mapping[str, float]) -> Placement:
        self._configure(qpos)
        poses = {link: self.model.get_transform(link, self.root) for link in self.links}
        placed = {}
        for joint in self.moving:
            child = poses[joint.child]
            # the child's frame turns about (or slides along) the axis through its origin
            placed[joint.name] = Axis(child[:3, :3] @ self.axes[joint.name], child[:3, 3].copy())
        return Placement(poses, placed)

    def link(self, qpos: Mapping[str, float], name: str) -> np.ndarray:
        """One link's pose alone (yourdfpy walks only its chain)."""
        self._configure(qpos)
        return self.model.get_transform(name, self.root)

    def _configure(self, qpos: Mapping[str, float]) -> None:
        wanted = {j.name: float(qpos.get(j.name, 0.0)) for j in self.moving}
        changed = {
            name: value for name, value in wanted.items() if self._configured.get(name) != value
        }
        if changed:
            self.model.update_cfg(changed)
            self._configured.update(changed)


def _yourdfpy_model(text: bytes) -> URDF | None:
    root, _ = parse_xml(text, "")
    if root is None:
        return None
    skeleton = etree.Element("robot", name=root.get("name", "robot"))
    for element in root:
        if element.tag == "link":
            etree.SubElement(skeleton, "link", name=element.get("name", ""))
        elif element.tag == "joint":
            skeleton.append(_without_mimic(element))
    import numpy as np
    import yourdfpy

    try:
        loaded = yourdfpy.URDF.load(
            io.BytesIO(etree.tostring(skeleton)), build_scene_graph=False, load_meshes=False
        )
        for joint in loaded.robot.joints:
            axis = np.asarray(joint.axis if joint.axis is not None else (1, 0, 0), dtype=float)
            norm = float(np.linalg.norm(axis))
            joint.axis = axis / norm if norm > 1e-12 else np.array([1.0, 0.0, 0.0])
        return yourdfpy.URDF(robot=loaded.robot, build_scene_graph=True, load_meshes=False)
    except (ValueError, KeyError, TypeError, AttributeError):  # what its parser raises
        return None


def _without_mimic(joint: etree._Element) -> etree._Element:
    copy = etree.Element("joint", dict(joint.attrib))
    for child in joint:
        if isinstance(child.tag, str) and child.tag != "mimic":
            copy.append(etree.fromstring(etree.tostring(child)))
    return copy
