"""RS535: a keyframe the MJCF's own actuators cannot hold in MuJoCo either: the description, not
the spec's drives, is what fails the hold.

A robot that drifts off its keyframe in ManiSkill (RS501) could be a scaffold whose gains are
too weak or a description that cannot hold that pose at all (a knee its servo cannot carry).
For an MJCF robot (either loader) MuJoCo is the independent judge: ``check`` holds the same
keyframe in MuJoCo for as long as ManiSkill's hold lasts, under the file's own position servos
(``<position>``, or ``<general>`` with a servo's gain and bias, their ``ctrl`` at the
keyframe), with a free root held where ManiSkill's test stand holds it and gravity off where
the mode cancels it (``balance_passive_force``). It costs milliseconds. Then:

- MuJoCo holds it and ManiSkill does not: RS501 stays an error, and says that the spec's drives
  in ManiSkill fail, not the description (``robospec tune --reference mujoco`` fits them to
  MuJoCo's servos);
- neither holds it: RS535, a warning at the file's actuator of the joint that drifted most in
  MuJoCo, with both drifts, instead of RS501: no gains in the spec make the robot hold a pose
  its own description cannot.

Each hold's finding reports both largest joint drifts (``max_joint_drift``,
``mujoco_max_joint_drift``). A file without position servos on the held joints is not judged
(``mujoco``: why). Standing on the ground is not compared: the file's floor, if any, is not
ManiSkill's.

Passing: an MJCF arm whose servos (kp 400) and spec (stiffness 400) both hold it within
0.01 rad over 0.5 s.
Failing: the same arm with servos of kp 0.5: its shoulder sags 0.35 rad in MuJoCo and 0.7 rad
in ManiSkill over 0.5 s (RS535).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import MJCF_KEYFRAME_UNHELD
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Metric, metrics

MUJOCO_HINT = (
    "the file's own actuators hold it in MuJoCo: give the spec's drives MuJoCo's gains "
    "(robospec tune --reference mujoco fits them), or "
)


@dataclass(frozen=True)
class MujocoHold:
    """MuJoCo's hold of one keyframe: its largest joint drift and where, or why it was not
    held (``skipped``)."""

    drift: float = 0.0
    joint: str | None = None
    unit: str = "rad"
    skipped: str | None = None
    unservoed: tuple[str, ...] = ()  # joints ManiSkill holds that no servo of the file drives

    def holds(self, limit: float) -> bool:
        return self.skipped is None and self.drift <= limit


def judge(
    run: CheckRun,
    joint_names: list[str],
    start: np.ndarray,
    held: np.ndarray,
    root: tuple[np.ndarray, np.ndarray] | None,
    seconds: float,
    sample_dt: float,
    gravity: bool,
) -> MujocoHold | None:
    """Hold ``start`` (ManiSkill's qpos, by ``joint_names``) in MuJoCo for ``seconds``, the
    joints ``held`` marks measured; a free root held at ``root`` (position, wxyz quaternion).
    None for a robot not described in MJCF."""
    path = mjcf_file(run)
    if path is None:
        return None
    from robospec.derive.mjcf_files import compiled_model
    from robospec.physics.mujoco_servos import drive, place, position_actuators

    try:
        model = compiled_model(mended_mjcf(run, path), str(path))
    except (OSError, ValueError) as exc:
        return MujocoHold(skipped=f"MuJoCo cannot compile the file ({exc})")
    if model.nu == 0:
        return MujocoHold(skipped="the file has no actuators")
    servos = position_actuators(model)
    measured = [name for name, keep in zip(joint_names, held, strict=True) if keep]
    used = [name for name in measured if name in servos]
    unservoed = tuple(name for name in measured if name not in servos)
    if not used:
        return MujocoHold(
            skipped="no joint it holds has a position servo in the file (<position>, or "
            "<general> with a servo's gain and bias)",
            unservoed=unservoed,
        )
    import mujoco

    data = mujoco.MjData(model)
    if not gravity:
        model.opt.gravity[:] = 0.0
    place(model, data, {name: float(v) for name, v in zip(joint_names, start, strict=True)})
    _put_root(model, data, root)
    index = [joint_names.index(name) for name in used]
    addresses = [int(model.jnt_qposadr[_joint(model, name)]) for name in used]
    actuators = [servos[name][0] for name in used]
    # a position servo's ctrl is its length: gear times the joint's position
    ctrl = start[index] * np.array([servos[name][3] for name in used])
    substeps = max(round(sample_dt / model.opt.timestep), 1)
    samples = max(round(seconds / (substeps * model.opt.timestep)), 1) + 1
    qpos = drive(model, data, actuators, addresses, np.tile(ctrl, (samples, 1)), substeps)
    if not np.isfinite(qpos).all():
        return MujocoHold(drift=float("inf"), joint=used[0], unservoed=unservoed)
    drift = np.abs(qpos - start[index]).max(axis=0)
    worst = int(np.argmax(drift))
    slide = model.jnt_type[_joint(model, used[worst])] == mujoco.mjtJoint.mjJNT_SLIDE
    return MujocoHold(float(drift[worst]), used[worst], "m" if slide else "rad", None, unservoed)


def mjcf_file(run: CheckRun) -> Path | None:
    """The robot's MJCF as its author wrote it, whichever loader reads it (ManiSkill's, or
    MuJoCo's compiled into a URDF: ``loader: mujoco``); None for a robot described otherwise."""
    spec_description = getattr(run.context.spec, "description", None)
    compiled = spec_description is not None and spec_description.kind == "mjcf"
    if run.robot.description_kind != "mjcf" and not compiled:
        return None
    absolute = run.robot.description.absolute
    return Path(absolute) if absolute is not None else None


def mended_mjcf(run: CheckRun, path: Path) -> bytes:
    """The MJCF at ``path`` with the mends the spec declares for it, which MuJoCo reads too
    (the unit of its angles, names it defines twice: robosuite's Robotiq 2F-85 needs both to
    compile as its author meant)."""
    from robospec.derive import Source, mended_bytes

    data = path.read_bytes()
    declared = getattr(getattr(run.context.spec, "description", None), "mend", None)
    mends = declared.model_dump(exclude_none=True) if declared is not None else {}
    if not mends:
        return data
    return mended_bytes(Source(str(path), path.name, "mjcf", data), mends) or data


def _joint(model: Any, name: str) -> int:
    import mujoco

    return int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name))


def _put_root(model: Any, data: Any, root: tuple[np.ndarray, np.ndarray] | None) -> None:
    """A free root where ManiSkill holds its root link (on the test stand)."""
    import mujoco

    if root is None:
        return
    for j in range(model.njnt):
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
            q = int(model.jnt_qposadr[j])
            data.qpos[q : q + 3] = root[0]
            data.qpos[q + 3 : q + 7] = root[1]
            break
    mujoco.mj_forward(model, data)


def metrics_of(found: MujocoHold) -> dict[str, Metric]:
    """MuJoCo's side of a hold, for its finding's metrics."""
    return metrics(
        mujoco_max_joint_drift=None if found.skipped else found.drift,
        mujoco_joint=found.joint,
        mujoco=found.skipped or "held under the file's actuators",
    )


def verdict(
    run: CheckRun, label: str, mode: str, found: MujocoHold, maniskill: str, drift_alone: bool
) -> str | Diagnostic | None:
    """What MuJoCo says of a hold ManiSkill failed (``maniskill``: its worst drift, in words):
    that it holds it (a problem's words, for RS501), that it cannot either (RS535, where the
    drift is all that failed: ``drift_alone``), or nothing (not judged)."""
    if found.skipped is not None:
        return None
    if found.holds(run.settings.keyframe_hold.max_joint_drift):
        return (
            f"MuJoCo holds it under the file's own actuators (largest drift "
            f"{found.drift:.3g} {found.unit}, '{found.joint}'): the spec's drives in "
            "ManiSkill fail it, not the description"
        )
    return cannot_hold(run, label, mode, found, maniskill) if drift_alone else None


def hint_before(found: MujocoHold | None, limit: float) -> str:
    """RS501's hint's start where MuJoCo holds the keyframe: the file's gains hold it."""
    return MUJOCO_HINT if found is not None and found.holds(limit) else ""


def cannot_hold(
    run: CheckRun, label: str, mode: str, found: MujocoHold, maniskill: str
) -> Diagnostic:
    """RS535 at the file's actuator of the joint MuJoCo let drift most."""
    line = next((a.line for a in run.context.description.actuators if a.joint == found.joint), None)
    at = (
        run.context.at_description(line)
        if line is not None
        else run.at(("keyframes", label) if label != "(initial)" else ("uid",))
    )
    return warning(
        at,
        MJCF_KEYFRAME_UNHELD,
        f"keyframe '{label}' cannot be held by the description either: under the file's own "
        f"actuators MuJoCo lets joint '{found.joint}' drift {found.drift:.3g} {found.unit} "
        f"over the same hold, where ManiSkill ({mode}) lets {maniskill}; no gains in the "
        "spec make the robot hold a pose its own description cannot",
        "move the keyframe where the file's actuators can carry it (off joint limits, less "
        "load on the weakest joint), or correct the actuators' gains and force ranges in the "
        "file if the real robot holds it",
    )


def words(found: MujocoHold) -> str:
    """MuJoCo's side of a hold, for a summary."""
    if found.skipped is not None:
        return "MuJoCo not judged"
    return f"MuJoCo {found.drift:.2g} {found.unit} ({found.joint})"
