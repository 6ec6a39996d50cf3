"""``--reference mujoco``: the reference trajectory made by MuJoCo itself, from the robot's MJCF
and its position actuators, so that a robot ported from MuJoCo can be fitted to behave as it
did there.

The same steps the fit replays: each joint a position actuator drives gets a square wave of a
small step about where it starts (:mod:`robospec.tune.reference.excitation`) as its actuator's
``ctrl``; MuJoCo integrates with the model's own timestep and options, and the joints are
sampled at ManiSkill's physics rate. Treated as ManiSkill treats the robot: a free root is held
where it starts (``check`` holds a floating robot by its root too), and where the control mode
compensates gravity (``balance_passive_force``) MuJoCo runs without gravity.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from robospec.physics.mujoco_servos import drive, place, position_actuators
from robospec.tune.reference.excitation import square_waves
from robospec.tune.reference.trajectory import Reference

SOURCE = "mujoco"


@dataclass
class Made:
    reference: Reference | None
    actuated: dict[str, tuple[float, float]]  # joint -> MuJoCo's (kp, kv)
    notes: list[str] = field(default_factory=list)


def make_reference(
    path: str,
    joints: Sequence[str],
    start: Mapping[str, float],
    limits: np.ndarray,
    prismatic: np.ndarray,
    sample_dt: float,
    gravity: bool,
) -> Made:
    """Simulate ``joints`` (those of them a position actuator drives) in MuJoCo from
    ``start`` (joint -> position; others at the model's qpos0)."""
    import mujoco

    from robospec.derive.mjcf_files import compiled_model

    # robospec's one compile of an MJCF (the same model every command reads; no
    # MUJOCO_LOG.TXT written into the working folder for a compiler warning)
    with open(path, "rb") as file:
        model = compiled_model(file.read(), path)
    data = mujoco.MjData(model)
    servos = position_actuators(model)
    notes: list[str] = []
    used = [j for j in joints if j in servos and abs(servos[j][3] - 1.0) < 1e-12]
    geared = [j for j in joints if j in servos and j not in used]
    if geared:
        notes.append(
            "not fitted, their MuJoCo actuators have a gear other than 1: " + ", ".join(geared)
        )
    if not used:
        return Made(None, {}, notes)
    if not gravity:
        model.opt.gravity[:] = 0.0
    place(model, data, start)
    index = [list(joints).index(j) for j in used]
    t, targets = square_waves(
        np.array([start[j] for j in used]), limits[index], prismatic[index], sample_dt
    )
    substeps = max(round(sample_dt / model.opt.timestep), 1)
    if abs(substeps * model.opt.timestep - sample_dt) > 1e-9:
        notes.append(
            f"MuJoCo's timestep {model.opt.timestep:g} s does not divide ManiSkill's "
            f"{sample_dt:g} s: MuJoCo was sampled every {substeps * model.opt.timestep:g} s"
        )
    addresses = [
        int(model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, j)]) for j in used
    ]
    actuators = [servos[j][0] for j in used]
    qpos = drive(model, data, actuators, addresses, targets, substeps)
    t = t[: qpos.shape[0]] * (substeps * model.opt.timestep / sample_dt)
    reference = Reference(t, targets, qpos, tuple(used), SOURCE)
    return Made(reference, {j: (servos[j][1], servos[j][2]) for j in used}, notes)
