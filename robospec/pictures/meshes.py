"""A mesh file as MuJoCo can draw it: triangle sets, each with the file's own colour.

ManiSkill's robots ship their visuals as .glb, .dae, .obj, .stl and .ply; MuJoCo reads STL and
OBJ only, and takes no per-vertex colours. trimesh reads them all (pycollada for .dae), with
each node's transform applied, so a part here sits in the file's own frame, as SAPIEN (assimp)
places it. A part's colour is its material's (a glTF base colour, an OBJ/DAE diffuse colour),
times the mean of its texture when it has one; a mesh coloured per face or per vertex (a PLY)
is split into its few main colours.

Reading a mesh costs far more than drawing it, so each file read is kept in robospec's cache
folder, keyed by its bytes (and an OBJ's material files): ``meshes/<sha256>.npz``.
"""

from __future__ import annotations

import hashlib
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robospec.files import cache_root

CACHE_VERSION = b"robospec-mesh-4"
# a part with more triangles is simplified to about this many (fast-simplification's quadric
# decimation): a picture of 320x240 pixels shows no more, and drawing on the CPU pays for each
MAX_FACES = 5_000
MAX_COLOURS = 6  # a mesh coloured per face keeps this many colours (the rest join the nearest)
_MTLLIB = re.compile(rb"^\s*mtllib\s+(.+?)\s*$", re.MULTILINE)


@dataclass(frozen=True)
class MeshPart:
    vertices: np.ndarray  # (n, 3) float32, in the file's frame
    faces: np.ndarray  # (m, 3) int32
    rgba: tuple[float, float, float, float] | None  # None: the file gives no colour


class MeshError(Exception):
    """The mesh cannot be read; the message says why."""


def load_mesh(path: str) -> tuple[MeshPart, ...]:
    """The parts of the mesh at ``path`` (from the cache when it was read before)."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise MeshError(f"cannot be opened ({exc.strerror or exc})") from exc
    key = _key(path, data)
    cached = cache_root() / "meshes" / f"{key}.npz"
    parts = _read_cached(cached)
    if parts is None:
        parts = _read_mesh(path)
        _write_cached(cached, parts)
    return parts


def _key(path: str, data: bytes) -> str:
    digest = hashlib.sha256(CACHE_VERSION)
    digest.update(Path(path).suffix.lower().encode())
    digest.update(data)
    if path.lower().endswith(".obj"):  # its colours are in the material files it names
        for name in _MTLLIB.findall(data[: 1 << 16]):
            material = Path(path).parent / name.decode("utf-8", "replace")
            try:
                digest.update(material.read_bytes())
            except OSError:
                digest.update(b"missing")
    return digest.hexdigest()


def _read_cached(path: Path) -> tuple[MeshPart, ...] | None:
    try:
        with np.load(path) as stored:
            count = int(stored["count"])
            return tuple(
                MeshPart(
                    stored[f"v{i}"],
                    stored[f"f{i}"],
                    None if np.isnan(stored[f"c{i}"]).any() else tuple(stored[f"c{i}"].tolist()),
                )
                for i in range(count)
            )
    except (OSError, KeyError, ValueError):
        return None


def _write_cached(path: Path, parts: tuple[MeshPart, ...]) -> None:
    arrays: dict[str, Any] = {"count": np.array(len(parts))}
    for i, part in enumerate(parts):
        arrays[f"v{i}"] = part.vertices
        arrays[f"f{i}"] = part.faces
        arrays[f"c{i}"] = np.array(part.rgba if part.rgba else [np.nan] * 4, dtype=np.float32)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, staging = tempfile.mkstemp(prefix=".robospec-", suffix=".npz", dir=path.parent)
        with os.fdopen(handle, "wb") as stream:
            np.savez(stream, **arrays)
        os.replace(staging, path)
    except OSError:
        return  # a cache that cannot be written only costs time


def _read_mesh(path: str) -> tuple[MeshPart, ...]:
    import trimesh

    try:
        scene = trimesh.load(path, force="scene")
    except Exception as exc:  # trimesh raises whatever its readers raise
        raise MeshError(f"trimesh cannot read it ({type(exc).__name__}: {exc})") from exc
    assert isinstance(scene, trimesh.Scene)  # force="scene"
    parts: list[MeshPart] = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        geometry = scene.geometry.get(name)
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue  # points and lines draw nothing
        vertices = np.asarray(geometry.vertices, dtype=np.float64)
        vertices = vertices @ transform[:3, :3].T + transform[:3, 3]
        faces = np.asarray(geometry.faces, dtype=np.int64)
        parts.extend(_coloured_parts(vertices, faces, geometry.visual))
    if not parts:
        raise MeshError("it holds no triangles")
    return tuple(parts)


def _coloured_parts(vertices: np.ndarray, faces: np.ndarray, visual: Any) -> list[MeshPart]:
    kind = getattr(visual, "kind", None)
    if kind == "texture":
        return [_part(vertices, faces, _material_colour(visual.material))]
    if kind in ("face", "vertex") and getattr(visual, "defined", False):
        colours = np.asarray(visual.face_colors, dtype=np.float64)[:, :4] / 255.0
        return _split_by_colour(vertices, faces, colours)
    return [_part(vertices, faces, None)]


def _material_colour(material: Any) -> tuple[float, float, float, float] | None:
    factor = getattr(material, "baseColorFactor", None)
    if factor is None:
        factor = getattr(material, "diffuse", None)
    colour = np.asarray(factor, dtype=np.float64)[:4] / 255.0 if factor is not None else np.ones(4)
    if colour.shape != (4,):
        colour = np.ones(4)
    image = getattr(material, "baseColorTexture", None) or getattr(material, "image", None)
    if image is not None:
        try:
            pixels = np.asarray(image.convert("RGBA").resize((16, 16)), dtype=np.float64)
            colour = colour * pixels.reshape(-1, 4).mean(axis=0) / 255.0
        except Exception:  # an unreadable texture leaves the base colour
            pass
    if factor is None and image is None:
        return None
    return tuple(float(c) for c in colour)  # type: ignore[return-value]


def _split_by_colour(
    vertices: np.ndarray, faces: np.ndarray, colours: np.ndarray
) -> list[MeshPart]:
    # quantized so that near colours count as one; the rarest join their nearest main colour
    quantized = np.round(colours * 15.0)
    unique, inverse, counts = np.unique(quantized, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    main = np.argsort(-counts)[:MAX_COLOURS]
    nearest = np.argmin(((unique[:, None, :] - unique[None, main, :]) ** 2).sum(axis=2), axis=1)
    group = nearest[inverse]
    parts = []
    for index in range(len(main)):
        chosen = group == index
        if chosen.any():
            mean = colours[chosen].mean(axis=0)
            parts.append(_part(vertices, faces[chosen], tuple(float(c) for c in mean)))
    return parts


def _part(vertices: np.ndarray, faces: np.ndarray, rgba: tuple[float, ...] | None) -> MeshPart:
    """Only the vertices ``faces`` use, renumbered; simplified past :data:`MAX_FACES`."""
    # vertices at one position are one (files split them along seams of normals or UVs)
    points, renumbered = np.unique(
        vertices[faces.reshape(-1)].astype(np.float32), axis=0, return_inverse=True
    )
    triangles = renumbered.reshape(-1, 3).astype(np.int32)
    # triangles that lost an edge are dropped: MuJoCo refuses them
    triangles = triangles[
        (triangles[:, 0] != triangles[:, 1])
        & (triangles[:, 1] != triangles[:, 2])
        & (triangles[:, 0] != triangles[:, 2])
    ]
    if len(triangles) > MAX_FACES:
        import fast_simplification

        points, triangles = fast_simplification.simplify(points, triangles, target_count=MAX_FACES)
    return MeshPart(
        np.asarray(points, dtype=np.float32),
        np.asarray(triangles, dtype=np.int32),
        rgba,  # type: ignore[arg-type]
    )
