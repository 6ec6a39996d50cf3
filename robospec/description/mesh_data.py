"""The vertices of a mesh file, read without a mesh library (this runs on the validate path).

robospec reads STL (binary and ASCII), Wavefront OBJ and COLLADA (``.dae``: the positions of
every ``<geometry>``, scene transforms left out) for what it judges from the geometry itself:
whether PhysX can build a collision shape from it (no NaN or infinite vertex, not empty, not
flat), how large a link's shapes are (an inertia from them), and to write a mirrored copy
(:mod:`robospec.derive.mirrors`). Other formats give None: nothing is judged. Reads are cached
by path, modification time and size. Without numpy (``validate`` does not import it): coordinates
are kept in flat arrays and judged at C speed (a 16 MB set of STL files in about a second).
"""

from __future__ import annotations

import math
import os
import re
import struct
import sys
from array import array
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cached_property, lru_cache

from robospec.geometry import Vector

# a mesh this large is not read for judging (its bounds are not worth seconds of validate)
MAX_BYTES = 64 << 20


@dataclass(eq=False)
class MeshData:
    """A mesh's vertices as one flat ``array('d')`` (x, y, z, x, y, z, ...) and its triangles
    as one flat ``array('q')`` of vertex indices (none for COLLADA, read for its bounds):
    compact, and judged at C speed without numpy (which ``validate`` does not import)."""

    coordinates: array
    indices: array

    @property
    def vertex_count(self) -> int:
        return len(self.coordinates) // 3

    @property
    def triangle_count(self) -> int:
        return len(self.indices) // 3

    @cached_property
    def finite(self) -> bool:
        try:  # a NaN or an infinity makes the exact sum non-finite, or raises
            return math.isfinite(math.fsum(self.coordinates))
        except (ValueError, OverflowError):
            return False

    def bounds(self) -> tuple[Vector, Vector] | None:
        """The axis-aligned box of the vertices (NaN left out); None when there are none."""
        if self.vertex_count and self.finite:  # min and max at C speed
            axes_ = [self.coordinates[i::3] for i in range(3)]
            return (min(axes_[0]), min(axes_[1]), min(axes_[2])), (
                max(axes_[0]),
                max(axes_[1]),
                max(axes_[2]),
            )
        axes = [[v for v in self.coordinates[i::3] if v == v] for i in range(3)]
        if not all(axes):
            return None
        finite = [[v for v in axis if math.isfinite(v)] or axis for axis in axes]
        low = (min(finite[0]), min(finite[1]), min(finite[2]))
        high = (max(finite[0]), max(finite[1]), max(finite[2]))
        return low, high

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

    def vertex(self, index: int) -> Vector:
        c = self.coordinates
        return (c[3 * index], c[3 * index + 1], c[3 * index + 2])

    def triangles(self) -> list[tuple[int, int, int]]:
        i = self.indices
        return [(i[k], i[k + 1], i[k + 2]) for k in range(0, len(i) - 2, 3)]


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


def _mesh(coordinates: Iterable[float], indices: Iterable[int]) -> MeshData:
    return MeshData(array("d", coordinates), array("q", indices))


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
    # each record: 3 floats of normal, 9 of corners, 2 bytes of attribute; the corners, cut
    # out record by record, are read as one array of floats
    floats = array("f")
    for first in range(0, count, _CHUNK):
        records = min(_CHUNK, count - first)
        corners = _records(records).unpack_from(data, 84 + 50 * first)
        floats.frombytes(b"".join(corners))
    if sys.byteorder == "big":
        floats.byteswap()
    return _mesh(floats, range(3 * count))


_CHUNK = 8192  # STL records cut out per struct call


@lru_cache(maxsize=4)
def _records(count: int) -> struct.Struct:
    """``count`` STL records, each read as its 36 bytes of corners."""
    return struct.Struct("<" + "12x36s2x" * count)


_VERTEX = re.compile(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)")


def _ascii_stl(data: bytes) -> MeshData:
    vertices = [(float(x), float(y), float(z)) for x, y, z in _VERTEX.findall(data)]
    count = len(vertices) // 3
    return _mesh((c for v in vertices[: 3 * count] for c in v), range(3 * count))


def _obj(data: bytes) -> MeshData:
    vertices: list[Vector] = []
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
    return _mesh((c for v in vertices for c in v), (i for t in triangles for i in t))


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
        floats = source.find("{*}float_array")
        if floats is None or not floats.text:
            continue
        values = floats.text.split()
        vertices.extend(float(v) for v in values[: len(values) // 3 * 3])
    return _mesh(vertices, [])
