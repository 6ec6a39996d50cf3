"""Which loader ``robospec new`` writes for an MJCF, and why: MuJoCo's compiled model
(``description: {mjcf: FILE, loader: mujoco}``, robospec.derive.mujoco_urdf) wherever MuJoCo
compiles the file, with a comment that says what ManiSkill's own MJCF loader would get wrong
for this file — the total mass it would simulate against MuJoCo's, the bodies past its 32, the
ball joints it cannot load, the joints without an axis it turns about x, the bodies of visual
geoms it would give no mass.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.description import RobotDescription
from robospec.diagnostics.codes import MENDED_AXES, MJCF_MASSES

if TYPE_CHECKING:
    from robospec.resolve.description_loading import Loaded

# the mends that change what MuJoCo itself reads or accepts, which the compiled model takes
# where the file needs them: the unit of its angles, names defined twice (MuJoCo refuses them);
# the others mend what ManiSkill's MJCF loader reads otherwise than MuJoCo
MUJOCO_MENDS = ("angles", "asset_names")
MAX_BODIES = 32  # ManiSkill's MJCF loader gives body k bit k of collision group 2
_MASS_TOLERANCE = 0.01  # a total within 1% of MuJoCo's is not worth a word


def why_mujoco(mjcf: bytes, path: Path, maniskill: frozenset[str]) -> str:
    """What ManiSkill's MJCF loader would get wrong for the MJCF ``mjcf`` (read from ``path``),
    in a line for the comment beside ``loader: mujoco``; ``maniskill``: the codes robospec
    reports of the file read as that loader reads it."""
    import mujoco

    from robospec.authoring.new.joint_loads import mjcf_inertials
    from robospec.derive.mjcf_files import compiled_model
    from robospec.kinematics.mjcf_model import read_mjcf_model

    model = compiled_model(mjcf, str(path))
    bodies = range(1, int(model.nbody))
    wrong = []
    parsed = read_mjcf_model(mjcf, str(path))
    meshes = any(int(t) == int(mujoco.mjtGeom.mjGEOM_MESH) for t in model.geom_type)
    ours = float(sum(model.body_mass[b] for b in bodies))
    if parsed is not None and not meshes:  # (robospec weighs no mesh as the loader does)
        theirs = sum(inertial.mass for inertial in mjcf_inertials(parsed).values())
        if ours > 0 and abs(theirs - ours) > _MASS_TOLERANCE * ours:
            wrong.append(f"weigh it {theirs:.3g} kg from its geoms (MuJoCo: {ours:.3g} kg)")
    elif MJCF_MASSES in maniskill:
        wrong.append(
            f"weigh its links by their geoms, not the file's masses (MuJoCo: {ours:.3g} kg)"
        )
    if MENDED_AXES in maniskill:  # the axes mend wrote MuJoCo's axis on joints that write none
        wrong.append("turn its joints that write no axis about x, where MuJoCo turns them about z")
    if len(bodies) > MAX_BODIES:
        wrong.append(f"stop at {MAX_BODIES} of its {len(bodies)} bodies")
    balls = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or f"joint{j}"
        for j in range(int(model.njnt))
        if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_BALL)
    ]
    if balls:
        wrong.append(
            f"not load its ball joints ({', '.join(balls[:3])}{'...' if balls[3:] else ''})"
        )
    ghosts = sum(
        1
        for b in bodies
        if int(model.body_geomnum[b]) > 0
        and not any(
            int(model.geom_contype[g]) or int(model.geom_conaffinity[g])
            for g in range(
                int(model.body_geomadr[b]), int(model.body_geomadr[b] + model.body_geomnum[b])
            )
        )
    )
    if ghosts:
        bodies_of = "body" if ghosts == 1 else "bodies"
        wrong.append(f"give its {ghosts} {bodies_of} of visual geoms only no mass")
    if not wrong:
        return "MuJoCo compiles the file: the robot has MuJoCo's masses, inertias and frames"
    return "MuJoCo's compiled model: ManiSkill's MJCF loader would " + "; ".join(wrong)


@dataclass(frozen=True)
class ManiSkillReading:
    """An MJCF file as ManiSkill's own loader would read it, with the mends it needs: the
    loaded description (None: it cannot be read so) and the codes robospec says of it."""

    loaded: Loaded | None
    codes: frozenset[str]


def maniskill_reading(mjcf_path: str) -> ManiSkillReading:
    from robospec.diagnostics import Location
    from robospec.resolve.description_loading import DescriptionEntry, Loaded, Reader, load

    reader = Reader(Path(""), Path(""), lambda _: Location(mjcf_path), entry_is_file=True)
    loaded = load(reader, DescriptionEntry(mjcf_path, "mjcf", mends=None))
    return ManiSkillReading(
        loaded if isinstance(loaded, Loaded) else None,
        frozenset(d.code for d in reader.diagnostics),
    )


def with_file_facts(
    description: RobotDescription, reading: ManiSkillReading
) -> tuple[RobotDescription, frozenset[str]]:
    """``description`` (the compiled URDF's) with the joint couplings, closed loops, mocap
    welds and collision filters robospec reads from the MJCF file as written (what ``new``
    turns into mimic controllers, ``loops``, drives and ``never_collide``), where it reads
    them — the file read as ManiSkill's loader would, with the mends it needs (a file it cannot
    read gives none) — and the codes of what robospec says of that reading."""
    loaded, codes = reading.loaded, reading.codes
    if loaded is None:
        return description, codes
    written = loaded.description
    links = set(description.link_names)
    joints = {j.name for j in description.joints}
    carried = {"connect"}  # the compiled model's, in the description (derive.mujoco_urdf)
    facts: dict[str, Any] = {
        "couplings": tuple(c for c in written.couplings if {c.follower, c.mimic.joint} <= joints),
        # MuJoCo's compiled <connect>s (the description's), and what it does not carry as
        # the file states it (<weld>)
        "closures": description.closures
        + tuple(
            c for c in written.closures if {c.first, c.second} <= links and c.kind not in carried
        ),
        "filtered_pairs": tuple(p for p in written.filtered_pairs if set(p) <= links),
        "mocap_welds": tuple(b for b in written.mocap_welds if b in links),
    }
    return dataclasses.replace(description, **facts), codes


def mujoco_mends(reading: ManiSkillReading) -> dict[str, Any]:
    """The mends of :data:`MUJOCO_MENDS` the MJCF ``reading`` read needs (as robospec suggests
    them for the file), for MuJoCo to compile what its author meant."""
    if reading.loaded is None:
        return {}
    return {k: v for k, v in reading.loaded.prepared.mends.items() if k in MUJOCO_MENDS}
