"""RS530 and RS531: a closed loop's two points meet at rest, and stay together while the robot
moves.

A loop (``loops:``) holds a point of one link on a point of the other with a drive whose
translation limits are zero. The spec writes the point in each link's frame; if the two do not
name the same place at rest, the drive snaps the links together on the first step, wrenching
the linkage out of the shape its joints give it (RS530: the distance at each keyframe, and as
loaded, before anything moves, against ``checks.loops.max_gap_at_rest``). While the robot
moves, PhysX solves the drive with the joints, and a linkage driven harder than its solver
holds opens (RS531: the largest distance under the random actions of
``checks.random_actions``, in the first control mode, from the first keyframe, against
``checks.loops.max_gap``). A floating robot's loop that opened only while the floor pressed on
a link its joints move, and stays closed under the same actions on a test stand, is a warning,
as random_actions judges a joint the floor flung: random actions topple TALOS onto its
grippers, whose loops its weight then pulls 3 mm apart.

Passing: the Robotiq 2F-85 as ``robospec new`` writes it, its four-bars closed where the
knuckles meet the inner fingers.
Failing: the same loop with the inner finger's point 2 cm off: at rest the points are 20 mm
apart.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import LOOP_APART_AT_REST, LOOP_PULLS_APART
from robospec.geometry import Vector, rotate
from robospec.physics import ground
from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.random_actions import random_draws
from robospec.physics.sim import Sim
from robospec.resolve.resolved import ResolvedKeyframe, ResolvedLoop

if TYPE_CHECKING:
    from mani_skill.utils.structs import Pose

NAME = "loops"


def check(run: CheckRun) -> list[Finding]:
    loops = run.context.robot.loops
    if not loops:
        return []
    sim = run.sim(run.modes[0])
    findings = [_at_rest(run, sim, start) for start in [None, *run.robot.keyframes]]
    findings.append(_moving(run, sim))
    return findings


def gaps(sim: Sim, loops: tuple[ResolvedLoop, ...]) -> np.ndarray:
    """Each loop's distance between its two points now, in m (the worst of the envs)."""
    out = []
    for loop in loops:
        ends = []
        for link, (p, _) in zip(loop.links, loop.poses, strict=True):
            ends.append(_points(sim.robot.links_map[link].pose, p))
        out.append(float(np.max(np.linalg.norm(ends[0] - ends[1], axis=-1))))
    return np.array(out)


def _points(pose: Pose, p: Vector) -> np.ndarray:
    """``p`` (in the link's frame) in the world, per env: shape (envs, 3)."""
    positions = pose.p.cpu().numpy().astype(np.float64)
    quaternions = pose.q.cpu().numpy().astype(np.float64)
    return np.array(
        [
            np.add(position, rotate((q[0], q[1], q[2], q[3]), p))
            for position, q in zip(positions, quaternions, strict=True)
        ]
    )


def _at_rest(run: CheckRun, sim: Sim, start: ResolvedKeyframe | None) -> Finding:
    loops = run.robot.loops
    sim.start(start)
    apart = gaps(sim, loops)
    label = keyframe_label(start)
    limit = run.settings.loops.max_gap_at_rest
    details = tuple(
        metrics(loop=loop.name, gap=float(g)) for loop, g in zip(loops, apart, strict=True)
    )
    open_ = [(loop, g) for loop, g in zip(loops, apart, strict=True) if g > limit]
    if not open_:
        return Finding(
            NAME, None, label, Status.PASS, "the loops' points meet", _worst(apart), (), details
        )
    diagnostics: list[Diagnostic] = []
    for loop, gap in open_:
        first, second = loop.links
        diagnostics.append(
            run.fail(
                ("loops", loop.name, "at"),
                LOOP_APART_AT_REST,
                f"loop '{loop.name}': at {'keyframe ' + repr(label) if start else 'the load'} "
                f"its point on '{first}' and its point on '{second}' are {gap * 1000:.1f} mm "
                f"apart (more than max_gap_at_rest {limit * 1000:g} mm): they are not where "
                "the links meet",
                "give the point where the two links meet in each link's frame (robospec new "
                "computes them from the description); a loop joins links that touch there",
            )
        )
    summary = ", ".join(f"{loop.name} {g * 1000:.1f} mm apart" for loop, g in open_)
    return Finding(
        NAME, None, label, Status.FAIL, summary, _worst(apart), tuple(diagnostics), details
    )


@dataclass
class _Opening:
    """How far each loop opened under one run of random actions (shape ``(L,)``), and whether
    its worst opening came while the floor pressed on a link its joints move."""

    gap: np.ndarray
    grounded: np.ndarray


def _drive_randomly(run: CheckRun, sim: Sim, on_stand: bool = False) -> _Opening:
    """The random actions of ``checks.random_actions`` in the first mode, from the first
    keyframe; ``on_stand``: held clear of the floor (``Sim.test_stand``)."""
    loops = run.robot.loops
    settings = run.settings.random_actions
    start = run.robot.keyframes[0] if run.robot.keyframes else None
    draw = random_draws(sim, settings.seed)
    sim.start(start)
    pin = sim.test_stand() if on_stand else None
    # as random_actions watches the floor, a free robot only: random actions topple it onto a
    # gripper (TALOS lands on its fingertips), and a linkage pressed on by its weight opens
    moved = [set().union(*(sim.moved_by(j) for j in loop.joints)) for loop in loops]
    floor = ground.FloorPress(sim, moved, not on_stand and not sim.fixed_root)
    opening = _Opening(np.zeros(len(loops)), np.zeros(len(loops), dtype=bool))
    for _ in range(settings.steps):
        sim.step(draw(), pin)
        now = gaps(sim, loops)
        if not np.all(np.isfinite(now)):
            break  # NaN: random_actions says why (RS502)
        for i, on_floor in floor.pressed(now > opening.gap).items():
            opening.grounded[i] = on_floor
        opening.gap = np.maximum(opening.gap, now)
    return opening


def _moving(run: CheckRun, sim: Sim) -> Finding:
    """The random actions of ``checks.random_actions`` in the first mode, from the first
    keyframe: the largest distance each loop opens to. A loop that opened only while the floor
    pressed on its links, and stays closed under the same actions on a test stand, is a
    warning: the floor opened it, not its drive."""
    loops = run.robot.loops
    limit = run.settings.loops.max_gap
    opening = _drive_randomly(run, sim)
    worst = opening.gap
    floor = np.zeros(len(loops), dtype=bool)
    if ((worst > limit) & opening.grounded).any():
        held = _drive_randomly(run, sim, on_stand=True)
        floor = opening.grounded & (held.gap <= limit)
    subject = f"{run.settings.random_actions.steps} random steps"
    details = tuple(
        metrics(loop=loop.name, gap=float(g)) for loop, g in zip(loops, worst, strict=True)
    )
    opened = [
        (loop, float(g), bool(f))
        for loop, g, f in zip(loops, worst, floor, strict=True)
        if g > limit
    ]
    if not opened:
        return Finding(
            NAME,
            sim.mode,
            subject,
            Status.PASS,
            "the loops stay closed",
            _worst(worst),
            (),
            details,
        )
    diagnostics = tuple(_pulled_apart(run, sim, loop, g, f) for loop, g, f in opened)
    status = Status.FAIL if any(d.is_error for d in diagnostics) else Status.INFO
    summary = ", ".join(f"{loop.name} opened {g * 1000:.1f} mm" for loop, g, _ in opened)
    return Finding(NAME, sim.mode, subject, status, summary, _worst(worst), diagnostics, details)


def _pulled_apart(
    run: CheckRun, sim: Sim, loop: ResolvedLoop, gap: float, floor: bool
) -> Diagnostic:
    """RS531: ``loop`` opened to ``gap`` (a warning where the floor opened it)."""
    limit = run.settings.loops.max_gap
    what = (
        f"loop '{loop.name}' pulls apart under random actions in mode '{sim.mode}': its "
        f"two points {gap * 1000:.1f} mm apart (more than max_gap {limit * 1000:g} mm)"
    )
    if floor:
        return warning(
            run.at(("loops", loop.name)),
            LOOP_PULLS_APART,
            what + " while a link it moves, not one the robot stands on, pressed on the "
            "ground: random actions toppled the free robot onto it; held clear of the floor "
            "on a test stand, the same actions do not",
            "nothing to fix in the linkage: the robot's weight landed on it",
        )
    return run.fail(
        ("loops", loop.name),
        LOOP_PULLS_APART,
        what,
        "drive the linkage more gently (a lower force_limit on its driver), or give the "
        "solver more iterations (simulation.solver_position_iterations)",
    )


def _worst(apart: np.ndarray) -> dict[str, float | int | str | bool | None]:
    return metrics(max_gap=float(np.max(apart)) if len(apart) else 0.0)
