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
``checks.loops.max_gap``).

Passing: the Robotiq 2F-85 as ``robospec new`` writes it, its four-bars closed where the
knuckles meet the inner fingers.
Failing: the same loop with the inner finger's point 2 cm off: at rest the points are 20 mm
apart.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robospec.diagnostics import Diagnostic
from robospec.geometry import Vector, rotate
from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import Sim
from robospec.resolve.resolved import ResolvedKeyframe, ResolvedLoop

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


def _points(pose: Any, p: Vector) -> np.ndarray:
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
                "RS530",
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


def _moving(run: CheckRun, sim: Sim) -> Finding:
    """The random actions of ``checks.random_actions`` in the first mode, from the first
    keyframe: the largest distance each loop opens to."""
    loops = run.robot.loops
    settings = run.settings.random_actions
    start = run.robot.keyframes[0] if run.robot.keyframes else None
    rng = np.random.default_rng(settings.seed)
    low = np.where(np.isfinite(sim.action_low), sim.action_low, -1.0)
    high = np.where(np.isfinite(sim.action_high), sim.action_high, 1.0)
    sim.start(start)
    worst = np.zeros(len(loops))
    for _ in range(settings.steps):
        sim.step(rng.uniform(low, high))
        now = gaps(sim, loops)
        if not np.all(np.isfinite(now)):
            break  # NaN: random_actions says why (RS502)
        worst = np.maximum(worst, now)
    limit = run.settings.loops.max_gap
    subject = f"{settings.steps} random steps"
    details = tuple(
        metrics(loop=loop.name, gap=float(g)) for loop, g in zip(loops, worst, strict=True)
    )
    opened = [(loop, g) for loop, g in zip(loops, worst, strict=True) if g > limit]
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
    diagnostics = tuple(
        run.fail(
            ("loops", loop.name),
            "RS531",
            f"loop '{loop.name}' pulls apart under random actions in mode '{sim.mode}': its "
            f"two points {g * 1000:.1f} mm apart (more than max_gap {limit * 1000:g} mm)",
            "drive the linkage more gently (a lower force_limit on its driver), or give the "
            "solver more iterations (simulation.solver_position_iterations)",
        )
        for loop, g in opened
    )
    summary = ", ".join(f"{loop.name} opened {g * 1000:.1f} mm" for loop, g in opened)
    return Finding(
        NAME, sim.mode, subject, Status.FAIL, summary, _worst(worst), diagnostics, details
    )


def _worst(apart: np.ndarray) -> dict[str, float | int | str | bool | None]:
    return metrics(max_gap=float(np.max(apart)) if len(apart) else 0.0)
