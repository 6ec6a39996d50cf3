"""Every mend class, in the order they run: text first (the file must become XML), then the
tree, each before the ones that read what it mends (substitutions before the package URIs they
write and the numbers whose separators are mended, those before the mirrored scales and the
shapes' inertias that read them, masses before the inertias scaled with them)."""

from __future__ import annotations

from typing import cast

import robospec.derive.angles as angles
import robospec.derive.asset_names as asset_names
import robospec.derive.axes as axes
import robospec.derive.bodies as bodies
import robospec.derive.contype as contype
import robospec.derive.freejoint as freejoint
import robospec.derive.geom_meshes as geom_meshes
import robospec.derive.geoms as geoms
import robospec.derive.includes as includes
import robospec.derive.inertia as inertia
import robospec.derive.integers as integers
import robospec.derive.limits as limits
import robospec.derive.mass as mass
import robospec.derive.mesh_names as mesh_names
import robospec.derive.mesh_scale as mesh_scale
import robospec.derive.mimic as mimic
import robospec.derive.mirrors as mirrors
import robospec.derive.namespaces as namespaces
import robospec.derive.orientations as orientations
import robospec.derive.packages as packages
import robospec.derive.planar_base as planar_base
import robospec.derive.separators as separators
import robospec.derive.spherical as spherical
import robospec.derive.substitutions as substitutions
import robospec.derive.textures as textures
import robospec.derive.transmissions as transmissions
import robospec.derive.xml_repair as xml_repair
from robospec.derive.mend import MendClass

MENDS: tuple[MendClass, ...] = cast(
    "tuple[MendClass, ...]",
    (
        xml_repair,
        namespaces,
        includes,
        geoms,
        mesh_names,
        asset_names,
        angles,
        geom_meshes,
        mesh_scale,
        axes,
        contype,
        freejoint,
        orientations,
        bodies,
        substitutions,
        separators,
        packages,
        mirrors,
        textures,
        transmissions,
        mass,
        inertia,
        integers,
        limits,
        spherical,
        mimic,
    ),
)


# Transformations a spec asks for in a section of its own (not ``description.mend``), each a
# module of the same interface, run in this order among the mends: the planar base after the
# mends that make the file loadable, before those that read joint types (it welds wheels'
# ball joints, which `spherical` would otherwise turn into hinges)
SECTIONS: dict[str, MendClass] = {"mobile_base": cast("MendClass", planar_base)}
ORDER: tuple[MendClass, ...] = (
    *MENDS[: MENDS.index(cast("MendClass", limits)) + 1],
    cast("MendClass", planar_base),
    *MENDS[MENDS.index(cast("MendClass", limits)) + 1 :],
)


def mend_class(name: str) -> MendClass | None:
    return next((m for m in MENDS if m.NAME == name), None)
