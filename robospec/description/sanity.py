"""What other robot doctors check of a URDF and SAPIEN does not: located warnings about a
description that loads but is probably not what its author meant.

- RS088: lengths in millimetres (joint origins and primitive sizes hundreds of times a robot's);
- RS089: an inertia far too large or too small for the link's mass and collision shapes (the
  radius of gyration against the shapes' size: kg·mm² written as kg·m² is 10⁶ too large);
- RS090: masses under a gram beside links of kilograms (the solver struggles with the ratio);
- RS091: a driven joint with no or zero effort or velocity limit;
- RS093: collision meshes whose contents SAPIEN cannot use: NaN or infinite vertices, no
  triangles, or flat (PhysX's QuickHull logs "critical" and builds nothing).

Each kind is one warning per description, at the first element, with the count and the lines
of the others. Meshes are read by robospec.description.mesh_data (STL, OBJ, COLLADA), each once.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping

from lxml import etree

from robospec.description.facts import MeshFile
from robospec.description.inertia import principal_moments
from robospec.description.mesh_data import read_mesh
from robospec.description.shapes import collision_box
from robospec.description.urdf_values import Findings, at
from robospec.diagnostics import Diagnostic, Location, warning
from robospec.diagnostics.codes import (
    INERTIA_FOR_SIZE,
    MESH_CONTENTS,
    MILLIMETRES,
    NO_RATE_LIMIT,
    TINY_MASS,
)

SANITY_CODES = frozenset({MILLIMETRES, INERTIA_FOR_SIZE, TINY_MASS, NO_RATE_LIMIT, MESH_CONTENTS})

# a typical joint offset of more than this is no robot's (a humanoid's are tenths of a metre)
_MILLIMETRE_MEDIAN = 5.0  # m
TINY = 1e-3  # kg: under a gram
_HEAVY = 1.0  # kg: beside a link this heavy
# a radius of gyration this many times the shapes' half-diagonal, or this fraction of it
_TOO_LARGE, _TOO_SMALL = 30.0, 1e-3


def check_sanity(
    root: etree._Element,
    path: str,
    mesh_files: tuple[MeshFile, ...],
    packages: Mapping[str, str] | None = None,
) -> list[Diagnostic]:
    found = Findings()
    _millimetres(root, path, found)
    _masses_and_inertias(root, path, packages, found)
    _rate_limits(root, path, found)
    _mesh_contents(mesh_files, path, found)
    return found.result()


def _floats(text: str | None) -> list[float]:
    try:
        return [float(v) for v in (text or "").split()]
    except ValueError:
        return []


def _millimetres(root: etree._Element, path: str, found: Findings) -> None:
    offsets = []
    for origin in root.iterfind("joint/origin"):
        xyz = _floats(origin.get("xyz"))
        if len(xyz) == 3 and all(math.isfinite(v) for v in xyz):
            length = math.sqrt(sum(v * v for v in xyz))
            if length > 0:
                offsets.append((length, origin))
    if len(offsets) < 2 or statistics.median(o[0] for o in offsets) < _MILLIMETRE_MEDIAN:
        return
    length, origin = max(offsets, key=lambda o: o[0])
    found.add(
        warning(
            at(path, origin),
            MILLIMETRES,
            f"the joint origins look like millimetres: half of them are more than "
            f"{statistics.median(o[0] for o in offsets):.3g} m apart, and this one "
            f"{length:.3g} m; SAPIEN reads metres",
            "write the lengths in metres (scale a mesh written in millimetres with "
            'scale="0.001 0.001 0.001")',
        )
    )


def _masses_and_inertias(
    root: etree._Element, path: str, packages: Mapping[str, str] | None, found: Findings
) -> None:
    masses: list[tuple[float, etree._Element, etree._Element]] = []
    for link in root.iterfind("link"):
        element = link.find("inertial/mass")
        value = _floats(element.get("value") if element is not None else None)
        if element is not None and len(value) == 1 and math.isfinite(value[0]):
            masses.append((value[0], element, link))
    heaviest = max((m for m, _, _ in masses), default=0.0)
    for mass, element, link in masses:
        name = link.get("name")
        if 0 < mass < TINY and heaviest >= _HEAVY:
            found.add(
                warning(
                    at(path, element),
                    TINY_MASS,
                    f"link '{name}' weighs {mass:g} kg beside links of up to {heaviest:.3g} kg: "
                    "PhysX solves such mass ratios poorly (joints drift, the state can go NaN)",
                    "give it its real mass, or `description: {mend: {mass: bound}}` raises "
                    "masses under a gram to 1 g",
                ),
                fold_as="more links under a gram",
            )
        _inertia_for_size(link, mass, path, packages, found)


def _inertia_for_size(
    link: etree._Element,
    mass: float,
    path: str,
    packages: Mapping[str, str] | None,
    found: Findings,
) -> None:
    inertia = link.find("inertial/inertia")
    if inertia is None or mass <= 0:
        return
    values = [_floats(inertia.get(a)) for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
    if any(len(v) != 1 for v in values) or not any(v[0] for v in values):
        return
    largest = principal_moments(*(v[0] for v in values))[2]
    if largest <= 0:
        return  # SAPIEN rejects it: RS059 says so
    box = collision_box(link, path, packages)
    if box is None:
        return
    half_diagonal = 0.5 * math.sqrt(sum((box[1][i] - box[0][i]) ** 2 for i in range(3)))
    if half_diagonal <= 0:
        return
    gyration = math.sqrt(largest / mass)
    ratio = gyration / half_diagonal
    if _TOO_SMALL <= ratio <= _TOO_LARGE:
        return
    how = "large" if ratio > _TOO_LARGE else "small"
    found.add(
        warning(
            at(path, inertia),
            INERTIA_FOR_SIZE,
            f"link '{link.get('name')}': the inertia is far too {how} for its mass and shapes: "
            f"a radius of gyration of {gyration:.3g} m for shapes {2 * half_diagonal:.3g} m "
            "across" + (" (kg·mm² written as kg·m² is 10⁶ too large)" if how == "large" else ""),
            "check its units and that it is about the centre of mass; `description: {mend: "
            "{inertia: shapes}}` writes the inertia of the shapes instead",
        ),
        fold_as=f"more inertias far too {how} for their links",
    )


def _rate_limits(root: etree._Element, path: str, found: Findings) -> None:
    for joint in root.iterfind("joint"):
        if joint.get("type") not in ("revolute", "prismatic"):
            continue
        if joint.find("mimic") is not None:
            continue  # driven through its leader
        limit = joint.find("limit")
        missing = [
            a
            for a in ("effort", "velocity")
            if limit is None or _floats(limit.get(a)) in ([], [0.0])
        ]
        if missing:
            found.add(
                warning(
                    at(path, limit if limit is not None else joint),
                    NO_RATE_LIMIT,
                    f"joint '{joint.get('name')}' has no {' or '.join(missing)} limit (or 0): "
                    "nothing in the description bounds the force or the speed its drive may use",
                    'write <limit effort="..." velocity="..."/> from the actuator\'s data sheet',
                ),
                fold_as="more joints without an effort or velocity limit",
            )


def _mesh_contents(mesh_files: tuple[MeshFile, ...], path: str, found: Findings) -> None:
    seen: set[str] = set()
    for mesh in mesh_files:
        if mesh.role != "collision" or mesh.path is None or mesh.path in seen:
            continue
        seen.add(mesh.path)
        data = read_mesh(mesh.path)
        if data is None:
            continue
        reason = None
        if not data.finite:
            reason = "it has NaN or infinite vertices"
        elif data.vertex_count < 4:
            reason = "it has fewer than four vertices"
        elif data.flat_axis() is not None:
            reason = f"it is flat (all its vertices share one {'xyz'[data.flat_axis() or 0]})"
        if reason is not None:
            found.add(
                warning(
                    at_line(path, mesh.line),
                    MESH_CONTENTS,
                    f"collision mesh '{mesh.uri}': PhysX can build no convex shape from it: "
                    f"{reason} (SAPIEN logs 'critical: QuickHull ...' and the link loads without "
                    "this shape)",
                    "fix or replace the mesh file, or give the link a primitive collision shape",
                ),
                fold_as="more collision meshes PhysX cannot use",
            )


def at_line(path: str, line: int) -> Location:
    from robospec.description.source_columns import tag_column

    return Location(path, max(line, 1), tag_column(path, max(line, 1), "mesh"))
