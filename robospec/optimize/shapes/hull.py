"""``hull``: one convex shape per mesh, its vertices capped (``max_vertices``), written the same
whatever order qhull found them in."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    import trimesh


def capped_hull(vertices: np.ndarray, max_vertices: int | None) -> tuple[np.ndarray, np.ndarray]:
    """The convex hull of ``vertices``; with ``max_vertices``, a hull of at most that many of its
    vertices, grown greedily: from the extreme points along the axes, add the vertex farthest
    outside the hull so far, until the cap. Inside the full hull, and close to it."""
    import numpy as np

    full = convex_hull(vertices)
    if max_vertices is None or len(full.vertices) <= max_vertices:
        return _canonical(full)
    points = np.asarray(full.vertices)
    extremes = {int(f(points[:, axis])) for axis in range(3) for f in (np.argmin, np.argmax)}
    chosen = sorted(extremes)
    while len(chosen) < max_vertices:
        distance = _outside(points, points[chosen])
        farthest = int(np.argmax(distance))
        if distance[farthest] <= 0:
            break
        chosen.append(farthest)
    return _canonical(convex_hull(points[chosen]))


def _outside(points: np.ndarray, hull_points: np.ndarray) -> np.ndarray:
    """How far each point lies outside the hull of ``hull_points`` (or, while those are flat,
    from the nearest of them)."""
    import numpy as np
    from scipy.spatial import ConvexHull, QhullError

    try:
        planes = ConvexHull(hull_points).equations
    except QhullError:
        gaps = np.linalg.norm(points[:, None] - hull_points[None], axis=2)
        return np.min(gaps, axis=1)
    return np.max(points @ planes[:, :3].T + planes[:, 3], axis=1)


def convex_hull(points: np.ndarray) -> trimesh.Trimesh:
    import numpy as np
    import trimesh

    return trimesh.convex.convex_hull(np.asarray(points, dtype=np.float64))


def _canonical(hull: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    """The hull's vertices sorted (so the bytes do not depend on qhull's order) and its faces."""
    import numpy as np

    vertices = np.asarray(hull.vertices)
    order = np.lexsort(vertices.T[::-1])
    rank = np.empty(len(order), dtype=np.int64)
    rank[order] = np.arange(len(order))
    faces = rank[np.asarray(hull.faces)]
    faces = faces[np.lexsort(faces.T[::-1])]
    return vertices[order], faces
