"""Mend class ``mesh_names: mujoco`` (RS715, MJCF): meshes ManiSkill's loader names otherwise.

MuJoCo names a ``<mesh>`` without ``name=`` after its file, without folders or extension
(``file="meshes/link1.stl"`` is ``link1``), and geoms say ``mesh="link1"``. ManiSkill's loader
keeps the folders (``meshes/link1``) and fails on the first such geom with a ``KeyError``
(RS085; exporters that write one folder per robot name every mesh so). Each unnamed mesh is
given the name MuJoCo gives it: nothing MuJoCo reads changes.
"""

from __future__ import annotations

import os
from typing import Literal

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import assets, mujoco_mesh_name, whole
from robospec.diagnostics.codes import MENDED_MESH_NAMES, MJCF_MESH_UNRESOLVED

NAME = "mesh_names"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_MESH_NAMES
FIXES = (MJCF_MESH_UNRESOLVED,)
WHY = "unnamed meshes in folders: ManiSkill's loader names them with the folder, MuJoCo without"


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    for mesh in assets(root, "mesh"):
        file = mesh.get("file")
        if mesh.get("name") or not file:
            continue
        loader_name = os.path.splitext(file)[0]
        name = mujoco_mesh_name(mesh)
        if name == loader_name:
            continue
        mesh.set("name", name)
        document.changed(
            mesh,
            f'<mesh file="{file}">',
            f"unnamed (ManiSkill: '{loader_name}', MuJoCo: '{name}')",
            f'name="{name}"',
        )


def suggest(document: Document) -> str | None:
    return "mujoco" if document.would_change(apply, "mujoco") else None
