"""Whether a robot on the ground can stand where a keyframe puts it: its centre of mass over
the support polygon of its contacts with the ground (the convex hull of the contact points,
seen from above). A robot whose centre of mass lies outside it falls whatever its drives do
(a humanoid on a PD hold without a balance controller leans until it does); one whose centre
lies inside can stand on stiff enough drives.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from robospec.geometry import Vector

# the centre of mass must lie this far inside the polygon (m): on its edge a robot balances on
# a knife's edge, and the contacts PhysX reports move by millimetres from step to step
MARGIN = 0.005
# a contact bears weight only this close to the ground (m): PhysX reports contact points within
# its contact offset, centimetres apart. A robot settles by millimetres onto its feet as its
# drives take its weight (the Minitaur's motor housings, 0 to 9 mm up, all bear it); a foot
# further up is not standing (iCub's right foot, its leg swung forward by the rest pose, 13 to
# 37 mm up: counted, it made a polygon the centre of mass lay 4.5 cm inside, and the robot, on
# one foot, fell over)
TOUCHING = 0.01


@dataclass(frozen=True)
class Support:
    """A robot's contacts with the ground at one pose, and where its centre of mass is."""

    links: tuple[str, ...]  # the links touching the ground
    polygon: np.ndarray  # (k, 2): the convex hull of the contact points, counter-clockwise
    com: np.ndarray  # (3,): the centre of mass
    inside: float  # how far the centre of mass lies inside the polygon (m; < 0: outside)

    @property
    def touches(self) -> bool:
        return bool(self.links)

    @property
    def stands(self) -> bool:
        return self.touches and self.inside >= MARGIN


def support(contacts: Sequence[tuple[str, Vector, float]], com: np.ndarray) -> Support:
    """The support of ``contacts`` ((link, point, depth), as ``Sim.ground_contacts`` gives
    them) for a robot whose centre of mass is ``com``: the points that touch it (no more than
    :data:`TOUCHING` above it)."""
    bearing = [(link, point) for link, point, depth in contacts if depth >= -TOUCHING]
    links = tuple(sorted({link for link, _ in bearing}))
    points = np.array([p[:2] for _, p in bearing], dtype=np.float64).reshape(-1, 2)
    hull = convex_hull(points)
    return Support(links, hull, np.asarray(com, dtype=np.float64), inside_distance(hull, com[:2]))


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Andrew's monotone chain: the hull's corners counter-clockwise (a point or a segment when
    the points are that)."""
    unique = sorted({(round(float(x), 9), round(float(y), 9)) for x, y in points})
    if len(unique) <= 2:
        return np.array(unique, dtype=np.float64).reshape(-1, 2)

    def turn(o: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[float, float]] = []
    for p in unique:
        while len(lower) >= 2 and turn(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple[float, float]] = []
    for p in reversed(unique):
        while len(upper) >= 2 and turn(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1], dtype=np.float64)


def inside_distance(polygon: np.ndarray, point: np.ndarray) -> float:
    """How far ``point`` lies inside the convex ``polygon`` (its distance to the nearest edge),
    negative outside; a polygon of fewer than three corners has no inside (minus the distance
    to it)."""
    point = np.asarray(point, dtype=np.float64)[:2]
    if len(polygon) == 0:
        return -np.inf
    edges = [(polygon[i], polygon[(i + 1) % len(polygon)]) for i in range(len(polygon))]
    nearest = min(_segment_distance(point, a, b) for a, b in edges)
    if len(polygon) < 3:
        return -nearest
    inside = all(_cross(b - a, point - a) >= 0 for a, b in edges)
    return nearest if inside else -nearest


def _cross(u: np.ndarray, v: np.ndarray) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    length = float(ab @ ab)
    t = 0.0 if length == 0 else min(max(float((p - a) @ ab) / length, 0.0), 1.0)
    return float(np.linalg.norm(p - (a + t * ab)))
