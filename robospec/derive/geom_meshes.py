"""Mend class ``geom_meshes: defaults`` (RS723, MJCF): meshes a default class names that
ManiSkill's loader does not give the geom.

MuJoCo names a geom's mesh from its class as it does any attribute; ManiSkill's loader reads
the classes by rules of its own (robospec.description.mjcf_class_meshes), and a model that
spells its root class ``<default class="main">`` gives every geom that names no class no mesh
there: ``_build_geom`` raises ``KeyError: None`` (RS085), or loads a unit sphere in the mesh's
place. Each such geom gets ``mesh=`` written on it, the name MuJoCo reads: MuJoCo reads the
model as before, and ManiSkill reads the mesh.
"""

from __future__ import annotations

from typing import Literal

from robospec.derive.document import Document
from robospec.derive.mjcf_tree import classes, whole
from robospec.description.mjcf_class_meshes import lost_meshes
from robospec.description.mjcf_loaded import loader_classes
from robospec.diagnostics.codes import MENDED_GEOM_MESHES, MJCF_MESH_UNRESOLVED

NAME = "geom_meshes"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_GEOM_MESHES
FIXES = (MJCF_MESH_UNRESOLVED,)
WHY = "geoms take their mesh from a default class ManiSkill's loader does not apply to them"


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    worldbody = root.find("worldbody")
    if worldbody is None:
        return  # no robot: the description's parse says so
    loaded, _lines = loader_classes(child for child in root if child.tag == "default")
    for lost in list(lost_meshes(worldbody, loaded, classes(root, document.source.path))):
        geom = lost.geom
        body = geom.getparent()
        owner = body.get("name") if body is not None and body.tag == "body" else None
        subject = f"geom '{geom.get('name')}'" if geom.get("name") else "<geom>"
        read = "no mesh" if lost.loaded_mesh is None else f"mesh '{lost.loaded_mesh}'"
        document.changed(
            geom,
            subject + (f" of body '{owner}'" if owner else ""),
            f"mesh '{lost.mesh}' from class '{lost.holder}' ({read} in ManiSkill)",
            f'mesh="{lost.mesh}"',
        )
        geom.set("mesh", lost.mesh)


def suggest(document: Document) -> str | None:
    return "defaults" if document.would_change(apply, "defaults") else None
