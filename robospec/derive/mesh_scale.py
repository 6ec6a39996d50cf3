"""Mend class ``mesh_scale: defaults`` (RS716, MJCF): mesh scales set in ``<default>``.

MuJoCo gives a ``<mesh>`` the ``scale`` of its class's defaults (Menagerie's models write
``<default><mesh scale="0.001 0.001 0.001"/></default>`` for meshes drawn in millimetres);
ManiSkill's loader reads a mesh's scale only from the element itself, so such meshes load at
the size the file is drawn in: a thousand times too large, collision shapes and masses with
them (RS074). The scale MuJoCo uses is written on each mesh.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import assets, classes, effective, mujoco_mesh_name, whole
from robospec.diagnostics.codes import MENDED_MESH_SCALES, MJCF_MESH_SCALE

NAME = "mesh_scale"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_MESH_SCALES
FIXES = (MJCF_MESH_SCALE,)
WHY = "mesh scales come from <default>, which ManiSkill's loader does not read for meshes"


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    table = classes(root, document.source.path)
    for mesh in assets(root, "mesh"):
        if "scale" in mesh.attrib:
            continue
        scale = effective(table, mesh).get("scale")
        if scale is None or _unit(scale):
            continue
        mesh.set("scale", scale)
        document.changed(
            mesh,
            f"mesh '{mujoco_mesh_name(mesh)}'",
            f'no scale (ManiSkill: 1 1 1; its <default>\'s: "{scale}")',
            f'scale="{scale}"',
        )


def _unit(scale: str) -> bool:
    try:
        return [float(v) for v in scale.split()] in ([1.0, 1.0, 1.0], [1.0])
    except ValueError:
        return False  # written as it is: the model's parse says what is wrong with it


def suggest(document: Document) -> str | None:
    return "defaults" if document.would_change(apply, "defaults") else None
