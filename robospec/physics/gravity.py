"""RS518: a floating robot hovers. RS519: the root ManiSkill loads is not the one the spec says.

ManiSkill's gravity compensation (``balance_passive_force``, true unless a mode says
``balance_passive_force: false``) works by turning gravity off for every link of the robot. For
a robot mounted on a fixed root that is what it should do; a robot with a free root (a
quadruped, a humanoid, a floating hand) then floats in zero gravity, and every other check
passes it: a keyframe held in mid-air does not drift. So for each control mode of a floating
robot, the robot is put at its first keyframe, lifted 0.5 m, and left to fall for 0.5 s with
its drives holding its joints (a free fall covers 1.2 m); a robot that falls less than half the
lift hovers. The finding says whether ManiSkill turned gravity off, and where to say
``balance_passive_force: false``. A mode that writes ``balance_passive_force: true`` on purpose
(a robot meant to float in zero gravity) gets a warning instead of an error.

Whether the root is fixed is read from the robot as loaded, not from the spec: ManiSkill's MJCF
loader frees the root body of a ``<freejoint/>`` and fixes any other, whatever
``loader.fix_root_link`` says. When the two disagree the spec describes another robot than the
one tasks get: RS519, at ``fix_root_link`` (or at the description when the default is meant).

Passing: ManiSkill's humanoid: its modes say ``balance_passive_force: false``, and lifted half a
metre it falls back to the floor.
Failing: the same humanoid without ``balance_passive_force: false`` in ``pd_joint_pos``: lifted
half a metre, it stays there (RS518, at the mode).
"""

from __future__ import annotations

import numpy as np

from robospec.diagnostics import Location, Severity, error, warning
from robospec.diagnostics.codes import HOVERS, WRONG_ROOT
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import Sim

NAME = "gravity"
LIFT = 0.5  # metres above the first keyframe
FALL_TIME = 0.5  # seconds: a free fall covers 1.2 m, so a lifted robot lands


def check(run: CheckRun) -> list[Finding]:
    if not run.modes:
        return []
    loaded_fixed = run.sim(run.modes[0]).fixed_root
    findings = []
    if loaded_fixed != run.robot.fix_root_link:
        findings.append(_root_mismatch(run, loaded_fixed))
    if loaded_fixed:
        return findings  # a mounted robot: nothing to fall, and no row in every robot's table
    return findings + [_fall(run, run.sim(mode)) for mode in run.modes]


def _root_mismatch(run: CheckRun, loaded_fixed: bool) -> Finding:
    key = run.at(("loader", "fix_root_link"))
    written = key != run.at(("loader",))  # else the key fell back to its parent: not written
    said = f"fix_root_link: {'true' if run.robot.fix_root_link else 'false'}" + (
        "" if written else " (the default)"
    )
    loaded = "fixed to the world" if loaded_fixed else "free"
    why = (
        " (ManiSkill's MJCF loader frees the root body of a <freejoint/> and fixes any other, "
        "whatever fix_root_link says)"
        if run.robot.description_kind == "mjcf"
        else ""
    )
    diagnostic = error(
        key if written else run.at(("description",)),
        WRONG_ROOT,
        f"the spec says {said}, but ManiSkill loads the root link "
        f"'{run.context.description.root_link}' {loaded}{why}",
        f"say fix_root_link: {'true' if loaded_fixed else 'false'} to describe the robot tasks "
        "get"
        + (
            ", or remove the <freejoint/> if the robot is mounted"
            if run.robot.description_kind == "mjcf" and not loaded_fixed
            else ""
        ),
    )
    summary = f"the spec says {said}; the root loads {loaded}"
    return Finding(NAME, None, "root", Status.FAIL, summary, {}, (diagnostic,))


def _fall(run: CheckRun, sim: Sim) -> Finding:
    sim.start(run.keyframes[0])
    sim.hold_drive_targets()
    before = float(sim.root_position()[:, 2].min())
    sim.lifted_root(LIFT)
    gravity_off = sim.gravity_off()
    for _ in range(round(FALL_TIME * sim.sim_freq)):
        sim.sim_step()
    fell = max(0.0, before + LIFT - float(sim.root_position()[:, 2].max()))
    values = metrics(lift=LIFT, seconds=FALL_TIME, fell=fell, gravity_off=gravity_off)
    summary = f"lifted {LIFT:g} m, fell {fell:.3g} m in {FALL_TIME:g} s" + (
        " (gravity off)" if gravity_off else ""
    )
    if fell >= LIFT / 2 or not np.isfinite(fell):
        return Finding(NAME, sim.mode, "fall", Status.PASS, summary, values)
    mode = next(m for m in run.robot.modes if m.name == sim.mode)
    written = mode.balance_passive_force is True
    path = ("control_modes", sim.mode) + (("balance_passive_force",) if written else ())
    cause = (
        "ManiSkill turned gravity off for every link"
        + (
            " (balance_passive_force: true)"
            if written
            else " (balance_passive_force is true unless the mode says false)"
        )
        if gravity_off
        else "something holds its root up"
    )
    message = (
        f"mode {sim.mode}: the floating robot hovers: lifted {LIFT:g} m above its keyframe, "
        f"it fell {fell:.3g} m in {FALL_TIME:g} s; {cause}"
    )
    hint = (
        "a floating robot needs gravity: say balance_passive_force: false in this mode"
        + (
            ""
            if mode.groups is not None
            else " (written as {group: controller, balance_passive_force: false})"
        )
        + ", or fix its root (loader: {fix_root_link: true}) if it is mounted"
    )
    at: Location = run.at(path)
    diagnostic = (warning if written else error)(at, HOVERS, message, hint)
    status = Status.FAIL if diagnostic.severity is Severity.ERROR else Status.INFO
    return Finding(NAME, sim.mode, "fall", status, summary, values, (diagnostic,))
