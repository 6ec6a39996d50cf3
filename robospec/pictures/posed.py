"""The robot's shapes placed in the world at a keyframe, as ManiSkill would place them.

A URDF robot: each link's ``<visual>`` and ``<collision>`` geometry (mesh, box, sphere,
cylinder, capsule — cylinders and capsules along the shape's z, as SAPIEN turns them), put where
robospec's own forward kinematics (:mod:`robospec.kinematics.forward`) puts the link, with the
keyframe's pose on the root link. Colours as SAPIEN's URDF loader takes them: the visual's
``<material>`` colour (its own or a top-level one it names) over the mesh's.

An MJCF robot: MuJoCo places its bodies (its own compiler reads the file's defaults, meshes and
orientations), the keyframe's joint values added to each joint's reference as ManiSkill does,
and the whole moved so that the root body sits where the keyframe puts it
(:mod:`robospec.resolve.root_pose`). ManiSkill's loader draws a geom in groups 0 and 2 only and
gives one a collision shape unless its ``contype`` is 0 (:mod:`robospec.description.mjcf_geoms`);
planes and ellipsoids it skips, and so do these pictures.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np

from robospec.description.facts import RobotDescription
from robospec.description.numbers import finite_numbers
from robospec.description.urdf import parse_xml
from robospec.diagnostics import Diagnostic, Location, warning
from robospec.kinematics.forward import urdf_kinematics
from robospec.kinematics.frames import Transform, from_rpy
from robospec.pictures.gl import import_mujoco
from robospec.pictures.meshes import MeshError, MeshPart, load_mesh
from robospec.resolve.resolved import ResolvedRobot
from robospec.resolve.root_pose import root_body_pose

MESH_UNREADABLE = "RS662"
MJCF_UNLOADABLE = "RS663"

Layer = Literal["visual", "collision"]
Kind = Literal["mesh", "box", "sphere", "cylinder", "capsule"]
DEFAULT_RGBA = (0.72, 0.72, 0.74, 1.0)  # a shape that has no colour of its own
SHEET = 1e-4  # m: the half-thickness a flat primitive is drawn with (MuJoCo wants sizes > 0)


@dataclass(frozen=True)
class Shape:
    link: str
    layer: Layer
    kind: Kind
    # box: half sizes; sphere: (radius,); cylinder and capsule: (radius, half length) along
    # the shape's z; mesh: the scale along x, y, z
    size: tuple[float, ...]
    mesh: tuple[MeshPart, ...] = ()
    rgba: tuple[float, float, float, float] | None = None  # the description's; over the mesh's


@dataclass(frozen=True)
class PosedRobot:
    """The robot at one keyframe: every link's world pose (4x4), and every shape's."""

    keyframe: str
    root: np.ndarray  # the root link's world pose, 4x4
    links: Mapping[str, np.ndarray]
    shapes: tuple[Shape, ...]
    poses: tuple[np.ndarray, ...]  # shapes[i]'s world pose

    def bounds(self, layer: Layer = "visual") -> tuple[np.ndarray, np.ndarray]:
        """The axis-aligned box around the shapes of ``layer`` (the links' origins when the
        robot has none)."""
        points = self.points(layer)
        return points.min(axis=0), points.max(axis=0)

    def points(self, layer: Layer = "visual") -> np.ndarray:
        """Points on the shapes of ``layer`` in the world, (n, 3): the corners of each box
        around a shape, and a sample of each mesh's vertices (what a view is framed on)."""
        points = [
            corners
            for shape, pose in zip(self.shapes, self.poses, strict=True)
            if shape.layer == layer
            for corners in _shape_points(shape, pose)
        ]
        if not points:
            points = [pose[:3, 3][None, :] for pose in self.links.values()] or [np.zeros((1, 3))]
        return np.concatenate(points, axis=0)


@dataclass(frozen=True)
class KeyframePose:
    """What the pictures need of a keyframe: its name, each active joint's value by name, and
    the root link's world pose."""

    name: str
    qpos: Mapping[str, float]
    root: np.ndarray  # 4x4


def keyframe_poses(robot: ResolvedRobot) -> list[KeyframePose]:
    """The robot's keyframes; a robot without one is pictured at zero, as ManiSkill starts it."""
    poses = []
    for keyframe in robot.keyframes:
        values = keyframe.qpos or ()
        poses.append(
            KeyframePose(
                keyframe.name,
                dict(zip(robot.active_joints, values, strict=False)),
                pose_matrix(keyframe.p, keyframe.q),
            )
        )
    if not poses:
        poses.append(KeyframePose("zero", {}, np.eye(4)))
    return poses


def pose_matrix(p: tuple[float, ...], q: tuple[float, ...]) -> np.ndarray:
    """A 4x4 transform from a position and a wxyz quaternion."""
    w, x, y, z = q
    norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    matrix = np.eye(4)
    matrix[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    matrix[:3, 3] = p
    return matrix


def _matrix(transform: Transform) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, :3] = transform.rotation
    matrix[:3, 3] = transform.translation
    return matrix


SAMPLE = 256  # vertices of a mesh part that a view is framed on


def _shape_points(shape: Shape, pose: np.ndarray) -> list[np.ndarray]:
    if shape.kind == "mesh":
        scale = np.asarray(shape.size, dtype=np.float64)
        local = [
            part.vertices[:: max(1, len(part.vertices) // SAMPLE)].astype(np.float64) * scale
            for part in shape.mesh
        ]
        return [points @ pose[:3, :3].T + pose[:3, 3] for points in local]
    return [np.asarray(_corners(shape, pose))]


def _corners(shape: Shape, pose: np.ndarray) -> list[np.ndarray]:
    if shape.kind == "mesh":
        return []
    else:
        radius = shape.size[0]
        half = {
            "box": shape.size,
            "sphere": (radius, radius, radius),
            "cylinder": (radius, radius, shape.size[1] if len(shape.size) > 1 else 0.0),
            "capsule": (radius, radius, radius + (shape.size[1] if len(shape.size) > 1 else 0)),
        }[shape.kind]
        high = np.asarray(half, dtype=np.float64)
        low = -high
    corners = np.array(
        [[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])]
    )
    return list(corners @ pose[:3, :3].T + pose[:3, 3])


# -- URDF ------------------------------------------------------------------------------------


class UrdfShapes:
    """A URDF's shapes, read once; :meth:`posed` places them at each keyframe."""

    def __init__(
        self,
        text: bytes,
        description_path: str,
        mesh_path: Callable[[str], str | None],
        layers: tuple[Layer, ...],
    ) -> None:
        self.problems: list[Diagnostic] = []
        self.kinematics = urdf_kinematics(text)
        root, _ = parse_xml(text, description_path)
        self._entries: list[tuple[Shape, Transform]] = []
        if root is None:
            return
        colours = _top_level_colours(root)
        loaded: dict[str, tuple[MeshPart, ...] | None] = {}
        for link in root.iterfind("link"):
            for layer in layers:
                for element in link.iterfind(layer):
                    shape = self._shape(
                        link.get("name", ""),
                        layer,
                        element,
                        colours,
                        mesh_path,
                        loaded,
                        description_path,
                    )
                    if shape is not None:
                        self._entries.append((shape, _origin(element)))

    def posed(self, keyframe: KeyframePose) -> PosedRobot:
        relative = self.kinematics.link_poses(keyframe.qpos) if self.kinematics else {}
        links = {name: keyframe.root @ _matrix(pose) for name, pose in relative.items()}
        shapes, poses = [], []
        for shape, origin in self._entries:
            link = links.get(shape.link)
            if link is None:  # a link no joint reaches: the description's structure error
                continue
            shapes.append(shape)
            poses.append(link @ _matrix(origin))
        return PosedRobot(keyframe.name, keyframe.root, links, tuple(shapes), tuple(poses))

    def _shape(
        self,
        link: str,
        layer: Layer,
        element: object,
        colours: Mapping[str, tuple[float, float, float, float]],
        mesh_path: Callable[[str], str | None],
        loaded: dict[str, tuple[MeshPart, ...] | None],
        description_path: str,
    ) -> Shape | None:
        geometry = element.find("geometry")  # type: ignore[attr-defined]
        if geometry is None or len(geometry) == 0:
            return None
        kind_element = geometry[0]
        kind = kind_element.tag
        rgba = _visual_colour(element, colours) if layer == "visual" else None
        # a primitive of no extent (pybullet's Laikago has <sphere radius="0.0"/> toes) draws
        # nothing, and MuJoCo refuses it; a flat one (a box of zero height, a disc) is a sheet
        if kind == "box":
            size = finite_numbers(kind_element.get("size"), 3)
            if not size or max(size) <= 0:
                return None
            return Shape(link, layer, "box", tuple(max(s / 2, SHEET) for s in size), rgba=rgba)
        if kind == "sphere":
            radius = finite_numbers(kind_element.get("radius"), 1)
            return (
                Shape(link, layer, "sphere", radius, rgba=rgba)
                if radius and radius[0] > 0
                else None
            )
        if kind in ("cylinder", "capsule"):
            radius = finite_numbers(kind_element.get("radius"), 1)
            length = finite_numbers(kind_element.get("length"), 1)
            if not radius or not length or radius[0] <= 0:
                return None
            half = max(length[0] / 2, SHEET)
            return Shape(link, layer, kind, (radius[0], half), rgba=rgba)  # type: ignore[arg-type]
        if kind != "mesh":
            return None
        uri = kind_element.get("filename", "")
        scale = finite_numbers(kind_element.get("scale"), 3) or (1.0, 1.0, 1.0)
        path = mesh_path(uri)
        key = path or uri
        if key not in loaded:
            loaded[key] = self._load(path, uri, layer, link, kind_element, description_path)
        parts = loaded[key]
        if not parts:
            return None
        return Shape(link, layer, "mesh", tuple(scale), parts, rgba)

    def _load(
        self,
        path: str | None,
        uri: str,
        layer: Layer,
        link: str,
        element: object,
        description_path: str,
    ) -> tuple[MeshPart, ...] | None:
        if path is None:
            return None  # not found: validate reports it (RS056, RS058)
        try:
            return load_mesh(path)
        except MeshError as exc:
            line = getattr(element, "sourceline", None) or 1
            self.problems.append(
                warning(
                    Location(description_path, line, 1),
                    MESH_UNREADABLE,
                    f"{layer} mesh '{uri}' of link '{link}' cannot be drawn: {exc}",
                    "the pictures are drawn without it",
                )
            )
            return None


def _origin(element: object) -> Transform:
    origin = element.find("origin")  # type: ignore[attr-defined]
    if origin is None:
        return Transform()
    xyz = finite_numbers(origin.get("xyz"), 3) or (0.0, 0.0, 0.0)
    rpy = finite_numbers(origin.get("rpy"), 3) or (0.0, 0.0, 0.0)
    return Transform(from_rpy(*rpy), xyz)  # type: ignore[arg-type]


def _top_level_colours(root: object) -> dict[str, tuple[float, float, float, float]]:
    colours = {}
    for material in root.iterfind("material"):  # type: ignore[attr-defined]
        colour = material.find("color")
        rgba = finite_numbers(colour.get("rgba"), 4) if colour is not None else None
        if rgba:
            colours[material.get("name", "")] = rgba
    return colours  # type: ignore[return-value]


def _visual_colour(
    visual: object, colours: Mapping[str, tuple[float, float, float, float]]
) -> tuple[float, float, float, float] | None:
    material = visual.find("material")  # type: ignore[attr-defined]
    if material is None:
        return None
    colour = material.find("color")
    if colour is not None:
        rgba = finite_numbers(colour.get("rgba"), 4)
        if rgba:
            return rgba  # type: ignore[return-value]
    return colours.get(material.get("name", ""))


def urdf_mesh_paths(
    robot: ResolvedRobot, description: RobotDescription
) -> Callable[[str], str | None]:
    """Where each mesh URI of the description is on this machine (robospec found them while
    validating; a URI it did not look for is taken against the description's folder)."""
    found = {mesh.uri: mesh.path for mesh in description.mesh_files if mesh.role != "texture"}
    found.update(dict(robot.description.mesh_paths))
    folder = os.path.dirname(os.path.abspath(robot.description.absolute))

    def locate(uri: str) -> str | None:
        if uri in found:
            return found[uri]
        candidate = os.path.join(folder, uri)
        return candidate if os.path.isfile(candidate) else None

    return locate


# -- MJCF ------------------------------------------------------------------------------------

MANISKILL_VISUAL_GROUPS = (0, 2)


class MjcfShapes:
    """An MJCF robot's geoms, placed by MuJoCo at each keyframe."""

    def __init__(self, path: str, description: RobotDescription, layers: tuple[Layer, ...]) -> None:
        mujoco = import_mujoco()
        self.problems: list[Diagnostic] = []
        self.description = description
        self.layers = layers
        try:
            self.model = mujoco.MjModel.from_xml_path(path)
        except Exception as exc:  # MuJoCo's compiler errors are plain ValueErrors
            self.model = None
            self.problems.append(
                warning(
                    Location(path),
                    MJCF_UNLOADABLE,
                    f"MuJoCo cannot load the MJCF for the pictures: {exc}",
                    "the pictures show no robot",
                )
            )
            return
        self.data = mujoco.MjData(self.model)
        self.root = _articulated_root(self.model)

    def posed(self, keyframe: KeyframePose) -> PosedRobot:
        mujoco = import_mujoco()
        model = self.model
        if model is None:
            return PosedRobot(keyframe.name, keyframe.root, {}, (), ())
        data = self.data
        data.qpos[:] = model.qpos0
        for joint in range(model.njnt):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
            kind = int(model.jnt_type[joint])
            if name in keyframe.qpos and kind in (
                int(mujoco.mjtJoint.mjJNT_HINGE),
                int(mujoco.mjtJoint.mjJNT_SLIDE),
            ):
                # ManiSkill's zero is the joint's reference (MuJoCo's qpos0)
                address = model.jnt_qposadr[joint]
                data.qpos[address] = model.qpos0[address] + keyframe.qpos[name]
        mujoco.mj_kinematics(model, data)
        # move the whole so that the root body is where the keyframe puts it
        root_link = keyframe.root
        p, q = root_body_pose(self.description, _pose_tuple(root_link))
        wanted = pose_matrix(p, q)
        actual = _body_matrix(data, self.root)
        correction = wanted @ np.linalg.inv(actual)
        links = {self.description.root_link: root_link}
        members = [b for b in range(model.nbody) if _below(model, b, self.root)]
        for body in members:
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"body{body}"
            links[name] = correction @ _body_matrix(data, body)
        shapes, poses = [], []
        for geom in range(model.ngeom):
            body = model.geom_bodyid[geom]
            if body not in members:
                continue
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"body{body}"
            pose = np.eye(4)
            pose[:3, :3] = data.geom_xmat[geom].reshape(3, 3)
            pose[:3, 3] = data.geom_xpos[geom]
            for shape in self._shapes(geom, name):
                shapes.append(shape)
                poses.append(correction @ pose)
        return PosedRobot(keyframe.name, keyframe.root, links, tuple(shapes), tuple(poses))

    def _shapes(self, geom: int, link: str) -> list[Shape]:
        mujoco = import_mujoco()
        model = self.model
        assert model is not None
        kind = {
            int(mujoco.mjtGeom.mjGEOM_BOX): "box",
            int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere",
            int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
            int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
            int(mujoco.mjtGeom.mjGEOM_MESH): "mesh",
        }.get(int(model.geom_type[geom]))
        if kind is None:
            return []  # planes and ellipsoids ManiSkill skips; hfields and sdfs it cannot load
        size = tuple(float(s) for s in model.geom_size[geom])
        parts: tuple[MeshPart, ...] = ()
        if kind == "mesh":
            mesh = model.geom_dataid[geom]
            start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
            first, faces = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
            parts = (
                MeshPart(
                    np.asarray(model.mesh_vert[start : start + count], dtype=np.float32),
                    np.asarray(model.mesh_face[first : first + faces], dtype=np.int32),
                    None,
                ),
            )
            size = (1.0, 1.0, 1.0)
        elif kind == "sphere":
            size = size[:1]
        elif kind in ("cylinder", "capsule"):
            size = size[:2]
        material = model.geom_matid[geom]
        rgba = model.mat_rgba[material] if material >= 0 else model.geom_rgba[geom]
        colour = tuple(float(c) for c in rgba)
        layers: list[Layer] = []
        if model.geom_group[geom] in MANISKILL_VISUAL_GROUPS:
            layers.append("visual")
        if model.geom_contype[geom] != 0:
            layers.append("collision")
        return [
            Shape(link, layer, kind, size, parts, colour)  # type: ignore[arg-type]
            for layer in layers
            if layer in self.layers
        ]


def _articulated_root(model: object) -> int:
    """The first body below the world whose subtree has joints (the one ManiSkill loads)."""
    for body in range(1, model.nbody):  # type: ignore[attr-defined]
        if model.body_parentid[body] != 0:  # type: ignore[attr-defined]
            continue
        subtree = [b for b in range(model.nbody) if _below(model, b, body)]  # type: ignore[attr-defined]
        if any(model.body_jntnum[b] > 0 for b in subtree):  # type: ignore[attr-defined]
            return body
    return 1 if model.nbody > 1 else 0  # type: ignore[attr-defined]


def _below(model: object, body: int, ancestor: int) -> bool:
    while body > 0:
        if body == ancestor:
            return True
        body = int(model.body_parentid[body])  # type: ignore[attr-defined]
    return ancestor == 0


def _body_matrix(data: object, body: int) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, :3] = data.xmat[body].reshape(3, 3)  # type: ignore[attr-defined]
    matrix[:3, 3] = data.xpos[body]  # type: ignore[attr-defined]
    return matrix


def _pose_tuple(matrix: np.ndarray) -> tuple[tuple[float, float, float], tuple[float, ...]]:
    transform = Transform(
        tuple(tuple(float(v) for v in row) for row in matrix[:3, :3]),  # type: ignore[arg-type]
        tuple(float(v) for v in matrix[:3, 3]),  # type: ignore[arg-type]
    )
    return transform.translation, transform.quaternion()


def posed_robots(
    robot: ResolvedRobot,
    description: RobotDescription,
    keyframes: list[KeyframePose],
    layers: tuple[Layer, ...],
) -> tuple[list[PosedRobot], list[Diagnostic]]:
    """The robot at each keyframe, and what could not be drawn (RS662, RS663)."""
    source: UrdfShapes | MjcfShapes
    if robot.description_kind == "mjcf":
        source = MjcfShapes(str(robot.description.absolute), description, layers)
    else:
        text = robot.description.read_bytes()
        source = UrdfShapes(text, description.path, urdf_mesh_paths(robot, description), layers)
    return [source.posed(k) for k in keyframes], list(source.problems)
