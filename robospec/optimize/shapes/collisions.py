"""Each link's ``<collision>`` elements rewritten by a method: what
:func:`optimize_collisions` does, element by element, and what it reports of each."""

from __future__ import annotations

import copy
import dataclasses
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from lxml import etree

from robospec.optimize.condense import mass_from_shapes
from robospec.optimize.options import ShapeMethod
from robospec.optimize.shapes.decompose import coacd_hulls, import_coacd
from robospec.optimize.shapes.elements import Result, as_meshes, replace_element
from robospec.optimize.shapes.hull import capped_hull
from robospec.optimize.shapes.mesh import STL_SUFFIXES, Mesh, read_mesh, sapien_parts
from robospec.optimize.shapes.obj import obj_text, point_obj
from robospec.optimize.shapes.primitives import fit_primitives

if TYPE_CHECKING:
    import numpy as np

# what optimize_collisions does: every shapes method but keep, which does nothing
METHODS = tuple(m.value for m in ShapeMethod if m is not ShapeMethod.keep)


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
        import_coacd()  # fail before anything is written
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
        mesh = read_mesh(path)
    except Exception:  # a format trimesh cannot read here (COLLADA without pycollada, ...):
        # SAPIEN reads it with assimp, as it is
        return ShapeChange(link, filename, "kept", (), 1, 1, 0, 0), {}
    parts_before = sapien_parts(mesh) if multiple and filename.endswith(STL_SUFFIXES) else None
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
            replace_element(collision, converted.elements)
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
    replace_element(collision, result.elements)
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
    mesh: Mesh,
    parts: list[np.ndarray] | None,
    stem: str,
    assets: Path,
    max_vertices: int | None,
    bounds: tuple[float, float],
) -> Result | None:
    tolerance, max_error = bounds
    if method == "convert":
        if parts is None:
            return None  # not an STL SAPIEN splits: it loads as it did, without a warning
        return as_meshes("convert", collision, [point_obj(p) for p in parts], stem, assets)
    if method == "hull":
        vertices, faces = capped_hull(mesh.vertices, max_vertices)
        return as_meshes("hull", collision, [obj_text(vertices, faces)], stem, assets)
    if method == "coacd":
        hulls = coacd_hulls(mesh, max_vertices, tolerance)
        return as_meshes("coacd", collision, [obj_text(v, f) for v, f in hulls], stem, assets)
    return fit_primitives(collision, shape, mesh, parts, stem, assets, max_error)


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "link"
