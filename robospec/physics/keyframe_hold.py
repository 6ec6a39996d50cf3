"""RS501: a keyframe drifts while it is held: the robot, commanded to stay at a keyframe with a
joint-position mode for ``checks.keyframe_hold.steps`` control steps, moved further than
``max_joint_drift`` (a joint) or ``max_root_drift`` (the root link). RS523 (a warning): a
floating robot cannot stand at a keyframe, whatever its drives do.

ManiSkill's advice for a new robot is to watch exactly this in a viewer. Drift means the drives
cannot hold the pose: gains too weak for the load, a keyframe pressing against a joint limit,
into the robot itself or into the ground. Joints a velocity controller drives (wheels) and
passive joints are not held to an angle: they are left out of the joint drift.

A robot with a free root is held twice. On a test stand first — its root held clear of the
ground, the keyframe's pose lifted (``Sim.test_stand``) — which measures its drives alone
(RS501 when they cannot hold the pose): held where the keyframe stands it, its feet would press
on the ground with a root that cannot give way.
Then standing on the ground, but only where its statics say it can stand: its centre of mass
over the support polygon of its contacts with the ground at the keyframe
(:mod:`robospec.physics.statics`). There a fall is RS501; a robot whose centre of mass lies
outside the polygon (a humanoid on one foot, or leaning) cannot stand on any drives, and its
fall is RS523, a warning that says why. ``pin_root: true`` keeps only the test stand.

Passing: the Panda's ``rest`` keyframe held with ``pd_joint_pos`` moves less than a millimetre.
Failing: the same keyframe with ``pose: {p: [0, 0, 0.5]}`` on a robot with ``fix_root_link:
false`` whose modes keep gravity (``balance_passive_force: false``) falls to the ground (root
drift 0.5 m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robospec.diagnostics import warning
from robospec.diagnostics.codes import CANNOT_STAND, KEYFRAME_DRIFTS
from robospec.physics import ground, mimic_limits, mujoco_hold
from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import Sim
from robospec.physics.statics import Support, support
from robospec.resolve.resolved import ResolvedKeyframe

NAME = "keyframe_hold"


def hold_mode(run: CheckRun) -> tuple[str, bool]:
    """The mode to hold keyframes with, and whether its actions can command joint positions
    (else the drives are given the keyframe directly, below the controllers)."""
    settings = run.settings.keyframe_hold
    if settings.mode is not None:
        sim = run.sim(settings.mode)
        return settings.mode, all(g.absolute_position for g in sim.groups())
    for mode in run.modes:
        if all(g.absolute_position for g in run.sim(mode).groups()):
            return mode, True
    return run.modes[0], False


def check(run: CheckRun) -> list[Finding]:
    settings = run.settings.keyframe_hold
    if settings.mode is not None and settings.mode not in run.modes:
        diagnostic = run.fail(
            ("checks", "keyframe_hold", "mode"),
            KEYFRAME_DRIFTS,
            f"checks.keyframe_hold.mode '{settings.mode}' is not a control mode of this robot",
            "name one of: " + ", ".join(run.modes),
        )
        return [Finding(NAME, settings.mode, "-", Status.FAIL, "unknown mode", {}, (diagnostic,))]
    mode, by_action = hold_mode(run)
    sim = run.sim(mode)
    findings = []
    for keyframe in run.keyframes:
        if sim.fixed_root:
            findings.append(_hold(run, sim, keyframe, by_action, pinned=False))
            continue
        findings.append(_hold(run, sim, keyframe, by_action, pinned=True))
        if not settings.pin_root and not sim.backend.gpu:
            findings.append(_standing(run, sim, keyframe, by_action))
    return findings


def _held_joints(sim: Sim) -> np.ndarray:
    """Which joints a hold keeps at an angle: not passive ones, not velocity-driven ones (a
    wheel turns freely as the robot settles: that is no drift)."""
    held = np.ones(len(sim.joint_names), dtype=bool)
    for group in sim.groups():
        if group.kind in ("passive", "velocity"):
            held[list(group.joint_indices)] = False
    return held


@dataclass
class _Held:
    joint_drift: np.ndarray
    root_drift: float
    finite: bool
    how: str
    start: np.ndarray
    held: np.ndarray  # the joints measured
    root: tuple[np.ndarray, np.ndarray] | None  # a floating root's held pose (p, wxyz)


def _run_hold(
    run: CheckRun, sim: Sim, keyframe: ResolvedKeyframe | None, by_action: bool, pinned: bool
) -> _Held:
    settings = run.settings.keyframe_hold
    start = sim.start(keyframe)
    # on a test stand: lifted clear of the ground, its root held there (Sim.test_stand)
    pin = sim.test_stand() if pinned and not sim.fixed_root else None
    root_start = sim.root_position()
    root = None
    if not sim.fixed_root:
        pose = sim.robot.pose
        root = (pose.p[0].cpu().numpy().astype(float), pose.q[0].cpu().numpy().astype(float))
    action = sim.hold_action(start) if by_action else None
    if action is None:
        sim.hold_drive_targets()
    held = _held_joints(sim)
    joint_drift = np.zeros(len(sim.joint_names))
    root_drift = 0.0
    finite = True
    for _ in range(settings.steps):
        if action is not None:
            sim.step(action, pin)
        else:
            for _ in range(sim.sim_freq // sim.control_freq):
                sim.sim_step(pin)
        qpos = sim.qpos()
        if not np.isfinite(qpos).all():
            finite = False
            break
        joint_drift = np.maximum(joint_drift, np.abs(qpos - start).max(axis=0))
        root_drift = max(
            root_drift, float(np.linalg.norm(sim.root_position() - root_start, axis=-1).max())
        )
    joint_drift[~held] = 0.0
    how = "actions" if action is not None else "drive targets"
    if pin is not None:
        how += ", root held"
    return _Held(joint_drift, root_drift, finite, how, start, held, root)


def _in_mujoco(run: CheckRun, sim: Sim, found: _Held) -> mujoco_hold.MujocoHold | None:
    """The same hold in MuJoCo, for an MJCF robot (robospec.physics.mujoco_hold)."""
    steps = run.settings.keyframe_hold.steps
    return mujoco_hold.judge(
        run,
        list(sim.joint_names),
        found.start,
        found.held,
        found.root,
        steps / sim.control_freq,
        1.0 / sim.control_freq,
        gravity=not sim.gravity_off(),
    )


def _hold(
    run: CheckRun,
    sim: Sim,
    keyframe: ResolvedKeyframe | None,
    by_action: bool,
    pinned: bool,
    standing: Support | None = None,
) -> Finding:
    settings = run.settings.keyframe_hold
    found = _run_hold(run, sim, keyframe, by_action, pinned)
    joint_drift, root_drift = found.joint_drift, found.root_drift
    # MuJoCo judges the hold on the test stand (or a fixed root): its floor is not ManiSkill's
    judged = _in_mujoco(run, sim, found) if standing is None else None
    worst = int(np.argmax(joint_drift))
    label = keyframe_label(keyframe)
    subject = label
    if not sim.fixed_root and not settings.pin_root:
        subject = f"{label} ({'test stand' if pinned else 'standing'})"
    values = metrics(
        steps=settings.steps,
        held_by=found.how,
        max_joint_drift=float(joint_drift[worst]),
        joint=sim.joint_names[worst],
        max_root_drift=root_drift,
        finite=found.finite,
    )
    unit = "m" if sim.prismatic[worst] else "rad"
    summary = (
        f"joint drift {joint_drift[worst]:.2g} {unit} ({sim.joint_names[worst]}), "
        f"root drift {root_drift:.2g} m over {settings.steps} steps"
    )
    if judged is not None:
        values |= mujoco_hold.metrics_of(judged)
        summary += f"; {mujoco_hold.words(judged)}"
    problems = _problems(run, sim, found, worst)
    if not problems:
        return Finding(NAME, sim.mode, subject, Status.PASS, summary, values)
    mimic, contradicted = _mimic_mismatch(
        run, sim, np.asarray(keyframe.qpos) if keyframe and keyframe.qpos else sim.start(keyframe)
    )
    if mimic:
        problems.append(mimic)
    if judged is not None:
        maniskill = f"'{sim.joint_names[worst]}' drift {joint_drift[worst]:.3g} {unit}"
        drift_alone = found.finite and not mimic and root_drift <= settings.max_root_drift
        verdict = mujoco_hold.verdict(run, label, sim.mode, judged, maniskill, drift_alone)
        if isinstance(verdict, str):
            problems.append(verdict)
        elif verdict is not None:  # the description cannot hold it either: RS535
            return Finding(NAME, sim.mode, subject, Status.INFO, summary, values, (verdict,))
    if standing is not None and standing.touches:
        problems.append(
            f"it can stand there: its centre of mass is {standing.inside * 100:.3g} cm inside "
            f"the support polygon of its contacts ({', '.join(standing.links)})"
        )
    where = (
        "on a test stand (its root held clear of the ground)"
        if pinned and not sim.fixed_root
        else ""
    )
    diagnostic = run.fail(
        run.keyframe_path(keyframe),
        KEYFRAME_DRIFTS,
        f"keyframe '{label}' held with {sim.mode} ({found.how}) for {settings.steps} steps"
        + (f" {where}" if where else "")
        + ": "
        + "; ".join(problems)
        + ground.note(run, keyframe),
        mimic_limits.HINT
        if contradicted
        else mujoco_hold.hint_before(judged, settings.max_joint_drift)
        + "stiffen the drives holding it (robospec tune finds gains), move the keyframe off "
        "joint limits and away from self-contact and the ground, or set "
        "checks.keyframe_hold.max_joint_drift/max_root_drift if the motion is expected",
    )
    return Finding(NAME, sim.mode, subject, Status.FAIL, summary, values, (diagnostic,))


def _problems(run: CheckRun, sim: Sim, found: _Held, worst: int) -> list[str]:
    """What went wrong in ``found``'s hold: NaN, a joint or the root past its threshold."""
    settings = run.settings.keyframe_hold
    drift = found.joint_drift[worst]
    unit = "m" if sim.prismatic[worst] else "rad"
    problems = []
    if not found.finite:
        problems.append("the state went NaN")
    if drift > settings.max_joint_drift:
        problems.append(
            f"joint '{sim.joint_names[worst]}' drifted {drift:.3g} {unit} "
            f"(more than max_joint_drift {settings.max_joint_drift:g})"
        )
    if found.root_drift > settings.max_root_drift:
        problems.append(
            f"the root link drifted {found.root_drift:.3g} m (more than max_root_drift "
            f"{settings.max_root_drift:g})"
        )
    return problems


def _standing(
    run: CheckRun, sim: Sim, keyframe: ResolvedKeyframe | None, by_action: bool
) -> Finding:
    """The floating robot on the ground: held there where its statics say it can stand, else
    RS523 says why it falls."""
    label = keyframe_label(keyframe)
    subject = f"{label} (standing)"
    base = support_at(sim, keyframe)
    values = metrics(
        contacts=len(base.links),
        com_inside=float(base.inside) if np.isfinite(base.inside) else None,
    )
    if base.stands or (not base.touches and sim.gravity_off()):
        # (with gravity off nothing pulls it anywhere: held in mid-air it must stay there)
        return _hold(run, sim, keyframe, by_action, pinned=False, standing=base)
    outside = -base.inside
    if not base.touches:
        why = "it touches no ground: the keyframe holds it in mid-air, and gravity pulls it down"
    elif np.isfinite(outside) and len(base.polygon) >= 3:
        why = (
            f"its centre of mass lies {outside * 100:.3g} cm outside the support polygon of its "
            f"contacts with the ground ({', '.join(base.links)})"
        )
    else:
        why = (
            f"it touches the ground only at {', '.join(base.links)}: a point or a line, no "
            "polygon to balance over"
        )
    diagnostic = warning(
        run.at(run.keyframe_path(keyframe)),
        CANNOT_STAND,
        f"keyframe '{label}': the floating robot cannot stand there on any drives: {why}; "
        "it falls without a balance controller",
        "nothing to fix for a robot that balances actively (a humanoid): its drives were held "
        "on a test stand; for one meant to stand still, change the keyframe so that it stands "
        "on the ground with its centre of mass over its feet",
    )
    summary = "cannot stand: " + (
        "no ground under it" if not base.touches else "centre of mass outside its support"
    )
    return Finding(NAME, sim.mode, subject, Status.INFO, summary, values, (diagnostic,))


def support_at(sim: Sim, keyframe: ResolvedKeyframe | None) -> Support:
    """The robot's support at ``keyframe``: its root held there, its drives holding, one
    physics step for the contacts."""
    sim.start(keyframe)
    sim.hold_drive_targets()
    pin = sim.robot.pose
    sim.sim_step(pin)
    return support(sim.ground_contacts(), sim.centre_of_mass())


def _mimic_mismatch(run: CheckRun, sim: Sim, start: np.ndarray) -> tuple[str | None, bool]:
    """Why mimic joints move off a keyframe: the mode's ``pd_joint_pos_mimic`` controllers hold
    each mimic joint at ``multiplier * control + offset``, whatever the keyframe says. The
    flag is whether the description's <mimic> and <limit> contradict each other (RS545), so
    that no keyframe could agree with both."""
    index = {name: i for i, name in enumerate(sim.joint_names)}
    contradicted = mimic_limits.contradictions(run)
    wrong = []
    for group in sim.groups():
        name = run.controller_name(sim.mode, group.name)
        resolved = next((c for c in run.robot.controllers if c.name == name), None)
        if resolved is None or not resolved.kind.mimic:
            continue
        for joint, rule in (dict(resolved.kwargs).get("mimic") or {}).items():
            control = rule["joint"]
            held = rule.get("multiplier", 1.0) * start[index[control]] + rule.get("offset", 0.0)
            if abs(held - start[index[joint]]) > run.settings.keyframe_hold.max_joint_drift:
                wrong.append(f"'{joint}' is at {start[index[joint]]:.4g}, held at {held:.4g}")
    if not wrong:
        return None, False
    if contradicted:
        # no keyframe agrees with both: the description's <mimic> and <limit> disagree
        return "; ".join(c.words() for _, c in sorted(contradicted.items())) + (
            " (RS545): no keyframe agrees with both the mimic controllers and the limits ("
            + "; ".join(wrong)
            + ")"
        ), True
    return (
        f"the keyframe disagrees with the mimic controllers, which hold each mimic joint at "
        f"multiplier * control joint + offset ({'; '.join(wrong)})"
    ), False
