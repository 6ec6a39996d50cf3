"""Geoms whose mesh a default class names, which ManiSkill's MJCF loader reads otherwise.

MuJoCo gives a geom the attributes its class holds (its own ``class``, else the nearest
``childclass`` above it, else the root class ``main``), a class inheriting from the one it is
nested in. ManiSkill's loader keeps default tables of its own (robospec.description.mjcf_loaded
mirrors them) that differ where it matters for a mesh: a top-level ``<default class="main">``,
MuJoCo's spelling of the root class, is a class like any other there, applied to no geom that
does not name it. A geom that takes ``type="mesh"`` and its ``mesh`` from such a class is then
a mesh without a name in ``_build_geom`` (``KeyError: None``: nothing loads), or a unit sphere
where the mesh stood. Both readings are compared here, for validate (RS085) and for the mend
that writes the mesh on the geom (:mod:`robospec.derive.geom_meshes`).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from lxml import etree

from robospec.description.mjcf_loaded import Defaults, loader_elements
from robospec.description.mjcf_mujoco import Table, childclass, effective


@dataclass(frozen=True)
class LostMesh:
    """A geom MuJoCo reads as mesh ``mesh`` (given by class ``holder``) that ManiSkill's
    loader reads as ``loaded_type`` with ``loaded_mesh`` (None: no mesh name)."""

    geom: etree._Element
    mesh: str
    holder: str
    loaded_type: str
    loaded_mesh: str | None

    @property
    def fails(self) -> bool:
        """Whether the loader raises on it (a mesh without a name: ``KeyError: None``)."""
        return self.loaded_type == "mesh" and self.loaded_mesh is None


def lost_meshes(
    worldbody: etree._Element,
    loader_classes: Mapping[str, Defaults],
    mujoco_classes: dict[str, Table],
) -> Iterator[LostMesh]:
    """Every geom the loader parses whose mesh, named by a default class in MuJoCo's
    reading, the loader's reading does not give it."""
    for element, attributes in loader_elements(worldbody, loader_classes):
        if element.tag != "geom" or "mesh" in element.attrib:
            continue  # a mesh the geom names itself is read alike (RS085 checks the name)
        mujoco = effective(mujoco_classes, element)
        mesh = mujoco.get("mesh")
        if mesh is None or mujoco.get("type", "sphere") != "mesh":
            continue
        loaded_mesh = attributes.get("mesh")
        if loaded_mesh == mesh:
            continue
        loaded_type = "mesh" if loaded_mesh is not None else attributes.get("type", "sphere")
        yield LostMesh(element, mesh, childclass(element), loaded_type, loaded_mesh)
