"""Mend class ``mirrors: copies`` (RS714): collision meshes mirrored by a negative scale.

A URDF often draws a robot's right side with the left side's mesh and ``scale="1 -1 1"``
(PAL's TALOS, thirteen times). PhysX cannot mirror a convex mesh: SAPIEN hands it the negative
scale anyway, and the first contact between two such shapes kills the process in native code
(RS087). The mend writes a mirrored copy of each such mesh file (its vertices mirrored, its
triangles turned so they still face out) and names it with the scale's magnitudes, so PhysX
builds the same shape the file means. The copies are written once, named by their content, in
robospec's cache folder (``derived/``); ``build`` copies them into the package like any mesh.
Visual meshes are left as they are: the renderer mirrors them well.
"""

from __future__ import annotations

import hashlib
import os
import struct
from typing import Literal

from robospec.derive.document import Document
from robospec.description.mesh_data import MeshData, read_mesh
from robospec.description.meshes import locate
from robospec.description.packages import PackageFinder, find_up
from robospec.diagnostics.codes import CANNOT_MEND, MENDED_MIRRORS, MIRRORED_MESH

NAME = "mirrors"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_MIRRORS
FIXES = (MIRRORED_MESH,)
WHY = "collision meshes are mirrored by a negative scale, which crashes PhysX on contact"

DERIVED_FOLDER = "derived"


def apply(document: Document, policy: str) -> None:
    base_dir = os.path.dirname(os.path.abspath(document.source.path))
    finder = PackageFinder(base_dir, document.source.packages)
    for link in document.tree.iterfind("link"):
        for mesh in link.iterfind("collision/geometry/mesh"):
            scale = _scale(mesh.get("scale"))
            if scale is None or min(scale) >= 0:
                continue
            uri = mesh.get("filename", "")
            path = _find(uri, base_dir, finder)
            data = read_mesh(path) if path is not None else None
            if path is None or data is None or data.triangle_count == 0:
                document.refuse(
                    mesh,
                    CANNOT_MEND,
                    f"mend 'mirrors' cannot mirror '{uri}' of link '{link.get('name')}': "
                    + ("robospec reads no triangles from it" if path else "no such file"),
                    "give the collision a mirrored STL or OBJ file of its own",
                )
                continue
            signs = tuple(-1.0 if s < 0 else 1.0 for s in scale)
            before = " ".join(f"{s:g}" for s in scale)
            after = " ".join(f"{abs(s):g}" for s in scale)
            mesh.set("filename", mirrored_copy(path, data, signs))
            mesh.set("scale", after)
            document.changed(
                mesh,
                f"link '{link.get('name')}' collision mesh '{os.path.basename(uri)}'",
                f'scale="{before}"',
                f'a mirrored copy, scale="{after}"',
            )


def mirrored_copy(path: str, data: MeshData, signs: tuple[float, ...]) -> str:
    """The absolute path of a binary STL of ``data`` mirrored by ``signs``, written once into
    robospec's cache folder under a name made of the source's bytes and the signs."""
    from robospec.files import cache_root

    with open(path, "rb") as handle:
        key = hashlib.sha256(handle.read() + repr(signs).encode()).hexdigest()[:32]
    stem = os.path.splitext(os.path.basename(path))[0]
    folder = cache_root() / DERIVED_FOLDER
    target = folder / f"{stem}.mirrored.{key}.stl"
    if not target.is_file():
        import numpy as np

        folder.mkdir(parents=True, exist_ok=True)
        vertices = np.frombuffer(data.coordinates, dtype=np.float64).reshape(-1, 3)
        triangles = np.frombuffer(data.indices, dtype=np.int64).reshape(-1, 3)
        corners = vertices[triangles] * np.asarray(signs)  # (M, 3, 3)
        if signs[0] * signs[1] * signs[2] < 0:  # an odd mirror turns every face inside out
            corners = corners[:, [0, 2, 1], :]
        record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", 9), ("attribute", "<u2")])
        records = np.zeros(len(corners), dtype=record)
        records["corners"] = corners.reshape(-1, 9)
        header = struct.pack("<80sI", b"robospec: mirrored copy", len(records))
        staging = target.with_name(target.name + f".{os.getpid()}.tmp")
        staging.write_bytes(header + records.tobytes())
        os.replace(staging, target)  # whole or absent: a reader never sees a part
    return str(target)


def _scale(text: str | None) -> tuple[float, float, float] | None:
    if text is None:
        return None
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        return None
    return values if len(values) == 3 else None


def _find(uri: str, base_dir: str, finder: PackageFinder) -> str | None:
    if uri.startswith("package:///"):
        return find_up(uri[len("package://") :], base_dir)
    return locate(uri, base_dir, finder)[0]


def suggest(document: Document) -> str | None:
    return "copies" if document.would_change(apply, "copies") else None
