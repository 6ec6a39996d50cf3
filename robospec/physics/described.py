"""RS532: the robot ManiSkill loaded does not weigh what the description says. RS533: its links
do not stand where the description puts them.

Every other check judges behaviour, and behaviour proves nothing about a robot that is not the
one described: an MJCF humanoid whose links ManiSkill loads at SAPIEN's minimum mass weighs
21 mg where MuJoCo compiles 51.4 kg of it, and holds its keyframe perfectly. So ``check`` first
compares the robot as loaded with its description, and judges no behaviour of one that fails:

- **masses**, link by link and in total: what SAPIEN loaded (``link.mass``) against what the
  description says. For a URDF that is each link's ``<inertial><mass>`` (a link without one is
  not compared: SAPIEN gives it the mass of its collision shapes, which the file does not
  state); for an MJCF, what MuJoCo's compiler makes of the file (``body_mass``: inertials, geom
  masses and densities), since ManiSkill's loader reads no ``<inertial>`` and weighs each body's
  collision geoms at their density. An error where the total is off by a factor of 2 or more,
  or a link that carries at least 1 % of the total is off by a factor of 10 or more (a URDF
  link whose all-zero inertia SAPIEN ignores, RS061 at validate, then weighs 1e-6 kg); a
  warning where links differ by more than 1 % (ManiSkill's MJCF loader weighing geoms where the
  file gives inertials: RS075 at validate, measured here). Links described under a gram are not
  compared (SAPIEN raises such masses).
- **link frames**, with the joints where SAPIEN loaded them (0, or the nearest limit): each
  link's pose in the root link's frame against the description's forward kinematics
  (robospec.kinematics: yourdfpy for a URDF, MuJoCo for an MJCF). An error beyond 1 mm or
  0.01 rad.

Each error names the link, at its line in the description, with both numbers.

Passing: every spec in specs/ (ManiSkill's Panda to float precision; its humanoid, the 40.84 kg
MuJoCo compiles of it).
Failing: a URDF forearm of 2 kg with an all-zero inertia and no collision shape (1e-06 kg
loaded); an MJCF whose links weigh 4 kg and 2 kg by their ``<inertial>``s, loaded as the 0.098
kg and 0.067 kg of their thin capsules (RS532 at the link).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.codes import LINK_MISPLACED, LOADED_MASS_DIFFERS
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import Sim

if TYPE_CHECKING:
    from mani_skill.utils.structs import Pose

NAME = "described"
TOTAL_FACTOR = 2.0  # loaded total / described (or its inverse): a different robot
LINK_FACTOR = 10.0  # one link's loaded / described mass (or its inverse)
HEAVY_SHARE = 0.01  # of the described total: a link that matters to the robot's dynamics
LINK_TOLERANCE = 0.01  # relative: SAPIEN keeps masses in float32, files round them
SMALLEST = 1e-3  # kg: a described mass below it is not compared (SAPIEN raises such masses)
FRAME_DISTANCE = 1e-3  # m
FRAME_ANGLE = 1e-2  # rad


@dataclass(frozen=True)
class LinkMass:
    link: str
    described: float
    loaded: float

    @property
    def ratio(self) -> float:
        """How many times off (1 when equal), whichever way."""
        low, high = sorted((self.described, self.loaded))
        return high / max(low, 1e-12)

    def words(self) -> str:
        return f"link '{self.link}': {self.described:.4g} kg described, {self.loaded:.4g} kg loaded"


def check(run: CheckRun) -> list[Finding]:
    if not run.modes:
        return []
    sim = run.sim(run.modes[0])
    sim.start(None)  # the joints where SAPIEN built them, inside their limits
    loaded_masses = {name: float(link.mass[0]) for name, link in sim.robot.links_map.items()}
    findings = []
    described = described_masses(run)
    if described:
        findings.append(_masses(run, described, loaded_masses))
    frames = _frames(run, sim)
    if frames is not None:
        findings.append(frames)
    return findings


def failed(findings: list[Finding]) -> bool:
    """Whether the robot loaded is not the one described: no behaviour is judged then."""
    return any(f.check == NAME and f.failed for f in findings)


# -- masses ---------------------------------------------------------------------------------------


def described_masses(run: CheckRun) -> dict[str, float]:
    """Link -> the mass the description says it has (kg), for the links it says one of."""
    ref = run.robot.description
    try:
        text = ref.read_bytes()
    except OSError:
        return {}
    if run.context.description.kind == "mjcf":
        return _mujoco_masses(run, text, str(ref.absolute))
    from lxml import etree

    from robospec.description.inertia import stated_masses

    try:
        root = etree.fromstring(text, etree.XMLParser(resolve_entities=False, no_network=True))
    except etree.XMLSyntaxError:
        return {}
    return stated_masses(root)


def _mujoco_masses(run: CheckRun, text: bytes, path: str) -> dict[str, float]:
    """Each robot body's mass as MuJoCo compiles it, by the link ManiSkill names after it."""
    import mujoco

    from robospec.kinematics.mjcf_poses import compiled_model

    try:
        model = compiled_model(text, path)
    except ValueError:
        return {}
    links = {link.name for link in run.context.description.links}
    found = {}
    for body in range(1, model.nbody):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body)
        if name in links:
            found[name] = float(model.body_mass[body])
    return found


def _masses(run: CheckRun, described: dict[str, float], loaded: dict[str, float]) -> Finding:
    rows = [
        LinkMass(name, mass, loaded[name])
        for name, mass in described.items()
        if name in loaded and mass >= SMALLEST
    ]
    total_described = sum(row.described for row in rows)
    total_loaded = sum(row.loaded for row in rows)
    found = metrics(described_kg=total_described, loaded_kg=total_loaded, links=len(rows))
    summary = f"{total_loaded:.4g} kg loaded, {total_described:.4g} kg described"
    if not rows:
        return Finding(NAME, None, "mass", Status.SKIP, "no link of a gram or more", found)
    total = LinkMass("", total_described, total_loaded)
    heavy = [
        row
        for row in rows
        if row.described >= HEAVY_SHARE * total_described and row.ratio >= LINK_FACTOR
    ]
    off = sorted(
        (row for row in rows if row.ratio > 1 + LINK_TOLERANCE), key=lambda row: -row.ratio
    )
    diagnostics: list[Diagnostic] = []
    if total.ratio >= TOTAL_FACTOR or heavy:
        # at the link most off of those that matter, else (the total off) the heaviest
        worst = (
            max(heavy, key=lambda row: row.ratio)
            if heavy
            else max(rows, key=lambda row: row.described)
        )
        diagnostics.append(
            error(
                _at(run, worst.link),
                LOADED_MASS_DIFFERS,
                f"the robot ManiSkill loaded is not the one described: {total_loaded:.4g} kg "
                f"loaded where the description says {total_described:.4g} kg; "
                f"{_listed([worst, *(r for r in off if r is not worst)])}",
                _mass_hint(run),
            )
        )
    elif off:
        diagnostics.append(
            warning(
                _at(run, off[0].link),
                LOADED_MASS_DIFFERS,
                f"ManiSkill loaded {len(off)} link(s) at other masses than the description "
                f"says ({total_loaded:.4g} kg in all, {total_described:.4g} kg described): "
                f"{_listed(off)}",
                _mass_hint(run),
            )
        )
    status = Status.FAIL if any(d.is_error for d in diagnostics) else Status.PASS
    return Finding(NAME, None, "mass", status, summary, found, tuple(diagnostics))


def _listed(rows: list[LinkMass], shown: int = 4) -> str:
    text = "; ".join(row.words() for row in rows[:shown])
    return text + (f"; and {len(rows) - shown} more" if len(rows) > shown else "")


def _mass_hint(run: CheckRun) -> str:
    if run.context.description.kind == "mjcf":
        return (
            "ManiSkill's MJCF loader weighs each body's collision geoms (contype not 0) at "
            "their density and reads no <inertial> or geom mass= (RS075): give the geoms that "
            "carry the mass a collision shape, or their density"
        )
    return (
        "SAPIEN takes a link's <inertial> only with a positive mass and inertia (RS061), else "
        "the mass of its collision shapes at 1000 kg/m³, or 1e-6 kg without any: give the "
        "link a valid <inertial>"
    )


# -- frames ---------------------------------------------------------------------------------------


def _frames(run: CheckRun, sim: Sim) -> Finding | None:
    from robospec.kinematics.forward import kinematics_of

    ref = run.robot.description
    try:
        text = ref.read_bytes()
    except OSError:
        return None
    model = kinematics_of(run.context.description, text, str(ref.absolute))
    if model is None:
        return None
    qpos = sim.qpos()[0]
    placed = model.at({name: float(v) for name, v in zip(sim.joint_names, qpos, strict=True)})
    root = _matrix(sim.robot.root.pose)
    to_root = np.linalg.inv(root)
    worst: tuple[float, float, str] | None = None
    compared = 0
    for name, link in sim.robot.links_map.items():
        meant = placed.links.get(name)
        if meant is None:
            continue
        compared += 1
        pose = to_root @ _matrix(link.pose)
        distance = float(np.linalg.norm(pose[:3, 3] - meant[:3, 3]))
        turn = _angle(pose[:3, :3], meant[:3, :3])
        if worst is None or (distance, turn) > (worst[0], worst[1]):
            worst = (distance, turn, name)
    if worst is None:
        return None
    distance, turn, name = worst
    found = metrics(links=compared, worst_m=distance, worst_rad=turn)
    summary = f"{compared} links, worst '{name}' {distance * 1000:.3g} mm, {turn:.3g} rad off"
    if distance <= FRAME_DISTANCE and turn <= FRAME_ANGLE:
        return Finding(NAME, None, "frames", Status.PASS, summary, found)
    diagnostic = error(
        _at(run, name),
        LINK_MISPLACED,
        f"the robot ManiSkill loaded is not the one described: link '{name}' stands "
        f"{distance * 1000:.4g} mm and {math.degrees(turn):.3g}° away from where the "
        "description's forward kinematics puts it, with the joints where SAPIEN loaded them",
        "ManiSkill's loader reads this link's frame otherwise than the description's own "
        "format does (an MJCF orientation: RS080); write the frame in a form both read alike",
    )
    return Finding(NAME, None, "frames", Status.FAIL, summary, found, (diagnostic,))


def _matrix(pose: Pose) -> np.ndarray:
    """The 4x4 of a ManiSkill pose (its first environment's)."""
    from robospec.kinematics.placement import pose_matrix

    p = pose.p[0].cpu().numpy().astype(np.float64)
    q = pose.q[0].cpu().numpy().astype(np.float64)
    return pose_matrix(tuple(p), tuple(q))


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """The angle of the rotation between two rotation matrices."""
    cosine = (np.trace(a.T @ b) - 1.0) / 2.0
    return float(math.acos(max(-1.0, min(1.0, cosine))))


def _at(run: CheckRun, link: str) -> Location:
    line = next((k.line for k in run.context.description.links if k.name == link), None)
    return run.context.at_description(line) if line is not None else run.at(("description",))
