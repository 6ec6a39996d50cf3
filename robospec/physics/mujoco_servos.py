"""MuJoCo's position servos of an MJCF, and the one loop that steps them: what ``check`` holds a
keyframe with (robospec.physics.mujoco_hold) and what ``tune --reference mujoco`` records
(robospec.tune.reference.mujoco_reference)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np


def position_actuators(model: object) -> dict[str, tuple[int, float, float, float]]:
    """Joint name -> (actuator id, kp, kv, gear) for MuJoCo's position servos on one joint:
    fixed gain kp and affine bias ``(0, -kp, -kv)``."""
    import mujoco

    found: dict[str, tuple[int, float, float, float]] = {}
    m: mujoco.MjModel = model
    for a in range(m.nu):
        if m.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
            continue
        kp = float(m.actuator_gainprm[a, 0])
        bias = m.actuator_biasprm[a]
        if (
            m.actuator_gaintype[a] != mujoco.mjtGain.mjGAIN_FIXED
            or m.actuator_biastype[a] != mujoco.mjtBias.mjBIAS_AFFINE
            or kp <= 0
            or abs(float(bias[1]) + kp) > 1e-9 * kp
        ):
            continue
        joint = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, int(m.actuator_trnid[a, 0]))
        if joint is not None:
            found[joint] = (a, kp, -float(bias[2]), float(m.actuator_gear[a, 0]))
    return found


def place(model: Any, data: Any, start: Mapping[str, float]) -> None:
    """Put the joints named in ``start`` there (the others at the model's qpos0), at rest."""
    import mujoco

    for joint, value in start.items():
        jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        if jid >= 0:
            data.qpos[model.jnt_qposadr[jid]] = value
    mujoco.mj_forward(model, data)


def drive(
    model: object,
    data: object,
    actuators: Sequence[int],
    addresses: Sequence[int],
    targets: np.ndarray,
    substeps: int,
) -> np.ndarray:
    """The one MuJoCo stepping loop (the reference, check's keyframe hold): from where ``data``
    is, the actuators given ``targets[k - 1]`` as their ``ctrl`` for ``substeps`` steps to
    reach sample ``k``; the qpos at ``addresses`` of every sample (sample 0: the start). A free
    root is held where it starts, as ManiSkill's replay and check's test stand hold it."""
    import mujoco

    m: mujoco.MjModel = model
    d: mujoco.MjData = data
    free = [
        (int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j]))
        for j in range(m.njnt)
        if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE
    ]
    held = [(q, v, d.qpos[q : q + 7].copy()) for q, v in free]
    qpos = np.empty((targets.shape[0], len(addresses)))
    qpos[0] = d.qpos[list(addresses)]
    for k in range(1, targets.shape[0]):
        d.ctrl[list(actuators)] = targets[k - 1]
        for _ in range(substeps):
            mujoco.mj_step(m, d)
            for q, v, pose in held:
                d.qpos[q : q + 7] = pose
                d.qvel[v : v + 6] = 0.0
        qpos[k] = d.qpos[list(addresses)]
    return qpos
