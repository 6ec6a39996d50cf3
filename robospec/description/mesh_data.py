"""The vertices of a mesh file, read without a mesh library (this runs on the validate path).

robospec reads STL (binary and ASCII), Wavefront OBJ and COLLADA (``.dae``: the positions of
every ``<geometry>``, scene transforms left out) for what it judges from the geometry itself:
whether PhysX can build a collision shape from it (no NaN or infinite vertex, not empty, not
flat), how large a link's shapes are (an inertia from them), and to write a mirrored copy
(:mod:`robospec.derive.mirrors`). Other formats give None: nothing is judged. Reads are cached
by path, modification time and size. numpy is imported only when a mesh is read: a binary STL
of 300 000 triangles is read in milliseconds, where Python's own loops take seconds.
"""

from __future__ import annotations

import os
import re
import struct
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

Vertex = tuple[float, float, float]

# a mesh this large is not read for judging (its bounds are not worth seconds of validate)
MAX_BYTES = 64 << 20


@dataclass(frozen=True, eq=False)
class MeshData:
    vertices: Any  # numpy array (N, 3) of float64
    # triangles as vertex indices, numpy (M, 3) (STL and OBJ; none for COLLADA, read for bounds)
    triangles: Any

    @property
    def finite(self) -> bool:
        import numpy as np

        return bool(np.isfinite(self.vertices).all())

    def bounds(self) -> tuple[Vertex, Vertex] | None:
        """The axis-aligned box of the finite vertices; None when there are none."""
        import numpy as np

        finite = self.vertices[np.isfinite(self.vertices).all(axis=1)]
        if len(finite) == 0:
            return None
        low, high = finite.min(axis=0), finite.max(axis=0)
        return (float(low[0]), float(low[1]), float(low[2])), (
            float(high[0]),
            float(high[1]),
            float(high[2]),
        )

    def flat_axis(self, tolerance: float = 1e-9) -> int | None:
        """The axis along which the vertices all but coincide (a flat mesh, of which PhysX
        builds no convex hull), or None."""
        box = self.bounds()
        if box is None:
            return None
        sizes = [box[1][i] - box[0][i] for i in range(3)]
        largest = max(sizes)
        for i, size in enumerate(sizes):
            if size <= tolerance * max(largest, 1e-12):
                return i
        return None


def read_mesh(path: str) -> MeshData | None:
    """The mesh at ``path``, or None when its format is not one robospec reads (or it cannot
    be read: the loaders' own checks say so)."""
    try:
        status = os.stat(path)
    except OSError:
        return None
    if status.st_size > MAX_BYTES:
        return None
    return _read(os.path.abspath(path), status.st_mtime_ns, status.st_size)


@lru_cache(maxsize=256)
def _read(path: str, mtime: int, size: int) -> MeshData | None:
    suffix = os.path.splitext(path)[1].lower()
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError:
        return None
    try:
        if suffix == ".stl":
            return _stl(data)
        if suffix == ".obj":
            return _obj(data)
        if suffix == ".dae":
            return _dae(data)
    except (ValueError, struct.error, IndexError):
        return None
    return None


def _mesh(vertices: list[Vertex] | Any, triangles: list[tuple[int, int, int]] | Any) -> MeshData:
    import numpy as np

    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    return MeshData(v, t)


def _stl(data: bytes) -> MeshData:
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * count == len(data):
            return _binary_stl(data, count)
    if data.lstrip()[:5].lower() == b"solid":
        return _ascii_stl(data)
    (count,) = struct.unpack_from("<I", data, 80)  # a binary STL with trailing bytes
    return _binary_stl(data, min(count, (len(data) - 84) // 50))


def _binary_stl(data: bytes, count: int) -> MeshData:
    import numpy as np

    record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", 9), ("attribute", "<u2")])
    triangles = np.frombuffer(data, dtype=record, count=count, offset=84)
    vertices = triangles["corners"].reshape(-1, 3).astype(np.float64)
    return _mesh(vertices, np.arange(len(vertices)).reshape(-1, 3))


_VERTEX = re.compile(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)")


def _ascii_stl(data: bytes) -> MeshData:
    vertices = [(float(x), float(y), float(z)) for x, y, z in _VERTEX.findall(data)]
    count = len(vertices) // 3
    return _mesh(vertices[: 3 * count], [(i, i + 1, i + 2) for i in range(0, 3 * count, 3)])


def _obj(data: bytes) -> MeshData:
    vertices: list[Vertex] = []
    triangles: list[tuple[int, int, int]] = []
    for line in data.splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == b"v" and len(parts) >= 4:
            vertices.append((float(parts[1]), float(parts[2]), float(parts[3])))
        elif parts[0] == b"f" and len(parts) >= 4:
            indices = [int(p.split(b"/")[0]) for p in parts[1:]]
            indices = [i - 1 if i > 0 else len(vertices) + i for i in indices]
            for k in range(1, len(indices) - 1):  # a polygon as a fan of triangles
                triangles.append((indices[0], indices[k], indices[k + 1]))
    return _mesh(vertices, triangles)


def _dae(data: bytes) -> MeshData:
    from lxml import etree

    parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=True)
    root = etree.fromstring(data, parser)
    vertices: list[float] = []
    for source in root.iter("{*}source"):
        # the positions of a mesh: the source its <vertices> element names
        identifier = source.get("id", "")
        used = root.find(f".//{{*}}vertices/{{*}}input[@source='#{identifier}']")
        if used is None or used.get("semantic") != "POSITION":
            continue
        array = source.find("{*}float_array")
        if array is None or not array.text:
            continue
        values = array.text.split()
        vertices.extend(float(v) for v in values[: len(values) // 3 * 3])
    return _mesh(vertices, [])
