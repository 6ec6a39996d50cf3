"""``primitives``: a box, capsule or sphere for each shape SAPIEN builds from a mesh, where one
stands off it by at most ``max_error``; their sizes and origins as URDF writes them."""

from __future__ import annotations

import copy
import math
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from lxml import etree

from robospec.geometry import matrix_from_rpy, rpy_from_matrix
from robospec.optimize.shapes.elements import Result, as_meshes
from robospec.optimize.shapes.error_bound import Fit, fit_error
from robospec.optimize.shapes.hull import convex_hull
from robospec.optimize.shapes.mesh import Mesh
from robospec.optimize.shapes.obj import point_obj

if TYPE_CHECKING:
    import numpy as np
    import trimesh


def fit_primitives(
    collision: etree._Element,
    shape: etree._Element,
    mesh: Mesh,
    parts: list[np.ndarray] | None,
    stem: str,
    assets: Path,
    max_error: float,
) -> Result | None:
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
        return Result("unfitted", (), (), 0, fit_error=error, fit=kind)
    elements: list[etree._Element] = []
    files: list[tuple[str, str]] = []
    vertices = 0
    for part, (points, fit) in enumerate(zip(pieces, fits, strict=True)):
        if fit is not None and fit[2] <= max_error:
            elements.append(fit[0])
            continue
        # one of several parts, none fitting it: the convex shape SAPIEN cooks from it
        text, count = point_obj(points)
        converted = as_meshes("convert", collision, [(text, count)], f"{stem}_{part}", assets)
        elements += converted.elements
        files += converted.files
        vertices += count
    kinds = sorted({fit[1] for fit in fitted})
    return Result(
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
        hull = convex_hull(np.asarray(points, dtype=np.float64) * scale)
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


def _fits(hull: trimesh.Trimesh, bounds: tuple[np.ndarray, np.ndarray]) -> list[Fit]:
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


def _box(bounds: tuple[np.ndarray, np.ndarray]) -> Fit | None:
    transform, extents = bounds
    size = [float(e) for e in extents]
    # oriented_bounds gives the transform that moves the mesh to the box: the box is its inverse
    return "box", size[0] * size[1] * size[2], {"size": _floats(size)}, _inverse(transform)


def _capsule(hull: trimesh.Trimesh, bounds: tuple[np.ndarray, np.ndarray]) -> Fit | None:
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


def _sphere(hull: trimesh.Trimesh, bounds: tuple[np.ndarray, np.ndarray]) -> Fit | None:
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
