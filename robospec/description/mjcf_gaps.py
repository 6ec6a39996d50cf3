"""Everything ManiSkill 3.0.1's MJCF loader drops from the robot or reads differently than
MuJoCo, each reported once per kind at the MJCF element it concerns (RS070-RS085, RS094,
RS095).

Where the loaded robot is certainly wrong (a mesh ten times too large, a frame turned, a moving
link without mass) or the file cannot be loaded at all, the report is an error; otherwise a
warning that says what the robot will lack. Where the mend is mechanical the hint writes it
out (a mimic map, a never_collide list, a quat=). docs/loaders.md lists them all.
"""

from __future__ import annotations

from robospec.description.mjcf_axes import unaxed
from robospec.description.mjcf_constraints import (
    actuators,
    contacts,
    equalities,
    robot_names,
    tendons,
)
from robospec.description.mjcf_geoms import (
    collision_filters,
    geom_types,
    masses,
    massless_links,
    mesh_files,
    mesh_scale,
    orientations,
    visual_groups,
)
from robospec.description.mjcf_loaded import LoadedMjcf
from robospec.description.mjcf_structure import (
    collision_bits,
    joint_attributes,
    repeated_assets,
    skipped_wrapper,
)
from robospec.diagnostics import Diagnostic


def loader_gaps(loaded: LoadedMjcf) -> list[Diagnostic]:
    robot = robot_names(loaded)
    return [
        *equalities(loaded, robot),  # RS070
        *tendons(loaded, robot),  # RS071
        *contacts(loaded, robot),  # RS072
        *collision_filters(loaded),  # RS073
        *mesh_scale(loaded),  # RS074
        *masses(loaded),  # RS075
        *massless_links(loaded),  # RS076
        *actuators(loaded, robot),  # RS077
        *visual_groups(loaded),  # RS078
        *geom_types(loaded),  # RS079
        *orientations(loaded),  # RS080
        *collision_bits(loaded),  # RS081
        *skipped_wrapper(loaded),  # RS083
        *joint_attributes(loaded),  # RS084
        *mesh_files(loaded),  # RS085, RS056
        *repeated_assets(loaded),  # RS094
        *unaxed(loaded),  # RS095
    ]
