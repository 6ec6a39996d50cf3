"""The robot's shapes placed in the world at a keyframe, as ManiSkill would place them.

Every link is where the robot's forward kinematics puts it (:mod:`robospec.kinematics.forward`:
yourdfpy for a URDF, MuJoCo for an MJCF), in the root link's frame, and the root link where the
keyframe puts it (for an MJCF, the keyframe's pose is its root body's, as
:mod:`robospec.resolve.root_pose` says: the resolved keyframe holds the root link's). Both are
read from the file ManiSkill loads: the derived copy when the description needs mends.

A URDF robot: each link's ``<visual>`` and ``<collision>`` geometry (mesh, box, sphere,
cylinder, capsule — cylinders and capsules along the shape's z, as SAPIEN turns them) at its
origin on the link. Colours as SAPIEN's URDF loader takes them: the visual's ``<material>``
colour (its own or a top-level one it names) over the mesh's.

An MJCF robot: MuJoCo's geoms of the bodies ManiSkill loads, where MuJoCo puts them (its own
compiler reads the file's defaults, meshes and orientations). ManiSkill's loader draws a geom in
groups 0 and 2 only and gives one a collision shape unless its ``contype`` is 0
(:mod:`robospec.description.mjcf_geoms`); planes and ellipsoids it skips, and so do these
pictures.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np

from robospec.derive.mjcf_files import compiled_model
from robospec.description.facts import RobotDescription
from robospec.description.numbers import finite_numbers
from robospec.description.urdf import parse_xml
from robospec.diagnostics import Diagnostic, Location, warning
from robospec.diagnostics.codes import PICTURE_MESH_UNREADABLE, PICTURE_MJCF_UNLOADABLE
from robospec.geometry import quaternion_from_rpy
from robospec.kinematics.forward import kinematics_of
from robospec.kinematics.mjcf_poses import MjcfPoser
from robospec.kinematics.placement import pose_matrix
from robospec.pictures.gl import import_mujoco
from robospec.pictures.meshes import MeshError, MeshPart, load_mesh
from robospec.resolve.resolved import ResolvedRobot

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
        description: RobotDescription,
        mesh_path: Callable[[str], str | None],
        layers: tuple[Layer, ...],
    ) -> None:
        self.problems: list[Diagnostic] = []
        description_path = description.path
        self.kinematics = kinematics_of(description, text, description_path)
        root, _ = parse_xml(text, description_path)
        self._entries: list[tuple[Shape, np.ndarray]] = []
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
        relative = self.kinematics.at(keyframe.qpos).links if self.kinematics else {}
        links = {name: keyframe.root @ pose for name, pose in relative.items()}
        shapes, poses = [], []
        for shape, origin in self._entries:
            link = links.get(shape.link)
            if link is None:  # a link ManiSkill does not load (the tree's warning says so)
                continue
            shapes.append(shape)
            poses.append(link @ origin)
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
            return Shape(link, layer, kind, (radius[0], half), rgba=rgba)
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
                    PICTURE_MESH_UNREADABLE,
                    f"{layer} mesh '{uri}' of link '{link}' cannot be drawn: {exc}",
                    "the pictures are drawn without it",
                )
            )
            return None


def _origin(element: object) -> np.ndarray:
    origin = element.find("origin")  # type: ignore[attr-defined]
    if origin is None:
        return np.eye(4)
    xyz = finite_numbers(origin.get("xyz"), 3) or (0.0, 0.0, 0.0)
    rpy = finite_numbers(origin.get("rpy"), 3) or (0.0, 0.0, 0.0)
    return pose_matrix(xyz, quaternion_from_rpy(*rpy))


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

    def __init__(
        self, text: bytes, path: str, description: RobotDescription, layers: tuple[Layer, ...]
    ) -> None:
        import_mujoco()  # the render extra's, drawing offscreen
        self.problems: list[Diagnostic] = []
        self.layers = layers
        self.poser: MjcfPoser | None = None
        try:
            self.model = compiled_model(text, path)
        except ValueError as exc:
            self._cannot(path, f"MuJoCo cannot load the MJCF for the pictures: {exc}")
            return
        self.poser = MjcfPoser.of(description, self.model)
        if self.poser is None:
            self._cannot(path, "MuJoCo names the MJCF's bodies otherwise than robospec reads them")

    def _cannot(self, path: str, message: str) -> None:
        self.problems.append(
            warning(Location(path), PICTURE_MJCF_UNLOADABLE, message, "the pictures show no robot")
        )

    def posed(self, keyframe: KeyframePose) -> PosedRobot:
        if self.poser is None:
            return PosedRobot(keyframe.name, keyframe.root, {}, (), ())
        placement = self.poser(keyframe.qpos)
        links = {name: keyframe.root @ pose for name, pose in placement.links.items()}
        # the geoms of the bodies ManiSkill loads, each on the link of its body
        link_of = {body: link for link, (body, step) in self.poser.bodies.items() if step is None}
        shapes, poses = [], []
        for geom in range(self.model.ngeom):
            link = link_of.get(int(self.model.geom_bodyid[geom]))
            if link is None:
                continue
            pose = keyframe.root @ self.poser.geom_pose(geom)
            for shape in self._shapes(geom, link):
                shapes.append(shape)
                poses.append(pose)
        return PosedRobot(keyframe.name, keyframe.root, links, tuple(shapes), tuple(poses))

    def _shapes(self, geom: int, link: str) -> list[Shape]:
        mujoco = import_mujoco()
        model = self.model
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


def posed_robots(
    robot: ResolvedRobot,
    description: RobotDescription,
    keyframes: list[KeyframePose],
    layers: tuple[Layer, ...],
) -> tuple[list[PosedRobot], list[Diagnostic]]:
    """The robot at each keyframe, and what could not be drawn (RS662, RS663)."""
    ref = robot.description
    # the file ManiSkill loads: the derived copy when the description needs mends
    text = (
        ref.generated_text.encode("utf-8")
        if ref.generated_text is not None
        else ref.absolute.read_bytes()
    )
    source: UrdfShapes | MjcfShapes
    if robot.description_kind == "mjcf":
        source = MjcfShapes(text, str(ref.absolute), description, layers)
    else:
        source = UrdfShapes(text, description, urdf_mesh_paths(robot, description), layers)
    return [source.posed(k) for k in keyframes], list(source.problems)
