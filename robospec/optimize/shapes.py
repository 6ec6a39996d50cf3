"""Collision shapes SAPIEN simulates well: each link's collision meshes rewritten as files that
SAPIEN loads without complaint, or as fewer, simpler shapes.

What SAPIEN 3.0.3 builds from a ``<collision><mesh>`` (``sapien/wrapper/urdf_loader.py``,
``_parse_link``, and its C++ ``src/physx/mesh.cpp``):

- ``load_multiple_collisions_from_file`` false (ManiSkill's default): one PhysX convex hull of
  every vertex in the file (``add_convex_collision_from_file``); STL or not, no warning.
- true (ManiSkill's G1 and H1; ``BaseAgent.load_multiple_collisions``):
  ``add_multiple_convex_collisions_from_file`` -> ``PhysxConvexMesh::LoadByConnectedParts``. For
  ``.stl``/``.ply`` it is ``loadComponentVerticesFromMeshFileStlPly``: an STL prints "loading
  multiple convex collision meshes from STL file is unsupported ..." and is read with
  ``aiProcess_JoinIdenticalVertices``; ``splitMesh`` then cuts the mesh into its connected parts
  (a depth-first walk over the vertex graph) and each part's vertices, in walk order, are cooked
  into one PhysX convex hull (``vertexLimit = 255``). Any other format
  (``loadComponentVerticesFromMeshFileAssimpScene``) gives one convex hull per node of the
  file's scene: an OBJ of one object is one hull, read as written, without a warning.

PhysX's hull cooking depends on the order of its input points and on points inside the hull
(measured: cooking only the hull's vertices changes 8 of the G1's 122 parts), so ``convert``
writes each part's points in SAPIEN's walk order, one OBJ per part, one ``<collision>`` each.

Methods (``method=``): ``convert`` (that, for STL meshes; the behaviour stays), ``hull`` (one
convex OBJ per mesh, at most ``max_vertices`` vertices), ``coacd`` (a convex decomposition, one
OBJ per part), ``primitives`` (a box, capsule or sphere where one matches the mesh's hull within
``tolerance``). trimesh and numpy are imported when the function runs (they cost a second).
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

if TYPE_CHECKING:
    import numpy as np
    import trimesh

METHODS = ("convert", "hull", "coacd", "primitives")
# what splitMesh reads as STL/PLY (the suffix test in SAPIEN's mesh.cpp is case sensitive)
_STL_SUFFIXES = (".stl", ".STL")
_HEADER = "# written by robospec optimize\n"


class MissingDependency(Exception):
    """A method needs a package that is not installed: the caller turns it into a diagnostic."""

    def __init__(self, package: str, hint: str) -> None:
        super().__init__(f"robospec optimize needs the {package} package for this method")
        self.package = package
        self.hint = hint


@dataclass(frozen=True)
class ShapeChange:
    """What became of one ``<collision>`` element of a link."""

    link: str
    source: str  # the mesh file (or the primitive's tag) before
    method: str  # "convert", "hull", "coacd", "box", "capsule", "sphere", "kept"
    written: tuple[str, ...]  # files written, relative to the assets folder
    shapes_before: int  # collision shapes SAPIEN builds from it (loaded with multiple collisions)
    shapes_after: int
    vertices_before: int  # the mesh's distinct vertices
    vertices_after: int  # the written files' vertices (0 for primitives)


@dataclass(frozen=True)
class _Mesh:
    """A collision mesh read: distinct float32 vertices in first-occurrence order (what assimp's
    JoinIdenticalVertices keeps) and triangles over them."""

    vertices: np.ndarray
    faces: np.ndarray


@dataclass(frozen=True)
class _Result:
    """One collision element's replacement: new elements and files, or nothing (kept)."""

    method: str
    elements: tuple[etree._Element, ...]
    files: tuple[tuple[str, str], ...]  # (file name, OBJ text)
    vertices: int


def optimize_collisions(
    robot: etree._Element,
    assets: Path,
    *,
    method: str = "convert",
    max_vertices: int | None = None,
    tolerance: float = 0.05,
    multiple_collisions: bool = True,
) -> tuple[etree._Element, tuple[ShapeChange, ...]]:
    """A copy of ``robot`` (a URDF ``<robot>`` whose collision mesh paths are absolute) whose
    collision meshes are rewritten by ``method``, the new files written under ``assets`` (named
    ``<link>_<collision>[_<part>].obj``, same input, same bytes) and named by absolute path; and
    one :class:`ShapeChange` per collision element. ``multiple_collisions`` is the loader's
    ``load_multiple_collisions``: what ``convert`` must reproduce (without it an STL already
    loads as one hull, silently, and is kept)."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: one of {', '.join(METHODS)}")
    if max_vertices is not None and max_vertices < 4:
        raise ValueError("max_vertices must be at least 4 (a tetrahedron)")
    if method == "coacd":
        _import_coacd()  # fail before anything is written
    robot = copy.deepcopy(robot)
    changes: list[ShapeChange] = []
    files: dict[str, str] = {}
    for link in robot.iter("link"):
        name = link.get("name", "")
        for index, collision in enumerate(link.findall("collision")):
            change, written = _optimize_one(
                name, index, collision, assets, method, max_vertices, tolerance, multiple_collisions
            )
            changes.append(change)
            files.update(written)
    assets.mkdir(parents=True, exist_ok=True)
    for file_name, text in sorted(files.items()):
        (assets / file_name).write_text(text, encoding="utf-8", newline="\n")
    return robot, tuple(changes)


def _optimize_one(
    link: str,
    index: int,
    collision: etree._Element,
    assets: Path,
    method: str,
    max_vertices: int | None,
    tolerance: float,
    multiple: bool,
) -> tuple[ShapeChange, dict[str, str]]:
    geometry = collision.find("geometry")
    shape = None if geometry is None or len(geometry) == 0 else geometry[0]
    if shape is None or shape.tag != "mesh":
        source = "nothing" if shape is None else str(shape.tag)
        kept = int(shape is not None)  # a primitive stays as it is: one shape, no vertices
        return ShapeChange(link, source, "kept", (), kept, kept, 0, 0), {}
    filename = shape.get("filename", "")
    path = Path(filename)
    if not path.is_file():  # SAPIEN loads a missing file as nothing: leave it to the checks
        return ShapeChange(link, filename, "kept", (), 0, 0, 0, 0), {}
    try:
        mesh = _read_mesh(path)
    except Exception:  # a format trimesh cannot read here (COLLADA without pycollada, ...):
        # SAPIEN reads it with assimp, as it is
        return ShapeChange(link, filename, "kept", (), 1, 1, 0, 0), {}
    parts_before = _sapien_parts(mesh) if multiple and filename.endswith(_STL_SUFFIXES) else None
    shapes_before = 1 if parts_before is None else len(parts_before)
    stem = f"{_safe(link)}_{index}"
    result = _replacement(
        method, collision, shape, mesh, parts_before, stem, assets, max_vertices, tolerance
    )
    if result is None:
        vertices = len(mesh.vertices)
        change = ShapeChange(
            link, filename, "kept", (), shapes_before, shapes_before, vertices, vertices
        )
        return change, {}
    _replace(collision, result.elements)
    change = ShapeChange(
        link,
        filename,
        result.method,
        tuple(name for name, _ in result.files),
        shapes_before,
        len(result.elements),
        len(mesh.vertices),
        result.vertices,
    )
    return change, dict(result.files)


def _replacement(
    method: str,
    collision: etree._Element,
    shape: etree._Element,
    mesh: _Mesh,
    parts: list[np.ndarray] | None,
    stem: str,
    assets: Path,
    max_vertices: int | None,
    tolerance: float,
) -> _Result | None:
    if method == "convert":
        if parts is None:
            return None  # not an STL SAPIEN splits: it loads as it did, without a warning
        return _as_meshes("convert", collision, [_point_obj(p) for p in parts], stem, assets)
    if method == "hull":
        vertices, faces = _hull(mesh.vertices, max_vertices)
        return _as_meshes("hull", collision, [_obj(vertices, faces)], stem, assets)
    if method == "coacd":
        hulls = _coacd(mesh, max_vertices, tolerance)
        return _as_meshes("coacd", collision, [_obj(v, f) for v, f in hulls], stem, assets)
    return _primitive(collision, shape, mesh, tolerance)


def _as_meshes(
    method: str,
    collision: etree._Element,
    objs: Sequence[tuple[str, int]],
    stem: str,
    assets: Path,
) -> _Result:
    """One ``<collision>`` per OBJ, each a copy of the original (origin, scale, name) naming its
    file: every part is then one convex shape whether or not the loader splits files."""
    elements: list[etree._Element] = []
    files: list[tuple[str, str]] = []
    for part, (text, _) in enumerate(objs):
        file_name = f"{stem}.obj" if len(objs) == 1 else f"{stem}_{part}.obj"
        element = copy.deepcopy(collision)
        mesh = element.find("geometry/mesh")
        assert mesh is not None
        mesh.set("filename", str(assets / file_name))
        if len(objs) > 1 and element.get("name"):
            element.set("name", f"{element.get('name')}_{part}")
        elements.append(element)
        files.append((file_name, text))
    return _Result(method, tuple(elements), tuple(files), sum(n for _, n in objs))


def _replace(collision: etree._Element, elements: Sequence[etree._Element]) -> None:
    parent = collision.getparent()
    assert parent is not None
    position = parent.index(collision)
    tail = collision.tail
    parent.remove(collision)
    for offset, element in enumerate(elements):
        element.tail = tail
        parent.insert(position + offset, element)


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "link"


# -- reading meshes, and SAPIEN's split


def _read_mesh(path: Path) -> _Mesh:
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
    return _Mesh(unique[order], rank[inverse.reshape(-1)].reshape(-1, 3))


def _sapien_parts(mesh: _Mesh) -> list[np.ndarray]:
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


# -- writing OBJ files


def _point_obj(points: np.ndarray) -> tuple[str, int]:
    """An OBJ whose vertices reach PhysX exactly as ``points``, in order. Assimp's OBJ reader makes
    one vertex per face corner, so the faces take the points three by three (the last repeated
    to fill a triangle: a repeated point changes nothing) -- a triangle soup, only a point set
    for the hull that PhysX cooks from it."""
    count = len(points)
    lines = [_HEADER, "# the points of one convex collision shape, in the order PhysX reads them\n"]
    lines += [_vertex_line(p) for p in points]
    indices = [*range(1, count + 1)] + [count] * (-count % 3)
    lines += [f"f {a} {b} {c}\n" for a, b, c in zip(*[iter(indices)] * 3, strict=True)]
    return "".join(lines), count


def _obj(vertices: np.ndarray, faces: np.ndarray) -> tuple[str, int]:
    lines = [_HEADER, *(_vertex_line(v) for v in vertices)]
    lines += [f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist()]
    return "".join(lines), len(vertices)


def _vertex_line(vertex: Any) -> str:
    return "v " + " ".join(_number(x) for x in vertex) + "\n"


# assimp's fast_atoreal_move (Real = float): the integer part, then at most 15 decimals read as
# double(digits) * 10^-n and added in float, then an exponent applied as f *= powf(10, exp)
_DECIMALS = [10.0**-n for n in range(16)]


def _assimp_reads(text: str) -> float:
    import numpy as np

    negative = text.startswith("-")
    mantissa, _, exponent = text.lstrip("-").partition("e")
    whole, _, fraction = mantissa.partition(".")
    value = np.float32(float(int(whole or "0")))
    if fraction:
        fraction = fraction[:15]
        value = np.float32(value + np.float32(int(fraction) * _DECIMALS[len(fraction)]))
    if exponent:
        value = np.float32(value * np.float32(10.0 ** int(exponent)))
    return float(-value if negative else value)


def _number(x: float) -> str:
    """``x`` as a float32 written so that assimp's OBJ reader reads back the same bits: PhysX's
    hull depends on every one (measured: a part of the G1's hip changes its volume by 1.5e-4 when
    values near 1e-9 are off by a rounding). Positional where that suffices (the shortest text,
    else more decimals); an exponent only for the tiny values 15 decimals cannot hold."""
    import numpy as np

    value = float(np.float32(x))
    text = np.format_float_positional(np.float32(x), unique=True, trim="-")
    if _assimp_reads(text) == value:
        return text
    candidates = [f"{value:.{decimals}f}" for decimals in range(1, 16)]
    if value != 0:
        exponent = math.floor(math.log10(abs(value)))
        for shift in (0, -1, 1):
            scaled = value / 10.0 ** (exponent + shift)
            candidates += [f"{scaled:.{d}f}e{exponent + shift}" for d in range(6, 16)]
    for candidate in candidates:
        if _assimp_reads(candidate) == value:
            return candidate
    return text


# -- hulls


def _hull(vertices: np.ndarray, max_vertices: int | None) -> tuple[np.ndarray, np.ndarray]:
    """The convex hull of ``vertices``; with ``max_vertices``, a hull of at most that many of its
    vertices, grown greedily: from the extreme points along the axes, add the vertex farthest
    outside the hull so far, until the cap. Inside the full hull, and close to it."""
    import numpy as np

    full = _convex_hull(vertices)
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
    return _canonical(_convex_hull(points[chosen]))


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


def _convex_hull(points: np.ndarray) -> trimesh.Trimesh:
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


# -- coacd


def _import_coacd() -> Any:
    try:
        import coacd
    except ImportError as error:
        raise MissingDependency("coacd", "pip install 'robospec[optimize]'") from error
    return coacd


def _coacd(
    mesh: _Mesh, max_vertices: int | None, threshold: float
) -> list[tuple[np.ndarray, np.ndarray]]:
    import numpy as np

    coacd = _import_coacd()
    coacd.set_log_level("error")
    parts = coacd.run_coacd(
        coacd.Mesh(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces)),
        threshold=threshold,  # the concavity each part may keep
        seed=0,  # the same parts every run
        max_ch_vertex=max_vertices or 256,
    )
    return [_hull(np.asarray(vertices), max_vertices) for vertices, _ in parts]


# -- primitives


def _primitive(
    collision: etree._Element, shape: etree._Element, mesh: _Mesh, tolerance: float
) -> _Result | None:
    """The box, capsule or sphere whose volume is nearest the mesh's hull's, if within
    ``tolerance`` of it; the mesh's scale is baked into the primitive's size."""
    import numpy as np

    scale = np.array([float(s) for s in (shape.get("scale") or "1 1 1").split()])
    points = np.asarray(mesh.vertices, dtype=np.float64) * scale
    hull = _convex_hull(points)
    volume = float(hull.volume)
    if volume <= 0:
        return None
    fits = [fit for fit in (_box(hull), _capsule(hull), _sphere(hull)) if fit is not None]
    best = min(fits, key=lambda fit: abs(fit[1] - volume))
    if abs(best[1] - volume) > tolerance * volume:
        return None
    kind, _, attributes, transform = best
    element = copy.deepcopy(collision)
    geometry = element.find("geometry")
    assert geometry is not None
    for child in list(geometry):
        geometry.remove(child)
    etree.SubElement(geometry, kind, attributes)
    _set_origin(element, _origin_matrix(collision) @ transform)
    return _Result(kind, (element,), (), 0)


_Fit = tuple[str, float, dict[str, str], Any]  # tag, volume, attributes, transform in the mesh


def _box(hull: trimesh.Trimesh) -> _Fit | None:
    import trimesh

    transform, extents = trimesh.bounds.oriented_bounds(hull)
    size = [float(e) for e in extents]
    # oriented_bounds gives the transform that moves the mesh to the box: the box is its inverse
    return "box", size[0] * size[1] * size[2], {"size": _floats(size)}, _inverse(transform)


def _capsule(hull: trimesh.Trimesh) -> _Fit | None:
    """Along the oriented box's longest axis, the thinnest capsule around the hull's vertices."""
    import numpy as np
    import trimesh

    to_box, extents = trimesh.bounds.oriented_bounds(hull)
    box = _inverse(to_box)
    axis = int(np.argmax(extents))
    # turn the longest axis onto z (URDF's capsule axis; SAPIEN turns it onto PhysX's x)
    swap = np.eye(4)
    swap[:3, :3] = np.roll(np.eye(3), 2 - axis, axis=0)
    frame = box @ np.linalg.inv(swap)
    local = trimesh.transform_points(np.asarray(hull.vertices), np.linalg.inv(frame))
    radius = float(np.max(np.hypot(local[:, 0], local[:, 1])))
    if radius <= 0:
        return None
    reach = np.sqrt(np.maximum(radius**2 - local[:, 0] ** 2 - local[:, 1] ** 2, 0.0))
    top = float(np.max(local[:, 2] - reach))
    bottom = float(np.min(local[:, 2] + reach))
    length = max(top - bottom, 0.0)
    centre = np.eye(4)
    centre[2, 3] = (top + bottom) / 2
    volume = math.pi * radius**2 * length + 4 / 3 * math.pi * radius**3
    attributes = {"radius": _floats([radius]), "length": _floats([length])}
    return "capsule", volume, attributes, frame @ centre


def _sphere(hull: trimesh.Trimesh) -> _Fit | None:
    import numpy as np
    import trimesh

    centre, radius = trimesh.nsphere.minimum_nsphere(np.asarray(hull.vertices))
    transform = np.eye(4)
    transform[:3, 3] = centre
    volume = 4 / 3 * math.pi * float(radius) ** 3
    return "sphere", volume, {"radius": _floats([float(radius)])}, transform


# -- origins


def _origin_matrix(collision: etree._Element) -> np.ndarray:
    import trimesh

    origin = collision.find("origin")
    xyz = _read(origin, "xyz")
    rpy = _read(origin, "rpy")
    matrix = trimesh.transformations.euler_matrix(*rpy, axes="sxyz")
    matrix[:3, 3] = xyz
    return matrix


def _read(origin: etree._Element | None, key: str) -> list[float]:
    text = None if origin is None else origin.get(key)
    return [float(v) for v in text.split()] if text else [0.0, 0.0, 0.0]


def _set_origin(collision: etree._Element, matrix: np.ndarray) -> None:
    import trimesh

    origin = collision.find("origin")
    if origin is None:
        origin = etree.Element("origin")
        collision.insert(0, origin)
    rpy = trimesh.transformations.euler_from_matrix(matrix, axes="sxyz")
    origin.set("xyz", _floats(matrix[:3, 3]))
    origin.set("rpy", _floats(rpy))


def _inverse(matrix: np.ndarray) -> np.ndarray:
    import numpy as np

    return np.linalg.inv(matrix)


def _floats(values: Iterator[float] | Sequence[float] | Any) -> str:
    # 9 significant digits: float32 precision (what PhysX keeps), and stable text
    return " ".join(_short(float(v)) for v in values)


def _short(value: float) -> str:
    text = f"{value:.9g}"
    return "0" if text in ("-0", "0") else text
