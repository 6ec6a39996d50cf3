"""What stands around the robot in a picture: a ground, and for the cameras a table with a cube.

The robot views stand the robot on a ground at z = 0, or lower where the robot reaches below
it (a hand hanging in the air is not cut by the floor).

The table scene is ManiSkill's table-top task in general terms: a table whose top is at
``table_height`` (``checks.camera_views``; by default level with the robot's root link at the
keyframe, as ManiSkill's table scene mounts an arm on its table and as a humanoid's upper body
stands at a desk), reaching from just in front of the root link along its heading; a 4 cm cube
(PickCube's) on it, under the tcp when the tcp is above the table, else ahead of the robot; and
a ground at z = 0, or 0.9 m below a table that would be lower than half a metre above it (the
arm then stands on a table, as in ManiSkill's scene).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TABLE_NEAR = 0.2  # m from the root link to the table's near edge, along the heading
TABLE_DEPTH = 1.4
TABLE_WIDTH = 1.6
TABLE_LEGS = 0.9  # a table lower than LOW_TABLE above the ground stands on one this high
LOW_TABLE = 0.5
CUBE_HALF = 0.02
CUBE_AHEAD = 0.35  # m beyond the near edge, where the tcp is not above the table


@dataclass(frozen=True)
class Box:
    pose: np.ndarray  # 4x4
    half: tuple[float, float, float]


@dataclass(frozen=True)
class Stage:
    ground: float  # z of the ground plane
    table: Box | None = None
    cube: Box | None = None


def robot_stage(lowest: float) -> Stage:
    return Stage(min(0.0, lowest))


def table_stage(root: np.ndarray, tcp: np.ndarray | None, height: float | None) -> Stage:
    """The table scene for a robot whose root link is at ``root`` (4x4), its tcp at ``tcp``."""
    top = float(root[2, 3]) if height is None else float(height)
    ground = 0.0 if top >= LOW_TABLE else top - TABLE_LEGS
    heading = root[:3, 0].copy()
    heading[2] = 0.0
    norm = float(np.linalg.norm(heading))
    heading = heading / norm if norm > 1e-9 else np.array([1.0, 0.0, 0.0])
    side = np.array([-heading[1], heading[0], 0.0])
    rotation = np.column_stack([heading, side, [0.0, 0.0, 1.0]])
    origin = np.array([root[0, 3], root[1, 3], 0.0])
    centre = origin + heading * (TABLE_NEAR + TABLE_DEPTH / 2)
    thickness = (top - ground) / 2
    table = Box(
        _pose(rotation, [centre[0], centre[1], ground + thickness]),
        (TABLE_DEPTH / 2, TABLE_WIDTH / 2, thickness),
    )
    spot = origin + heading * (TABLE_NEAR + CUBE_AHEAD)
    if tcp is not None:
        along = float((tcp - origin) @ heading) - TABLE_NEAR
        across = float((tcp - origin) @ side)
        if (
            0.05 < along < TABLE_DEPTH - 0.05
            and abs(across) < TABLE_WIDTH / 2 - 0.05
            and (tcp[2] > top)
        ):
            spot = np.array([tcp[0], tcp[1], 0.0])
    cube = Box(_pose(rotation, [spot[0], spot[1], top + CUBE_HALF]), (CUBE_HALF,) * 3)
    return Stage(ground, table, cube)


def _pose(rotation: np.ndarray, position: list[float]) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = position
    return pose
