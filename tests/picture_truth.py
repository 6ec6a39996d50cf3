"""Whether a checked-in picture of a robot shows the robot where SAPIEN puts it.

The robot is loaded in ManiSkill (headless, on the CPU) at the keyframe the picture is drawn
at, and SAPIEN's link poses are the truth (:mod:`robospec.kinematics.simulated`):

* every link the picture places is where SAPIEN places it (:func:`placement_errors`);
* in the checked-in picture, the robot's pixels — those where it differs from the same view
  (the gallery's, framed as the gallery frames it) drawn without the robot — are where a
  segmentation render of the robot's shapes at SAPIEN's link poses puts the robot, and nowhere
  far from it; and each link that carries a shape, its origin where SAPIEN puts it projected
  with the picture's own camera, lands on the robot's pixels (:func:`picture_faults`). An empty
  floor, a robot in pieces, a picture of another pose or from another camera fails.

Used by tests/test_gallery.py (the zoo, docs/images/zoo) and tests/test_corpus.py (the
corpus, docs/images/robots).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

# the pixels where a picture differs from its empty stage by more than this (of 255, in any
# channel) are the robot's (its shadow's too): the palette of 128 colours moves the stage's own
# pixels by less, and a white Panda against the sky by more (measured: at 16, 99-100% of the
# Panda's, Fetch's and SO-100's pixels, and 0.6% of the rest, their shadows)
ROBOT_CONTRAST = 16
# how far from a link's projected origin the robot's pixels may start: a link's frame sits on
# its joint, often at the edge of its shape
REACH_PX = 4
# the links whose origin must land on the robot: all but a few (a frame at the tip of a thin
# shape drawn a pixel wide)
SHARE_ON_ROBOT = 0.9
# of the pixels where SAPIEN's placement puts the robot, the share the picture shows it on
# (a thin edge drawn a pixel off, a part as pale as the sky behind it may be missed)
SHARE_COVERED = 0.95
# of the pixels farther from SAPIEN's robot, the share that may differ from the empty stage
# (its shadow: measured 0.6% for the Panda, Fetch and SO-100)
SHARE_STRAY = 0.03
# SAPIEN computes in float32
POSITION_TOLERANCE = 1e-4  # m


@dataclass(frozen=True)
class Truth:
    """A picture's robot as SAPIEN places it, and as the picture does."""

    sapien: dict[str, np.ndarray]  # link -> world pose (4x4)
    pictured: object  # robospec.pictures.posed.PosedRobot: the picture's own placement
    layer: str  # what the picture shows: "visual", or "collision" for a robot with no visual
    view: object  # robospec.pictures.views.View: the picture's camera
    background: np.ndarray  # (H, W, 3): the picture's view drawn without the robot
    mask: np.ndarray  # (H, W) bool: the robot's pixels in that view, at SAPIEN's link poses


def sapien_truth(spec: Path) -> Truth:
    """The robot of ``spec`` at its first keyframe (as the gallery draws it), in SAPIEN and in
    the pictures' own placement, with the gallery's camera."""
    import robospec
    from robospec.docgen.gallery import GALLERY_VIEW
    from robospec.kinematics.simulated import Setting, simulated_link_poses
    from robospec.pictures.album import shown_layer
    from robospec.pictures.posed import PosedRobot, keyframe_poses, posed_robots
    from robospec.pictures.renderer import COLLISION, ROBOT_GROUND, VISUAL, Renderer
    from robospec.pictures.stage import robot_stage, table_stage
    from robospec.pictures.views import standard_view
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    robot, description = compiled.robot, compiled.description
    assert robot is not None and description is not None, compiled.diagnostics
    # two robots of the corpus may share a uid (rtb_panda's and pb_panda's scaffolds): each
    # truth replaces the last
    robospec.register(spec, override=True)
    first = robot.keyframes[0] if robot.keyframes else None
    setting = Setting(
        first.p if first else (0.0, 0.0, 0.0),
        first.q if first else (1.0, 0.0, 0.0, 0.0),
        (first.qpos if first and first.qpos else None) or [0.0] * len(robot.active_joints),
    )
    (sapien,) = simulated_link_poses(robot.uid, [setting])
    keyframe = keyframe_poses(robot)[:1]
    (pictured,), _ = posed_robots(robot, description, keyframe, ("visual", "collision"))
    layer = shown_layer(pictured)
    points = pictured.points(layer)
    view = standard_view(GALLERY_VIEW, points)
    # the same shapes, each on its link as SAPIEN places the link
    moved = [
        sapien[shape.link] @ np.linalg.inv(pictured.links[shape.link]) @ pose
        for shape, pose in zip(pictured.shapes, pictured.poses, strict=True)
    ]
    at_sapien = PosedRobot(pictured.keyframe, pictured.root, sapien, pictured.shapes, tuple(moved))
    renderer = Renderer(pictured, view.width, view.height)
    try:
        ground, table = robot_stage(float(points[:, 2].min())), table_stage(np.eye(4), None, None)
        renderer.place(pictured, ground, table)
        background = renderer.colour(view, (ROBOT_GROUND,))
        renderer.place(at_sapien, ground, table)
        mask = renderer.labels(view, (VISUAL if layer == "visual" else COLLISION,)) >= 0
    finally:
        renderer.close()
    return Truth(sapien, pictured, layer, view, background, mask)


def placement_errors(truth: Truth) -> dict[str, float]:
    """Each link the picture places farther than :data:`POSITION_TOLERANCE` from where SAPIEN
    places it (position and rotation, the largest difference), or that SAPIEN lacks."""
    errors = {}
    for link, pose in truth.pictured.links.items():  # type: ignore[attr-defined]
        theirs = truth.sapien.get(link)
        apart = float(np.abs(pose - theirs).max()) if theirs is not None else float("inf")
        if not apart <= POSITION_TOLERANCE:
            errors[link] = apart
    return errors


def picture_faults(truth: Truth, picture: Path) -> list[str]:
    """What is wrong with ``picture`` as a picture of the robot where SAPIEN puts it (nothing:
    an empty list)."""
    from PIL import Image

    drawn = np.asarray(Image.open(picture).convert("RGB"), dtype=np.int32)
    if drawn.shape != truth.background.shape:
        return [f"{drawn.shape[1]}x{drawn.shape[0]} pixels, not the gallery's view"]
    robot = np.abs(drawn - truth.background.astype(np.int32)).max(axis=2) > ROBOT_CONTRAST
    faults = []
    covered = float((robot & truth.mask).sum()) / max(1, int(truth.mask.sum()))
    if not covered >= SHARE_COVERED:
        faults.append(f"shows {covered:.0%} of the robot where SAPIEN puts it")
    far = ~_grown(truth.mask, REACH_PX)
    stray = float((robot & far).sum()) / max(1, int(far.sum()))
    if not stray <= SHARE_STRAY:
        faults.append(f"{stray:.0%} of the pixels away from the robot are not the empty stage")
    off, looked = links_off_the_robot(truth, robot)
    if not (looked > 0 and len(off) <= (1 - SHARE_ON_ROBOT) * looked):
        faults.append(f"{len(off)} of {looked} links' origins land off the robot: {off[:8]}")
    return faults


def links_off_the_robot(truth: Truth, robot: np.ndarray) -> tuple[list[str], int]:
    """The links with a shape whose origin, and each of whose shapes' origins, where SAPIEN
    puts them, land on none of the ``robot`` pixels (a mask of the picture); and how many
    links were looked for. (A link's frame may stand away from its own shapes: the Robotiq
    2F-140's right_gripper frame sits at its knuckle's pin, beside the pad it carries.)"""
    near = _grown(robot, REACH_PX)
    pictured = truth.pictured  # type: ignore[attr-defined]
    points: dict[str, list[np.ndarray]] = {}
    for shape, pose in zip(pictured.shapes, pictured.poses, strict=True):
        if shape.layer == truth.layer:  # type: ignore[attr-defined]
            at_sapien = truth.sapien[shape.link] @ np.linalg.inv(pictured.links[shape.link]) @ pose  # type: ignore[attr-defined]
            points.setdefault(shape.link, [truth.sapien[shape.link][:3, 3]]).append(
                at_sapien[:3, 3]
            )  # type: ignore[attr-defined]

    def lands(point: np.ndarray) -> bool:
        u, v, depth = truth.view.project(point)  # type: ignore[attr-defined]
        column, row = int(np.floor(u)), int(np.floor(v))
        inside = 0 <= row < near.shape[0] and 0 <= column < near.shape[1] and depth > 0
        return bool(inside and near[row, column])

    off = [link for link in sorted(points) if not any(map(lands, points[link]))]
    return off, len(points)


def _grown(mask: np.ndarray, reach: int) -> np.ndarray:
    """``mask`` grown by ``reach`` pixels (a square around each pixel)."""
    grown = mask.copy()
    padded = np.pad(mask, reach)
    height, width = mask.shape
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            grown |= padded[reach + dy : reach + dy + height, reach + dx : reach + dx + width]
    return grown
