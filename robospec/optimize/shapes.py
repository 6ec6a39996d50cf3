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
OBJ per part), ``primitives`` (a box, capsule or sphere where one lies within ``max_error``
metres of the mesh's hull, each mesh not fitted becoming its ``convert`` shapes). A primitive
fit encloses the hull (the oriented bounding box, the thinnest capsule along its longest axis,
the smallest sphere), so its error is how far its surface stands off the hull at most
(:func:`fit_error`). A link whose mass SAPIEN takes from its collision shapes (no usable
``<inertial>``) keeps its meshes: a primitive would change its mass. trimesh and numpy are
imported when the function runs (they cost a second).
"""

from __future__ import annotations

import copy
import dataclasses
import math
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

from robospec.geometry import matrix_from_rpy, rpy_from_matrix
from robospec.optimize.condense import mass_from_shapes

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
    # primitives: the best fit's error in m (whether or not it was within the bound), and why
    # a mesh was kept ("" when it was not, or for the other methods)
    fit_error: float | None = None
    fit: str = ""  # the best fit's kind (box, capsule, sphere)
    reason: str = ""
    primitives: int = 0  # shapes written as primitives


@dataclass(frozen=True)
class _Mesh:
    """A collision mesh read: distinct float32 vertices in first-occurrence order (what assimp's
    JoinIdenticalVertices keeps) and triangles over them."""

    vertices: np.ndarray
    faces: np.ndarray


@dataclass(frozen=True)
class _Result:
    """One collision element's replacement: new elements and files, or nothing (kept)."""

    method: str  # "unfitted": no primitive within the bound (elements: none)
    elements: tuple[etree._Element, ...]
    files: tuple[tuple[str, str], ...]  # (file name, OBJ text)
    vertices: int
    fit_error: float | None = None
    fit: str = ""
    primitives: int = 0


def optimize_collisions(
    robot: etree._Element,
    assets: Path,
    *,
    method: str = "convert",
    max_vertices: int | None = None,
    tolerance: float = 0.05,
    multiple_collisions: bool = True,
    max_error: float = 0.005,
) -> tuple[etree._Element, tuple[ShapeChange, ...]]:
    """A copy of ``robot`` (a URDF ``<robot>`` whose collision mesh paths are absolute) whose
    collision meshes are rewritten by ``method``, the new files written under ``assets`` (named
    ``<link>_<collision>[_<part>].obj``, same input, same bytes) and named by absolute path; and
    one :class:`ShapeChange` per collision element. ``multiple_collisions`` is the loader's
    ``load_multiple_collisions``: what ``convert`` must reproduce (without it an STL already
    loads as one hull, silently, and is kept). ``tolerance`` is coacd's concavity threshold;
    ``max_error`` the distance in m a primitive may stand off the mesh's hull."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: one of {', '.join(METHODS)}")
    if max_vertices is not None and max_vertices < 4:
        raise ValueError("max_vertices must be at least 4 (a tetrahedron)")
    if not max_error > 0:
        raise ValueError(f"max_error must be positive, not {max_error}")
    if method == "coacd":
        _import_coacd()  # fail before anything is written
    robot = copy.deepcopy(robot)
    changes: list[ShapeChange] = []
    files: dict[str, str] = {}
    for link in robot.iter("link"):
        name = link.get("name", "")
        # SAPIEN weighs this link by its shapes: a primitive would change its mass
        weighed = method == "primitives" and mass_from_shapes(link)
        for index, collision in enumerate(link.findall("collision")):
            change, written = _optimize_one(
                name,
                index,
                collision,
                assets,
                "convert" if weighed else method,
                max_vertices,
                (tolerance, max_error),
                multiple_collisions,
            )
            if weighed and change.method == "kept":
                change = dataclasses.replace(change, reason="mass from its collision shapes")
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
    bounds: tuple[float, float],  # coacd's tolerance, the primitives' max_error
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
        method, collision, shape, mesh, parts_before, stem, assets, max_vertices, bounds
    )
    if result is None:
        vertices = len(mesh.vertices)
        change = ShapeChange(
            link, filename, "kept", (), shapes_before, shapes_before, vertices, vertices
        )
        return change, {}
    if result.method == "unfitted":
        # no primitive within the bound: the mesh stays what SAPIEN makes of it (convert)
        converted = _replacement(
            "convert", collision, shape, mesh, parts_before, stem, assets, max_vertices, bounds
        )
        fitted = dataclasses.replace(result, method="kept")
        if converted is not None:
            _replace(collision, converted.elements)
            fitted = dataclasses.replace(converted, fit_error=result.fit_error, fit=result.fit)
        else:
            fitted = dataclasses.replace(fitted, vertices=len(mesh.vertices))
        count = len(fitted.elements) if converted is not None else shapes_before
        change = ShapeChange(
            link,
            filename,
            fitted.method,
            tuple(name for name, _ in fitted.files),
            shapes_before,
            count,
            len(mesh.vertices),
            fitted.vertices,
            fit_error=result.fit_error,
            fit=result.fit,
            reason="no primitive within the bound",
        )
        return change, dict(fitted.files)
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
        fit_error=result.fit_error,
        fit=result.fit,
        primitives=result.primitives,
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
    bounds: tuple[float, float],
) -> _Result | None:
    tolerance, max_error = bounds
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
    return _primitives(collision, shape, mesh, parts, stem, assets, max_error)


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


def _primitives(
    collision: etree._Element,
    shape: etree._Element,
    mesh: _Mesh,
    parts: list[np.ndarray] | None,
    stem: str,
    assets: Path,
    max_error: float,
) -> _Result | None:
    """Each shape SAPIEN builds from the mesh (its hull, or each part's of an STL it splits) as
    the box, capsule or sphere that stands off it least, where one does by at most
    ``max_error`` m; a part none fits stays the shape SAPIEN makes of it (as ``convert``
    writes it). ``unfitted`` when no shape fits (elements: none), naming the nearest miss."""
    pieces = parts if parts is not None else [mesh.vertices]
    fits = [_fit(collision, shape, points, max_error) for points in pieces]
    fitted = [fit for fit in fits if fit is not None and fit[2] <= max_error]
    if not fitted:
        misses = [fit for fit in fits if fit is not None]
        if not misses:
            return None
        kind, error = min(((f[1], f[2]) for f in misses), key=lambda pair: pair[1])
        return _Result("unfitted", (), (), 0, fit_error=error, fit=kind)
    elements: list[etree._Element] = []
    files: list[tuple[str, str]] = []
    vertices = 0
    for part, (points, fit) in enumerate(zip(pieces, fits, strict=True)):
        if fit is not None and fit[2] <= max_error:
            elements.append(fit[0])
            continue
        # one of several parts, none fitting it: the convex shape SAPIEN cooks from it
        text, count = _point_obj(points)
        converted = _as_meshes("convert", collision, [(text, count)], f"{stem}_{part}", assets)
        elements += converted.elements
        files += converted.files
        vertices += count
    kinds = sorted({fit[1] for fit in fitted})
    return _Result(
        fitted[0][1] if len(pieces) == 1 else "primitives",
        tuple(elements),
        tuple(files),
        vertices,
        fit_error=max(fit[2] for fit in fitted),
        fit="/".join(kinds),
        primitives=len(fitted),
    )


def _fit(
    collision: etree._Element, shape: etree._Element, points: np.ndarray, max_error: float
) -> tuple[etree._Element, str, float] | None:
    """The ``<collision>`` holding the box, capsule or sphere around ``points`` (in the mesh's
    frame, before its scale) that stands off their hull least, its kind and that distance in
    m; the mesh's scale is baked into the primitive's size. None for a flat part."""
    import numpy as np
    import trimesh

    scale = np.array([float(s) for s in (shape.get("scale") or "1 1 1").split()])
    try:
        hull = _convex_hull(np.asarray(points, dtype=np.float64) * scale)
    except Exception:  # fewer than four points not in a plane: qhull finds no hull
        return None
    if float(hull.volume) <= 0:
        return None
    # the principal axes first (cheap); the smallest oriented box (trimesh's search, a third
    # of a second on a detailed hull) only when a fit comes within four times the bound
    fits = _fits(hull, _principal_bounds(hull))
    errors = [fit_error(fit, hull) for fit in fits]
    if min(errors) <= 4 * max_error:
        tighter = _fits(hull, trimesh.bounds.oriented_bounds(hull))
        fits += tighter
        errors += [fit_error(fit, hull) for fit in tighter]
    best = int(np.argmin(errors))
    kind, _, attributes, transform = fits[best]
    element = copy.deepcopy(collision)
    geometry = element.find("geometry")
    assert geometry is not None
    for child in list(geometry):
        geometry.remove(child)
    etree.SubElement(geometry, kind, attributes)
    _set_origin(element, _origin_matrix(collision) @ transform)
    return element, kind, float(errors[best])


# directions over which a fit's error is sought, before the best few are refined
_DIRECTIONS = 1000
_REFINED = 4


def fit_error(fit: _Fit, hull: trimesh.Trimesh) -> float:
    """How far the primitive's surface stands off the hull at most, in m.

    The fit encloses the hull; for two convex shapes the Hausdorff distance is the largest
    difference of their support functions over directions u (h(u): how far the shape reaches
    along u), which both have in closed form here: the hull's from its vertices, a box's from
    its half extents, a sphere's and a capsule's from their centres and radius. It is sought
    over directions spread evenly on the sphere, the best few then refined by a local search
    (the difference is smooth away from a few directions): exact to a few hundredths of a
    millimetre on shapes of robot links."""
    import numpy as np

    vertices = np.asarray(hull.vertices, dtype=np.float64)
    reach = _support(fit)

    def gap(directions: np.ndarray) -> np.ndarray:
        directions = directions / np.linalg.norm(directions, axis=-1, keepdims=True)
        return reach(directions) - np.max(directions @ vertices.T, axis=-1)

    # a Fibonacci sphere: the same directions every run
    index = np.arange(_DIRECTIONS) + 0.5
    polar = np.arccos(1 - 2 * index / _DIRECTIONS)
    azimuth = np.pi * (1 + 5**0.5) * index
    directions = np.stack(
        [np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)], axis=1
    )
    gaps = gap(directions)
    best = float(np.max(gaps))
    # refine around the best few: rounds of perturbations in a shrinking cone, all at once
    rng = np.random.default_rng(0)
    candidates = directions[np.argsort(gaps)[-_REFINED:]]
    for spread in (0.05, 0.015, 0.005, 0.0015, 0.0005):
        tried = candidates[:, None, :] + spread * rng.standard_normal((len(candidates), 32, 3))
        tried = np.concatenate([candidates[:, None, :], tried], axis=1)
        scores = gap(tried.reshape(-1, 3)).reshape(len(candidates), -1)
        candidates = tried[np.arange(len(candidates)), np.argmax(scores, axis=1)]
        best = max(best, float(np.max(scores)))
    return max(best, 0.0)


def _support(fit: _Fit) -> Any:
    """The fit's support function: directions (n, 3) -> how far it reaches along each."""
    import numpy as np

    kind, _, attributes, transform = fit
    rotation, centre = np.asarray(transform)[:3, :3], np.asarray(transform)[:3, 3]
    if kind == "box":
        half = np.array([float(v) for v in attributes["size"].split()]) / 2
        return lambda u: u @ centre + np.abs(u @ rotation) @ half
    radius = float(attributes["radius"])
    if kind == "sphere":
        return lambda u: u @ centre + radius
    axis = rotation[:, 2] * float(attributes["length"]) / 2  # the capsule's axis is its z
    return lambda u: u @ centre + np.abs(u @ axis) + radius


_Fit = tuple[str, float, dict[str, str], Any]  # tag, volume, attributes, transform in the mesh


def _fits(hull: trimesh.Trimesh, bounds: tuple[np.ndarray, np.ndarray]) -> list[_Fit]:
    """The box and the capsule of a frame of the hull, and its smallest sphere."""
    fits = (_box(bounds), _capsule(hull, bounds), _sphere(hull, bounds))
    return [fit for fit in fits if fit is not None]


def _principal_bounds(hull: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    """As ``trimesh.bounds.oriented_bounds`` gives them (the transform that moves the hull
    into a box centred at the origin, and the box's extents), along the hull's principal
    axes of inertia."""
    import numpy as np

    points = np.asarray(hull.vertices, dtype=np.float64)
    _, axes = np.linalg.eigh(np.asarray(hull.moment_inertia))
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    local = points @ axes
    low, high = local.min(axis=0), local.max(axis=0)
    to_box = np.eye(4)
    to_box[:3, :3] = axes.T
    to_box[:3, 3] = -(low + high) / 2
    return to_box, high - low


def _box(bounds: tuple[np.ndarray, np.ndarray]) -> _Fit | None:
    transform, extents = bounds
    size = [float(e) for e in extents]
    # oriented_bounds gives the transform that moves the mesh to the box: the box is its inverse
    return "box", size[0] * size[1] * size[2], {"size": _floats(size)}, _inverse(transform)


def _capsule(hull: trimesh.Trimesh, bounds: tuple[np.ndarray, np.ndarray]) -> _Fit | None:
    """Along the oriented box's longest axis, the thinnest capsule around the hull's vertices."""
    import numpy as np
    import trimesh

    to_box, extents = bounds
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


def _sphere(hull: trimesh.Trimesh, bounds: tuple[np.ndarray, np.ndarray]) -> _Fit | None:
    """The sphere around the hull centred on its box: within a few % of the smallest (an
    exact smallest sphere takes trimesh a tenth of a second per hull), and a fit that is
    near the bound at all is of a near-round shape, whose box centre is its sphere's."""
    import numpy as np

    points = np.asarray(hull.vertices, dtype=np.float64)
    centre = _inverse(bounds[0])[:3, 3]
    radius = float(np.max(np.linalg.norm(points - centre, axis=1)))
    transform = np.eye(4)
    transform[:3, 3] = centre
    volume = 4 / 3 * math.pi * float(radius) ** 3
    return "sphere", volume, {"radius": _floats([float(radius)])}, transform


# -- origins


def _origin_matrix(collision: etree._Element) -> np.ndarray:
    import numpy as np

    origin = collision.find("origin")
    xyz = _read(origin, "xyz")
    roll, pitch, yaw = _read(origin, "rpy")
    matrix = np.eye(4)
    matrix[:3, :3] = matrix_from_rpy(roll, pitch, yaw)
    matrix[:3, 3] = xyz
    return matrix


def _read(origin: etree._Element | None, key: str) -> list[float]:
    text = None if origin is None else origin.get(key)
    return [float(v) for v in text.split()] if text else [0.0, 0.0, 0.0]


def _set_origin(collision: etree._Element, matrix: np.ndarray) -> None:
    origin = collision.find("origin")
    if origin is None:
        origin = etree.Element("origin")
        collision.insert(0, origin)
    rows = matrix[:3, :3].tolist()
    rpy = rpy_from_matrix((tuple(rows[0]), tuple(rows[1]), tuple(rows[2])))
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
