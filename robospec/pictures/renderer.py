"""One MuJoCo model of a robot and its surroundings, drawn offscreen per view.

Every shape of the robot is a geom of its own mocap body, and so are the grounds, the table and
the cube: placing the robot at another keyframe only moves bodies (no new model, no new OpenGL
context). Geom groups choose what a picture shows: the robot's visuals (0), its collision
shapes (1), the ground of the robot views (2), the table scene (3).

Pictures are drawn with MuJoCo's own OpenGL renderer (``mjr_render``) into an offscreen buffer
big enough for the largest view; each view sets the scene's OpenGL camera itself (position,
axes and frustum from :class:`~robospec.pictures.views.View`), so a camera's intrinsics and
near/far planes are its own. ``MUJOCO_GL`` defaults to ``egl``: Mesa's EGL renders on the CPU
(llvmpipe) where there is no GPU.

A segmentation picture gives each pixel what it shows: a robot shape's index, or one of the
:data:`GROUND`, :data:`TABLE`, :data:`CUBE` labels, or :data:`NOTHING` (nothing within far).
"""

from __future__ import annotations

import colorsys
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from robospec.diagnostics.codes import NO_OPENGL, PICTURE_SCENE_FAILED
from robospec.pictures.gl import RenderUnavailable, gl_context, import_mujoco
from robospec.pictures.posed import DEFAULT_RGBA, PosedRobot, Shape
from robospec.pictures.stage import Box, Stage
from robospec.pictures.views import View

VISUAL, COLLISION, ROBOT_GROUND, TABLE_SCENE = 0, 1, 2, 3
NOTHING, GROUND, TABLE, CUBE = -1, -2, -3, -4
GROUND_RGBA = (0.82, 0.84, 0.86, 1.0)
TABLE_RGBA = (0.62, 0.47, 0.33, 1.0)
CUBE_RGBA = (0.85, 0.12, 0.12, 1.0)
MIN_VERTICES = 4  # MuJoCo cannot make a mesh of fewer


@dataclass(frozen=True)
class _Geom:
    label: int  # a robot shape's index, or GROUND/TABLE/CUBE
    body: int  # its mocap body's index


class Renderer:
    """The robot of ``robot`` (any keyframe: :meth:`place` moves it) with a ground, a table
    and a cube; views up to ``width`` x ``height`` pixels."""

    def __init__(self, robot: PosedRobot, width: int, height: int) -> None:
        mujoco = import_mujoco()
        self._mujoco = mujoco
        self.shapes = robot.shapes
        spec = mujoco.MjSpec()
        spec.modelname = "robospec_pictures"
        spec.visual.global_.offwidth = max(width, 1)
        spec.visual.global_.offheight = max(height, 1)
        spec.visual.quality.shadowsize = 2048
        spec.visual.quality.offsamples = 4
        spec.visual.headlight.ambient = [0.4, 0.4, 0.4]
        spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
        spec.visual.headlight.specular = [0.1, 0.1, 0.1]
        spec.add_texture(
            name="sky",
            type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
            rgb1=[0.93, 0.95, 0.98],
            rgb2=[0.70, 0.75, 0.82],
            width=64,
            height=64,
        )
        spec.add_texture(
            name="grid",
            type=mujoco.mjtTexture.mjTEXTURE_2D,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
            rgb1=[0.97, 0.97, 0.98],
            rgb2=[0.88, 0.89, 0.91],
            width=64,
            height=64,
        )
        grid = spec.add_material(
            name="grid", texrepeat=[2, 2], texuniform=True, emission=0.45, specular=0.1
        )
        grid.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = "grid"
        spec.worldbody.add_light(
            pos=[0, 0, 4],
            dir=[-0.3, -0.2, -1.0],
            type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
            castshadow=True,
            diffuse=[0.6, 0.6, 0.6],
            specular=[0.15, 0.15, 0.15],
        )
        self._geoms: list[_Geom] = []
        self._bodies = 0
        meshes: dict[tuple[int, tuple[float, ...]], str] = {}
        links = sorted({s.link for s in robot.shapes})
        hue = {link: (i * 0.618034) % 1.0 for i, link in enumerate(links)}
        for index, shape in enumerate(robot.shapes):
            body = self._body(spec)
            group = VISUAL if shape.layer == "visual" else COLLISION
            for rgba, kind, size, mesh in self._geometry(spec, shape, meshes, hue):
                spec.body(body).add_geom(
                    type=kind,
                    size=size,
                    meshname=mesh,
                    rgba=rgba,
                    group=group,
                    contype=0,
                    conaffinity=0,
                )
                self._geoms.append(_Geom(index, self._bodies - 1))
        extent = float(np.linalg.norm(np.subtract(*robot.bounds()))) + 2.0
        self._robot_ground = self._plane(spec, extent, ROBOT_GROUND, "grid")
        self._table_ground = self._plane(spec, extent + 2.0, TABLE_SCENE, "grid")
        self._table = self._box(spec, TABLE, TABLE_RGBA)
        self._cube = self._box(spec, CUBE, CUBE_RGBA)
        spec.stat.extent = extent
        try:
            self.model = spec.compile()
        except ValueError as exc:  # a mesh MuJoCo refuses: the message names it
            raise RenderUnavailable(
                PICTURE_SCENE_FAILED,
                f"MuJoCo cannot build the pictures' scene: {exc}",
                "a mesh MuJoCo refuses; the other commands do not need the pictures",
            ) from exc
        self.data = mujoco.MjData(self.model)
        self._open(width, height)

    # -- building ----------------------------------------------------------------------------

    def _body(self, spec: Any) -> str:
        name = f"b{self._bodies}"
        spec.worldbody.add_body(name=name, mocap=True)
        self._bodies += 1
        return name

    def _geometry(
        self,
        spec: Any,
        shape: Shape,
        meshes: dict[tuple[int, tuple[float, ...]], str],
        hue: dict[str, float],
    ) -> list[tuple[list[float], Any, list[float], str]]:
        mujoco = self._mujoco
        if shape.layer == "collision":  # one colour per link, to tell the shapes apart
            r, g, b = colorsys.hsv_to_rgb(hue[shape.link], 0.55, 0.9)
            colour: tuple[float, ...] | None = (r, g, b, 1.0)
        else:
            colour = shape.rgba
        if shape.kind != "mesh":
            kind = {
                "box": mujoco.mjtGeom.mjGEOM_BOX,
                "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
                "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
                "capsule": mujoco.mjtGeom.mjGEOM_CAPSULE,
            }[shape.kind]
            size = [*shape.size, 0.0, 0.0][:3]
            return [(list(colour or DEFAULT_RGBA), kind, size, "")]
        out = []
        for part in shape.mesh:
            if len(part.vertices) < MIN_VERTICES or len(part.faces) == 0:
                continue
            key = (id(part), shape.size)
            if key not in meshes:
                name = f"m{len(meshes)}"
                mesh = spec.add_mesh(name=name)
                mesh.uservert = part.vertices.reshape(-1)
                mesh.userface = part.faces.reshape(-1)
                mesh.scale = list(shape.size)
                # drawn, never simulated: a shell's inertia accepts open and flat meshes
                mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
                meshes[key] = name
            rgba = colour or part.rgba or DEFAULT_RGBA
            out.append((list(rgba), mujoco.mjtGeom.mjGEOM_MESH, [0.0, 0.0, 0.0], meshes[key]))
        return out

    def _plane(self, spec: Any, extent: float, group: int, material: str) -> int:
        body = self._body(spec)
        spec.body(body).add_geom(
            type=self._mujoco.mjtGeom.mjGEOM_PLANE,
            size=[extent, extent, 0.1],
            material=material,
            group=group,
            contype=0,
            conaffinity=0,
        )
        self._geoms.append(_Geom(GROUND, self._bodies - 1))
        return self._bodies - 1

    def _box(self, spec: Any, label: int, rgba: tuple[float, ...]) -> int:
        body = self._body(spec)
        spec.body(body).add_geom(
            type=self._mujoco.mjtGeom.mjGEOM_BOX,
            size=[0.5, 0.5, 0.5],
            rgba=list(rgba),
            group=TABLE_SCENE,
            contype=0,
            conaffinity=0,
        )
        self._geoms.append(_Geom(label, self._bodies - 1))
        return self._bodies - 1

    def _open(self, width: int, height: int) -> None:
        mujoco = self._mujoco
        try:
            self._context = gl_context(width, height)
            self._mjr = mujoco.MjrContext(self.model, mujoco.mjtFontScale.mjFONTSCALE_100)
        except Exception as exc:  # PyOpenGL, EGL and MuJoCo each raise their own
            raise RenderUnavailable(
                NO_OPENGL,
                f"no OpenGL to draw with (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): "
                f"{type(exc).__name__}: {exc}",
                _GL_HINT,
            ) from exc
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._mjr)
        self._scene = mujoco.MjvScene(self.model, maxgeom=self.model.ngeom + 16)
        self._camera = mujoco.MjvCamera()
        self._option = mujoco.MjvOption()

    # -- placing and drawing -----------------------------------------------------------------

    def place(self, robot: PosedRobot, robot_stage: Stage, table_stage: Stage) -> None:
        """The robot at ``robot``'s keyframe, the grounds and the table scene as staged."""
        for index, pose in enumerate(robot.poses):
            self._move(index, pose)
        self._move(self._robot_ground, _translation(0.0, 0.0, robot_stage.ground))
        self._move(self._table_ground, _translation(0.0, 0.0, table_stage.ground))
        for body, box in ((self._table, table_stage.table), (self._cube, table_stage.cube)):
            self._place_box(body, box)
        self._mujoco.mj_kinematics(self.model, self.data)

    def _place_box(self, body: int, box: Box | None) -> None:
        geom = next(i for i, g in enumerate(self._geoms) if g.body == body)
        if box is None:
            self.model.geom_size[geom] = [1e-4, 1e-4, 1e-4]
            self._move(body, _translation(0.0, 0.0, -1e3))
            return
        self.model.geom_size[geom] = box.half
        self._move(body, box.pose)

    def _move(self, body: int, pose: np.ndarray) -> None:
        mocap = self.model.body_mocapid[body + 1]  # body 0 is the world
        self.data.mocap_pos[mocap] = pose[:3, 3]
        quaternion = np.zeros(4)
        self._mujoco.mju_mat2Quat(quaternion, np.ascontiguousarray(pose[:3, :3]).reshape(-1))
        self.data.mocap_quat[mocap] = quaternion

    def colour(self, view: View, groups: tuple[int, ...]) -> np.ndarray:
        """The view's picture, (height, width, 3) uint8, of the geoms in ``groups``."""
        return self._draw(view, groups, segment=False)

    def labels(self, view: View, groups: tuple[int, ...]) -> np.ndarray:
        """What each pixel shows, (height, width) int32: a robot shape's index, GROUND, TABLE,
        CUBE or NOTHING."""
        image = self._draw(view, groups, segment=True).astype(np.int64)
        segment = image[:, :, 0] + image[:, :, 1] * 256 + image[:, :, 2] * 65536
        scene = self._scene
        table = np.full(scene.ngeom + 1, NOTHING, dtype=np.int32)
        for i in range(scene.ngeom):
            geom = scene.geoms[i]
            if geom.segid >= 0 and geom.objtype == self._mujoco.mjtObj.mjOBJ_GEOM:
                table[geom.segid + 1] = self._geoms[geom.objid].label
        segment[(segment < 0) | (segment > scene.ngeom)] = 0
        return table[segment]

    def _draw(self, view: View, groups: tuple[int, ...], segment: bool) -> np.ndarray:
        mujoco = self._mujoco
        self._context.make_current()
        for group in range(len(self._option.geomgroup)):
            self._option.geomgroup[group] = 1 if group in groups else 0
        scene = self._scene
        mujoco.mjv_updateScene(
            self.model,
            self.data,
            self._option,
            None,
            self._camera,
            mujoco.mjtCatBit.mjCAT_ALL,
            scene,
        )
        near = view.near
        for camera in scene.camera:
            camera.pos[:] = view.position
            camera.forward[:] = view.forward
            camera.up[:] = view.up
            camera.orthographic = 0
            camera.frustum_near = near
            camera.frustum_far = view.far
            camera.frustum_top = view.cy / view.fy * near
            camera.frustum_bottom = -(view.height - view.cy) / view.fy * near
            camera.frustum_center = (view.width / 2 - view.cx) / view.fx * near
            camera.frustum_width = view.width / (2 * view.fx) * near
        if scene.nlight > 0 and self.model.vis.headlight.active:
            scene.lights[0].pos[:] = view.position
            scene.lights[0].dir[:] = view.forward
        scene.flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = segment
        scene.flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = segment
        scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = not segment
        rect = mujoco.MjrRect(0, 0, view.width, view.height)
        mujoco.mjr_render(rect, scene, self._mjr)
        pixels = np.empty((view.height, view.width, 3), dtype=np.uint8)
        mujoco.mjr_readPixels(pixels, None, rect, self._mjr)
        return np.flipud(pixels)

    def close(self) -> None:
        context = getattr(self, "_context", None)
        if context is not None:
            self._mjr.free()
            context.free()
            self._context = None


def _translation(x: float, y: float, z: float) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, 3] = (x, y, z)
    return pose


_GL_HINT = (
    "install Debian's libegl1 (apt-get install libegl1; Mesa draws on the CPU), or set "
    "MUJOCO_GL=osmesa with libosmesa6"
)
