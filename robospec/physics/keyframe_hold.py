"""RS501: a keyframe drifts while it is held: the robot, commanded to stay at a keyframe with a
joint-position mode for ``checks.keyframe_hold.steps`` control steps, moved further than
``max_joint_drift`` (a joint) or ``max_root_drift`` (the root link).

ManiSkill's advice for a new robot is to watch exactly this in a viewer. Drift means the drives
cannot hold the pose: gains too weak for the load, a keyframe pressing against a joint limit or
into the robot itself, or a floating robot that cannot stand the way the keyframe puts it.

Passing: the Panda's ``rest`` keyframe held with ``pd_joint_pos`` moves less than a millimetre.
Failing: the same keyframe with ``pose: {p: [0, 0, 0.5]}`` on a robot with ``fix_root_link:
false`` whose modes keep gravity (``balance_passive_force: false``) falls to the ground (root
drift 0.5 m).
"""

from __future__ import annotations

import numpy as np

from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import Sim

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
            "RS501",
            f"checks.keyframe_hold.mode '{settings.mode}' is not a control mode of this robot",
            "name one of: " + ", ".join(run.modes),
        )
        return [Finding(NAME, settings.mode, "-", Status.FAIL, "unknown mode", {}, (diagnostic,))]
    mode, by_action = hold_mode(run)
    sim = run.sim(mode)
    return [_hold(run, sim, keyframe, by_action) for keyframe in run.keyframes]


def _hold(run: CheckRun, sim: Sim, keyframe: object, by_action: bool) -> Finding:
    settings = run.settings.keyframe_hold
    start = sim.start(keyframe)  # type: ignore[arg-type]
    root_start = sim.root_position()
    free = np.zeros(len(sim.joint_names), dtype=bool)
    for group in sim.groups():
        if group.kind == "passive":
            free[list(group.joint_indices)] = True
    action = sim.hold_action(start) if by_action else None
    if action is None:
        sim.hold_drive_targets()
    joint_drift = np.zeros(len(sim.joint_names))
    root_drift = 0.0
    finite = True
    pin = sim.robot.pose if settings.pin_root and not sim.fixed_root else None
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
    joint_drift[free] = 0.0
    worst = int(np.argmax(joint_drift))
    label = keyframe_label(keyframe)  # type: ignore[arg-type]
    how = "actions" if action is not None else "drive targets"
    if pin is not None:
        how += ", root pinned"
    values = metrics(
        steps=settings.steps,
        held_by=how,
        max_joint_drift=float(joint_drift[worst]),
        joint=sim.joint_names[worst],
        max_root_drift=root_drift,
        finite=finite,
    )
    unit = "m" if sim.prismatic[worst] else "rad"
    summary = (
        f"joint drift {joint_drift[worst]:.2g} {unit} ({sim.joint_names[worst]}), "
        f"root drift {root_drift:.2g} m over {settings.steps} steps"
    )
    problems = []
    if not finite:
        problems.append("the state went NaN")
    if joint_drift[worst] > settings.max_joint_drift:
        problems.append(
            f"joint '{sim.joint_names[worst]}' drifted {joint_drift[worst]:.3g} {unit} "
            f"(more than max_joint_drift {settings.max_joint_drift:g})"
        )
    if root_drift > settings.max_root_drift:
        problems.append(
            f"the root link drifted {root_drift:.3g} m (more than max_root_drift "
            f"{settings.max_root_drift:g})"
        )
    if not problems:
        return Finding(NAME, sim.mode, label, Status.PASS, summary, values)
    mimic = _mimic_mismatch(run, sim, start)
    if mimic:
        problems.append(mimic)
    diagnostic = run.fail(
        run.keyframe_path(keyframe),  # type: ignore[arg-type]
        "RS501",
        f"keyframe '{label}' held with {sim.mode} ({how}) for {settings.steps} steps: "
        + "; ".join(problems),
        "stiffen the drives holding it, move the keyframe off joint limits and away from "
        "self-contact, or set checks.keyframe_hold.max_joint_drift/max_root_drift if the "
        "motion is expected (e.g. a floating robot settling onto the ground)",
    )
    return Finding(NAME, sim.mode, label, Status.FAIL, summary, values, (diagnostic,))


def _mimic_mismatch(run: CheckRun, sim: Sim, start: np.ndarray) -> str | None:
    """Why mimic joints move off a keyframe: the mode's ``pd_joint_pos_mimic`` controllers hold
    each mimic joint at ``multiplier * control + offset``, whatever the keyframe says."""
    index = {name: i for i, name in enumerate(sim.joint_names)}
    wrong = []
    for group in sim.groups():
        name = run.controller_name(sim.mode, group.name)
        resolved = next((c for c in run.robot.controllers if c.name == name), None)
        if resolved is None or resolved.type != "pd_joint_pos_mimic":
            continue
        for joint, rule in (dict(resolved.kwargs).get("mimic") or {}).items():
            control = rule["joint"]
            held = rule.get("multiplier", 1.0) * start[index[control]] + rule.get("offset", 0.0)
            if abs(held - start[index[joint]]) > run.settings.keyframe_hold.max_joint_drift:
                wrong.append(f"'{joint}' is at {start[index[joint]]:.4g}, held at {held:.4g}")
    if not wrong:
        return None
    return (
        f"the keyframe disagrees with the mimic controllers, which hold each mimic joint at "
        f"multiplier * control joint + offset ({'; '.join(wrong)})"
    )
