"""Every picture of a robot card, and what the cameras' pictures say about the cameras.

For each keyframe (a robot without one: at zero): the robot from each standard view
(:data:`~robospec.pictures.views.STANDARD_VIEWS`) on a ground, its collision shapes from the same
views when asked, and each camera's view from its mount with the camera's own size, intrinsics,
near and far — of the robot alone, and at the table scene (:mod:`.stage`). The cameras' views
are then drawn again as segmentation pictures and judged (:mod:`.camera_checks`).

Names, below the album's folder, one folder per keyframe (keyframe names and camera uids are
identifiers, so a dot keeps them apart): ``<keyframe>/<view>.png``,
``<keyframe>/<view>.collision.png``, ``<keyframe>/<camera>.camera.png``,
``<keyframe>/<camera>.table.png``. Nothing is written here: the pictures are PNG bytes, written
by the caller once everything succeeded.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import Literal

import numpy as np

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Diagnostic, Location, warning
from robospec.pictures import camera_checks
from robospec.pictures.posed import (
    KeyframePose,
    Layer,
    PosedRobot,
    keyframe_poses,
    posed_robots,
)
from robospec.pictures.renderer import (
    COLLISION,
    ROBOT_GROUND,
    TABLE_SCENE,
    VISUAL,
    Renderer,
)
from robospec.pictures.stage import Stage, robot_stage, table_stage
from robospec.pictures.views import (
    STANDARD_VIEWS,
    VIEW_HEIGHT,
    VIEW_WIDTH,
    camera_view,
    standard_view,
)
from robospec.resolve.resolved import ResolvedRobot

Kind = Literal["robot", "collision", "camera", "table"]
PNG_COLOURS = 128  # a palette this big keeps a 320x240 picture near 20 KB


@dataclass(frozen=True)
class Picture:
    kind: Kind
    keyframe: str
    name: str  # the view's name, or the camera's uid
    path: str  # below the album's folder, with / between folders
    png: bytes


@dataclass(frozen=True)
class Album:
    pictures: tuple[Picture, ...]
    diagnostics: tuple[Diagnostic, ...]


@dataclass(frozen=True)
class AlbumOptions:
    collisions: bool = False
    views: tuple[str, ...] = tuple(STANDARD_VIEWS)
    cameras: bool = True  # each camera's views (and their findings)
    first_keyframe_only: bool = False
    width: int = VIEW_WIDTH
    height: int = VIEW_HEIGHT


@dataclass(frozen=True)
class CameraSettings:
    """``checks.camera_views`` of the spec, and where each camera is written in it."""

    limits: camera_checks.Limits
    table_height: float | None
    locate: dict[str, Location]  # camera uid -> its key in the spec


def picture_path(kind: Kind, keyframe: str, name: str) -> str:
    suffix = {"robot": "", "collision": ".collision", "camera": ".camera", "table": ".table"}
    return f"{keyframe}/{name}{suffix[kind]}.png"


def make_album(
    robot: ResolvedRobot,
    description: RobotDescription,
    cameras: CameraSettings,
    shown_folder: str,
    options: AlbumOptions = AlbumOptions(),
) -> Album:
    """Every picture, and the diagnostics (the camera findings name each picture as
    ``shown_folder/<path>``). Raises :class:`~robospec.pictures.renderer.RenderUnavailable`
    when nothing can be drawn here."""
    keyframes = keyframe_poses(robot)[: 1 if options.first_keyframe_only else None]
    layers = ("visual", "collision") if options.collisions else ("visual",)
    posed, problems = posed_robots(robot, description, keyframes, layers)  # type: ignore[arg-type]
    if not options.collisions and shown_layer(posed[0]) == "collision":
        # nothing SAPIEN would draw: the robot's pictures show its collision shapes
        posed, problems = posed_robots(robot, description, keyframes, ("visual", "collision"))
    diagnostics: list[Diagnostic] = list(problems)
    cameras_drawn = robot.cameras if options.cameras else ()
    sizes = [(options.width, options.height)] + [(c.width, c.height) for c in cameras_drawn]
    renderer = Renderer(posed[0], max(w for w, _ in sizes), max(h for _, h in sizes))
    pictures: list[Picture] = []
    try:
        for keyframe, robot_at in zip(keyframes, posed, strict=True):
            pictures += _robot_views(renderer, robot_at, keyframe, robot, options)
            if not options.cameras:
                continue
            for picture, found in _camera_views(
                renderer, robot_at, robot, description, cameras, shown_folder
            ):
                pictures.append(picture)
                diagnostics.extend(found)
    finally:
        renderer.close()
    return Album(tuple(pictures), tuple(diagnostics))


def _robot_views(
    renderer: Renderer,
    robot_at: PosedRobot,
    keyframe: KeyframePose,
    robot: ResolvedRobot,
    options: AlbumOptions,
) -> list[Picture]:
    layer = shown_layer(robot_at)
    points = robot_at.points(layer)
    renderer.place(robot_at, robot_stage(float(points[:, 2].min())), _table(robot_at, robot, None))
    pictures = []
    for name in options.views:
        view = standard_view(name, points, options.width, options.height)
        rgb = renderer.colour(view, (VISUAL if layer == "visual" else COLLISION, ROBOT_GROUND))
        pictures.append(_picture("robot", keyframe.name, name, rgb))
        if options.collisions:
            rgb = renderer.colour(view, (COLLISION, ROBOT_GROUND))
            pictures.append(_picture("collision", keyframe.name, name, rgb))
    return pictures


def shown_layer(robot_at: PosedRobot) -> Layer:
    """What the robot's pictures show of it: its visual shapes, as SAPIEN draws the robot;
    its collision shapes when it has no visual shape SAPIEN would draw (pybullet's DeepMimic
    humanoid has collisions only; the Shadow hand's visual geoms are in MuJoCo's group 1,
    which ManiSkill's loader does not draw), rather than an empty floor."""
    return "visual" if any(shape.layer == "visual" for shape in robot_at.shapes) else "collision"


def _camera_views(
    renderer: Renderer,
    robot_at: PosedRobot,
    robot: ResolvedRobot,
    description: RobotDescription,
    settings: CameraSettings,
    shown_folder: str,
) -> list[tuple[Picture, list[Diagnostic]]]:
    if not robot.cameras:
        return []
    lowest = float(robot_at.points("visual")[:, 2].min())
    renderer.place(robot_at, robot_stage(lowest), _table(robot_at, robot, settings.table_height))
    tcp = tcp_position(robot, robot_at)
    tcp_links = rigid_tcp_links(robot, description)
    out: list[tuple[Picture, list[Diagnostic]]] = []
    for camera in robot.cameras:
        mount = robot_at.links.get(camera.mount)
        if mount is None:
            continue
        view = camera_view(camera, mount, camera.uid)
        alone = _picture("camera", robot_at.keyframe, camera.uid, renderer.colour(view, (VISUAL,)))
        scene = renderer.colour(view, (VISUAL, TABLE_SCENE))
        at_table = _picture("table", robot_at.keyframe, camera.uid, scene)
        mount_links = camera_checks.rigid_links(description, camera.mount)
        findings = camera_checks.judge(
            view,
            renderer.labels(view, (VISUAL,)),
            renderer.labels(view, (VISUAL, TABLE_SCENE)),
            robot_at,
            mount_links,
            tcp if tcp is not None and camera.mount in tcp_links else None,
            settings.limits,
            f"{shown_folder}/{alone.path}",
            f"{shown_folder}/{at_table.path}",
        )
        where = settings.locate.get(camera.uid, Location(robot.spec_path))
        found = [
            warning(
                where,
                f.code,
                f"camera '{camera.uid}' at keyframe '{robot_at.keyframe}': {f.message}",
                f.hint,
            )
            for f in findings
        ]
        out += [(alone, found), (at_table, [])]
    return out


def tcp_position(robot: ResolvedRobot, robot_at: PosedRobot) -> tuple[str, np.ndarray] | None:
    """The tcp's name and world position at this keyframe (a midpoint tcp: between its
    links); None when the spec names none."""
    tcp = robot.tcp
    if tcp is None:
        return None
    if tcp.link is not None and tcp.link in robot_at.links:
        return tcp.link, robot_at.links[tcp.link][:3, 3]
    if tcp.midpoint is not None and all(link in robot_at.links for link in tcp.midpoint):
        a, b = (robot_at.links[link][:3, 3] for link in tcp.midpoint)
        return f"midpoint of {tcp.midpoint[0]} and {tcp.midpoint[1]}", (a + b) / 2
    return None


def rigid_tcp_links(robot: ResolvedRobot, description: RobotDescription) -> frozenset[str]:
    """The links that move with the tcp: a camera mounted on one is a wrist camera."""
    tcp = robot.tcp
    if tcp is None:
        return frozenset()
    link = tcp.link
    if link is None and tcp.orientation not in (None, "midpoint"):
        link = tcp.orientation
    return camera_checks.rigid_links(description, link) if link else frozenset()


def _table(robot_at: PosedRobot, robot: ResolvedRobot, height: float | None) -> Stage:
    tcp = tcp_position(robot, robot_at)
    return table_stage(robot_at.root, tcp[1] if tcp else None, height)


def _picture(kind: Kind, keyframe: str, name: str, rgb: np.ndarray) -> Picture:
    return Picture(kind, keyframe, name, picture_path(kind, keyframe, name), png_bytes(rgb))


def png_bytes(rgb: np.ndarray) -> bytes:
    """A small PNG: the picture on a palette of :data:`PNG_COLOURS` colours, optimized."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(rgb)).quantize(
        colors=PNG_COLOURS, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE
    )
    buffer = io.BytesIO()
    image.save(buffer, format="PNG", optimize=True)
    return buffer.getvalue()
