"""The size of a URDF link's collision shapes, in its frame: what an inertia from the shapes is
made of (the ``shapes`` inertia policy, in the spirit of MuJoCo's ``inertiafromgeom``).

Primitives are measured from their attributes, meshes from their vertices
(robospec.description.mesh_data), each placed by its ``<origin>`` and scaled by its ``scale``.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping

from lxml import etree

from robospec.description.mesh_data import read_mesh
from robospec.description.meshes import locate
from robospec.description.packages import PackageFinder, find_up
from robospec.geometry import Matrix, Vector, apply, matrix_from_rpy

Box = tuple[Vector, Vector]  # the least and the greatest corner


def collision_box(
    link: etree._Element, path: str, packages: Mapping[str, str] | None = None
) -> Box | None:
    """The axis-aligned box, in the link's frame, around every collision shape of ``link``
    (of the URDF at ``path``); None when it has none robospec can measure."""
    base_dir = os.path.dirname(os.path.abspath(path))
    finder = PackageFinder(base_dir, packages)
    corners: list[Vector] = []
    for collision in link.iterfind("collision"):
        local = _local_box(collision, base_dir, finder)
        if local is None:
            continue
        rotation, offset = _origin(collision)
        for corner in _corners(local):
            rotated = apply(rotation, corner)
            corners.append((rotated[0] + offset[0], rotated[1] + offset[1], rotated[2] + offset[2]))
    if not corners:
        return None
    low = tuple(min(c[i] for c in corners) for i in range(3))
    high = tuple(max(c[i] for c in corners) for i in range(3))
    return low, high  # type: ignore[return-value]


def box_inertia(mass: float, box: Box) -> tuple[float, ...]:
    """(ixx, ixy, ixz, iyy, iyz, izz) of a solid box of ``mass`` filling ``box``."""
    x, y, z = (box[1][i] - box[0][i] for i in range(3))
    k = mass / 12
    return (k * (y * y + z * z), 0.0, 0.0, k * (x * x + z * z), 0.0, k * (x * x + y * y))


def _local_box(collision: etree._Element, base_dir: str, finder: PackageFinder) -> Box | None:
    geometry = collision.find("geometry")
    if geometry is None:
        return None
    for shape in geometry:
        try:
            if shape.tag == "box":
                x, y, z = (float(v) / 2 for v in shape.get("size", "").split())
                return (-x, -y, -z), (x, y, z)
            if shape.tag == "sphere":
                r = float(shape.get("radius", ""))
                return (-r, -r, -r), (r, r, r)
            if shape.tag in ("cylinder", "capsule"):
                r, half = float(shape.get("radius", "")), float(shape.get("length", "")) / 2
                half += r if shape.tag == "capsule" else 0
                return (-r, -r, -half), (r, r, half)
            if shape.tag == "mesh":
                return _mesh_box(shape, base_dir, finder)
        except ValueError:
            return None
    return None


def _mesh_box(mesh: etree._Element, base_dir: str, finder: PackageFinder) -> Box | None:
    uri = mesh.get("filename", "")
    if uri.startswith("package:///"):  # names no package: where it can only mean
        path = find_up(uri[len("package://") :], base_dir)
    else:
        path, _ = locate(uri, base_dir, finder)
    data = read_mesh(path) if path is not None else None
    bounds = data.bounds() if data is not None else None
    if bounds is None:
        return None
    scale = [float(v) for v in mesh.get("scale", "1 1 1").split()]
    if len(scale) != 3:
        return None
    ends = [[bounds[0][i] * scale[i], bounds[1][i] * scale[i]] for i in range(3)]
    return (
        (min(ends[0]), min(ends[1]), min(ends[2])),
        (max(ends[0]), max(ends[1]), max(ends[2])),
    )


def _origin(element: etree._Element) -> tuple[Matrix, Vector]:
    origin = element.find("origin")
    xyz, rpy = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    if origin is not None:
        try:
            xyz = [float(v) for v in origin.get("xyz", "0 0 0").split()][:3] or xyz
            rpy = [float(v) for v in origin.get("rpy", "0 0 0").split()][:3] or rpy
        except ValueError:
            pass
    roll, pitch, yaw = rpy
    return matrix_from_rpy(roll, pitch, yaw), (xyz[0], xyz[1], xyz[2])


def _corners(box: Box) -> Iterator[Vector]:
    for x in (box[0][0], box[1][0]):
        for y in (box[0][1], box[1][1]):
            for z in (box[0][2], box[1][2]):
                yield (x, y, z)
