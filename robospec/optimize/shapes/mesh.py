"""Collision meshes as SAPIEN reads them: the distinct vertices of a file, and the connected
parts SAPIEN's ``splitMesh`` cuts an STL into (``load_multiple_collisions``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

# what splitMesh reads as STL/PLY (the suffix test in SAPIEN's mesh.cpp is case sensitive)
STL_SUFFIXES = (".stl", ".STL")


@dataclass(frozen=True)
class Mesh:
    """A collision mesh read: distinct float32 vertices in first-occurrence order (what assimp's
    JoinIdenticalVertices keeps) and triangles over them."""

    vertices: np.ndarray
    faces: np.ndarray


def read_mesh(path: Path) -> Mesh:
    import numpy as np
    import trimesh

    loaded = trimesh.load(str(path), force="mesh", process=False)
    assert isinstance(loaded, trimesh.Trimesh)
    corners = np.asarray(loaded.vertices, dtype=np.float32)[np.asarray(loaded.faces).reshape(-1)]
    # assimp reads an STL as three vertices per triangle and JoinIdenticalVertices keeps each
    # distinct position once, at its first occurrence
    unique, first, inverse = np.unique(corners, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty(len(unique), dtype=np.int64)
    rank[order] = np.arange(len(unique))
    return Mesh(unique[order], rank[inverse.reshape(-1)].reshape(-1, 3))


def sapien_parts(mesh: Mesh) -> list[np.ndarray]:
    """SAPIEN's ``splitMesh``: parts in order of their first vertex, each part's vertices in the
    order of its depth-first walk (neighbours in index order, a stack): PhysX's hull depends on
    that order, so the walk is SAPIEN's step for step."""
    count = len(mesh.vertices)
    neighbours: list[set[int]] = [set() for _ in range(count)]
    for a, b, c in mesh.faces.tolist():
        neighbours[a].update((b, c))
        neighbours[b].update((a, c))
        neighbours[c].update((a, b))
    ordered = [sorted(n) for n in neighbours]
    visited = bytearray(count)
    parts = []
    for start in range(count):
        if visited[start]:
            continue
        visited[start] = 1
        group, stack = [start], [start]
        while stack:
            for m in ordered[stack.pop()]:
                if not visited[m]:
                    visited[m] = 1
                    group.append(m)
                    stack.append(m)
        parts.append(mesh.vertices[group])
    return parts
