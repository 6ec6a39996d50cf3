"""Where a picture is taken from, and how a point of the world lands on it.

A view is a pinhole camera in SAPIEN's conventions, which ManiSkill's ``CameraConfig`` uses: the
camera's x axis looks forward, y to its left, z up; ``fov`` is the vertical field of view, with
square pixels (``fx = fy``) and the principal point in the image's centre; an ``intrinsic``
matrix gives fx, fy, cx, cy instead (skew ignored, as SAPIEN ignores it). Pixel (u, v) counts
from the top-left corner, u to the right, v down.

A camera of the robot is seen from its mount link's pose at the keyframe times the camera's
pose on it. The standard views of the robot (front, side, three-quarter) look at the middle of
its bounding box from a fixed direction, as close as leaves every corner of the box in the frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from robospec.resolve.resolved import ResolvedCamera


@dataclass(frozen=True)
class View:
    name: str
    width: int
    height: int
    pose: np.ndarray  # 4x4: the camera in the world (x forward, y left, z up)
    fx: float
    fy: float
    cx: float
    cy: float
    near: float
    far: float

    @property
    def position(self) -> np.ndarray:
        return self.pose[:3, 3]

    @property
    def forward(self) -> np.ndarray:
        return self.pose[:3, 0]

    @property
    def up(self) -> np.ndarray:
        return self.pose[:3, 2]

    def project(self, point: np.ndarray) -> tuple[float, float, float]:
        """(u, v, depth): where ``point`` lands on the image and how far in front of the camera
        it is (negative: behind it)."""
        local = self.pose[:3, :3].T @ (np.asarray(point, dtype=np.float64) - self.position)
        depth = float(local[0])
        if abs(depth) < 1e-12:
            return math.inf, math.inf, depth
        u = self.cx - self.fx * float(local[1]) / depth
        v = self.cy - self.fy * float(local[2]) / depth
        return u, v, depth

    def sees(self, point: np.ndarray, margin: float = 0.0) -> bool:
        """Whether ``point`` lands inside the image, between near and far."""
        u, v, depth = self.project(point)
        return (
            self.near <= depth <= self.far
            and -margin <= u <= self.width + margin
            and -margin <= v <= self.height + margin
        )


def camera_view(camera: ResolvedCamera, mount: np.ndarray, name: str) -> View:
    from robospec.kinematics.placement import pose_matrix

    pose = mount @ pose_matrix(camera.p, camera.q)
    if camera.intrinsic is not None:
        k = camera.intrinsic
        fx, fy, cx, cy = k[0][0], k[1][1], k[0][2], k[1][2]
    else:
        fy = (camera.height / 2) / math.tan((camera.fov or math.pi / 2) / 2)
        fx, cx, cy = fy, camera.width / 2, camera.height / 2
    return View(name, camera.width, camera.height, pose, fx, fy, cx, cy, camera.near, camera.far)


# name -> (azimuth about z from +x, elevation), in degrees: the robot faces +x
STANDARD_VIEWS = {"three_quarter": (40.0, 28.0), "front": (0.0, 12.0), "side": (90.0, 12.0)}
VIEW_WIDTH, VIEW_HEIGHT = 320, 240
VIEW_FOVY = math.radians(40.0)
FRAME_MARGIN = 1.08  # the box fills this much less than the frame


def standard_view(
    name: str, points: np.ndarray, width: int = VIEW_WIDTH, height: int = VIEW_HEIGHT
) -> View:
    """The view ``name`` of :data:`STANDARD_VIEWS`, framed on ``points`` (n, 3): as close as
    keeps every point in the frame, with their picture in its middle."""
    azimuth, elevation = (math.radians(a) for a in STANDARD_VIEWS[name])
    toward = np.array(
        [
            -math.cos(elevation) * math.cos(azimuth),
            -math.cos(elevation) * math.sin(azimuth),
            -math.sin(elevation),
        ]
    )
    left = np.cross([0.0, 0.0, 1.0], toward)
    left /= np.linalg.norm(left)
    up = np.cross(toward, left)
    rotation = np.column_stack([toward, left, up])
    f = (height / 2) / math.tan(VIEW_FOVY / 2)
    # the slopes the frame allows, sideways and up, with a margin
    slope_x = (width / 2) / f / FRAME_MARGIN
    slope_y = (height / 2) / f / FRAME_MARGIN
    centre = (points.min(axis=0) + points.max(axis=0)) / 2
    distance = 0.0
    for _ in range(3):  # fit, centre the picture, fit again
        local = (points - centre) @ rotation
        along, sideways, upward = local[:, 0], local[:, 1], local[:, 2]
        distance = max(
            0.05,
            float(np.max(np.abs(sideways) / slope_x - along)),
            float(np.max(np.abs(upward) / slope_y - along)),
        )
        depth = np.maximum(distance + along, 1e-6)
        u, v = sideways / depth, upward / depth
        shift_x = (u.max() + u.min()) / 2 * distance
        shift_y = (v.max() + v.min()) / 2 * distance
        centre = centre + left * shift_x + up * shift_y
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = centre - toward * distance
    size = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) + distance
    return View(name, width, height, pose, f, f, width / 2, height / 2, 0.01, 10 * size)
