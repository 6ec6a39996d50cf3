"""The second half of a scaffold's gains: measured in ManiSkill and changed where they miss
(run by :mod:`.probe`, in its child process, on the draft scaffold at its rest pose).

1. Each position or velocity controller of the draft's ``pd_joint_pos`` mode is stepped as
   ``robospec check`` steps it and searched by ``robospec tune``'s search
   (:class:`robospec.tune.search.Search`: coupled joints together, force limits never past the
   description's ratings) for targets with a margin inside check's thresholds (:func:`targets`:
   half its overshoot and steady-state error, settled within half the step's duration).
   Controllers that meet them keep the analytic gains.
2. The robot is then held at its rest keyframe as ``robospec check`` holds it (the keyframe
   as the draft resolves it, its root where the description places it): a fixed robot where
   it stands, a floating one on a test stand (its root held clear of the ground) and, where
   its statics say it can stand, standing on the ground. Joints that drift past a fifth of
   check's ``max_joint_drift`` get stiffer (damping kept at the same ratio), a few rounds at
   most; a rated joint's force limit stays its rating (a load past it fails step 1's search
   first, which says so: RS609).
3. Random actions from the rest keyframe, as check sends them (its seed and steps): joints that
   run faster than half check's ``max_joint_speed``, or past their limits by more than half
   its ``joint_limit_tolerance``, get more damping (up to a damping ratio of 2), a few rounds at
   most. Random joint targets jump across a joint's whole range; damping is what keeps that
   from flinging it. The controllers of the joints damped are then searched again from there,
   so that none is left too slow for check's step.
4. A robot with closed loops: random actions as check sends them to its loops (check's first
   control mode, from the rest keyframe, the refined gains; a floating robot on its test stand,
   where the floor cannot press on the linkage). PhysX solves a loop's drive with the joints,
   so a linkage whipped about (an xArm6 gripper on its arm: 1.6 mm at ManiSkill's 15 solver
   position iterations) opens; the articulation's iterations double until the loops stay
   within half of check's ``max_gap``, and the scaffold recommends that many
   (``simulation.solver_position_iterations``, what ``sim_config_for`` passes to
   ``gym.make``).

The answer is each joint's stiffness, damping and force limit, the joints whose gains need
more force than their rating (the scaffold keeps the rating and says so: RS609), and the solver
position iterations the loops need (None: ManiSkill's default holds them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from robospec.authoring.new.gains import HOLD_SHARE  # of check's max_joint_drift
from robospec.physics.findings import significant
from robospec.physics.sim import Sim
from robospec.resolve.resolved import ResolvedKeyframe, ResolvedLoop

if TYPE_CHECKING:
    from robospec.model.frozen import Checks
    from robospec.tune.results import Targets

HOLD_ROUNDS = 4
RANDOM_ROUNDS = 3
RANDOM_SHARE = 0.5  # of check's max_joint_speed / max_root_speed: what random actions may reach
DAMPING_RAISE = 2.0
# random actions raise a joint's damping ratio to this at most: overdamped past it, the joint
# gets too slow for check's step (at ratio 2 a step rises in about 8/w)
MAX_RANDOM_ZETA = 2.0
MAX_RAISE = 10.0  # one round raises a joint's stiffness at most this many times
# solver position iterations tried at most (ManiSkill's scenes' 15 doubled four times): past
# them, check says the loops open (RS531)
MAX_ITERATIONS = 240
LOOP_SHARE = 0.5  # of check's loops.max_gap: how far the loops may open


@dataclass
class Refined:
    """What the refinement found, by joint (stiffness, damping, force_limit)."""

    gains: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    over_rating: dict[str, tuple[float, float]] = field(default_factory=dict)  # (asked, rating)
    simulations: int = 0
    changed: list[str] = field(default_factory=list)  # the controllers whose gains changed
    solver_position_iterations: int | None = None  # what the loops need; None: the scene's


def refine(
    sim: Sim, checks: Checks, ratings: dict[str, float], keyframe: ResolvedKeyframe
) -> Refined:
    """Refine the gains of ``sim``'s mode (the draft's pd_joint_pos) at ``keyframe``.
    ``checks``: the draft's ``checks`` section (its defaults); ``ratings``: joint -> the most
    force its motor is rated for."""

    found = Refined()
    _search(sim, checks, keyframe, ratings, found)
    _hold(sim, checks, keyframe, found, ratings)
    damped = _random(sim, checks, keyframe, found)
    if damped:
        # the damping random actions asked for may leave a joint too slow for check's step:
        # search those controllers again from where they are now (stiffer, as damped)
        _search(sim, checks, keyframe, ratings, found, only=damped)
    return found


def _search(
    sim: Sim,
    checks: Checks,
    keyframe: ResolvedKeyframe,
    ratings: dict[str, float],
    found: Refined,
    only: set[str] | None = None,
) -> None:
    """tune's search on each position or velocity controller of ``sim``'s mode (``only``: the
    groups holding these joints, started from their gains in ``found``)."""
    from robospec.tune.results import Gains
    from robospec.tune.search import Search

    for group in sim.groups():
        if group.kind not in ("position", "velocity") or not group.joint_indices:
            continue
        names = [sim.joint_names[j] for j in group.joint_indices]
        if only is not None and not only & set(names):
            continue
        initial = None
        if only is not None and all(name in found.gains for name in names):
            initial = Gains(*(tuple(found.gains[name][i] for name in names) for i in range(3)))
        caps = np.array([ratings.get(name, np.inf) for name in names])
        search = Search(
            sim,
            group.name,
            group.name,
            keyframe,
            checks.step_response.for_controller(group.name),
            targets(checks, group.name),
            force_caps=caps,
            initial=initial,
        )
        result = search.run()
        found.simulations += search.simulations
        after = result.after
        if after is None:
            continue
        if result.changed and group.name not in found.changed:
            found.changed.append(group.name)
        for k, name in enumerate(names):
            found.gains[name] = (
                significant(after.stiffness[k]),
                significant(after.damping[k]),
                significant(after.force_limit[k]),
            )
        missing = {joint for joint, _ in result.reasons}
        for joint, asked, rating in result.over_rating:
            if joint in missing:  # held at its rating, it misses the targets: say so
                found.over_rating[joint] = (asked, rating)


def targets(checks: Checks, controller: str) -> Targets:
    """What the refinement aims for: inside ``robospec check``'s thresholds by a margin (half
    its overshoot and steady-state error; settled within half the step's duration, which also
    keeps the rise well under max_rise_time), not tune's tighter defaults — a scaffold's gains
    need to work, and stiffer gains would ask more of motors than their ratings give."""
    from robospec.tune.results import Targets

    step = checks.step_response.for_controller(controller)
    return Targets(
        max_overshoot=float(step.max_overshoot) / 2,
        max_settling_time=min(float(step.duration) / 2, float(step.max_rise_time)),
        max_steady_state_error=float(step.max_steady_state_error) / 2,
        keep_force_limit=False,
        settling_band=float(step.settling_band),
    )


def _apply(sim: Sim, gains: dict[str, tuple[float, float, float]]) -> None:
    """Give every group's drives ``gains`` (after ``Sim.start``, which builds them afresh)."""
    for group in sim.groups():
        if group.kind != "position":
            continue
        names = [sim.joint_names[j] for j in group.joint_indices]
        if not all(name in gains for name in names):
            continue
        k, d, f = (np.array([gains[name][i] for name in names]) for i in range(3))
        sim.set_drive(group, k, d, f)


def _hold(
    sim: Sim,
    checks: Checks,
    keyframe: ResolvedKeyframe,
    found: Refined,
    ratings: dict[str, float],
) -> None:
    """Stiffen the joints that drift while the robot holds its keyframe: a fixed robot where
    it is mounted; a floating one on a test stand, and standing where it can stand."""
    from robospec.physics.keyframe_hold import support_at

    allowed = HOLD_SHARE * float(checks.keyframe_hold.max_joint_drift)
    steps = int(checks.keyframe_hold.steps)
    standing = not sim.fixed_root and support_at(sim, keyframe).stands
    before: dict[str, float] = {}  # joint -> its drift before its last raise
    previous: dict[str, tuple[float, float, float]] = {}
    stuck: set[str] = set()  # joints more stiffness did not help: their drift is not a sag
    for round_ in range(HOLD_ROUNDS + 1):
        drift = _drift(sim, keyframe, found.gains, steps, pinned=True)
        if standing:
            drift = np.maximum(drift, _drift(sim, keyframe, found.gains, steps, pinned=False))
        found.simulations += 2 if standing else 1
        measured = dict(zip(sim.joint_names, (float(v) for v in drift), strict=True))
        for name, old in before.items():
            if not measured[name] < 0.7 * old:  # a sag falls as the stiffness rises
                found.gains[name] = previous[name]
                stuck.add(name)
        before.clear()
        worst = {
            name: value
            for name, value in measured.items()
            if name in found.gains
            and name not in stuck
            and value > allowed
            and math.isfinite(value)
        }
        if not worst or round_ == HOLD_ROUNDS:  # the last round only measures
            return
        for name, value in worst.items():
            k, d, f = previous[name] = found.gains[name]
            before[name] = value
            raise_by = min(max(value / allowed, 1.5), MAX_RAISE)
            found.gains[name] = (
                significant(k * raise_by),
                significant(d * math.sqrt(raise_by)),
                f if name in ratings else significant(f * raise_by),  # a rating stays
            )
        if "hold" not in found.changed:
            found.changed.append("hold")


def _drift(
    sim: Sim,
    keyframe: ResolvedKeyframe,
    gains: dict[str, tuple[float, float, float]],
    steps: int,
    pinned: bool,
) -> np.ndarray:
    """Each joint's largest distance from the keyframe while the drives hold it."""
    start = sim.start(keyframe)
    _apply(sim, gains)
    sim.hold_drive_targets()
    # as robospec check holds it: a floating root on its test stand, a fixed one where it is
    pin = sim.test_stand() if pinned and not sim.fixed_root else None
    drift = np.zeros(len(sim.joint_names))
    for _ in range(steps * (sim.sim_freq // sim.control_freq)):
        sim.sim_step(pin)
        qpos = sim.qpos()
        if not np.isfinite(qpos).all():
            return np.full(len(sim.joint_names), np.inf)
        drift = np.maximum(drift, np.abs(qpos - start).max(axis=0))
    return drift


def _random(sim: Sim, checks: Checks, keyframe: ResolvedKeyframe, found: Refined) -> set[str]:
    """Damp the joints that random actions fling (see the module's doc, 3); the joints it
    damped."""
    settings = checks.random_actions
    damped: set[str] = set()
    inertia: dict[str, float] = {}
    sim.start(keyframe)
    for group in sim.groups():
        if group.kind == "position" and group.joint_indices:
            for index, value in zip(group.joint_indices, sim.inertia(group), strict=True):
                inertia[sim.joint_names[index]] = float(value)
    for _ in range(RANDOM_ROUNDS):
        speeds, excess = _random_speeds(sim, keyframe, found.gains, settings)
        found.simulations += 1
        limit = RANDOM_SHARE * float(settings.max_joint_speed)
        past = RANDOM_SHARE * float(settings.joint_limit_tolerance)
        fast = [
            name
            for name, speed, over in zip(sim.joint_names, speeds, excess, strict=True)
            if name in found.gains and not (speed <= limit and over <= past)
        ]
        if not fast:
            return damped
        raised = False
        for name in fast:
            k, d, f = found.gains[name]
            ceiling = 2.0 * MAX_RANDOM_ZETA * math.sqrt(k * inertia.get(name, 0.0))
            new = significant(min(d * DAMPING_RAISE, max(ceiling, d)))
            if new > d:
                found.gains[name] = (k, new, f)
                damped.add(name)
                raised = True
        if not raised:
            return damped
        if "random actions" not in found.changed:
            found.changed.append("random actions")
    return damped


def _random_speeds(
    sim: Sim,
    keyframe: ResolvedKeyframe,
    gains: dict[str, tuple[float, float, float]],
    settings: Any,
    iterations: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Each joint's top speed, and how far past its limits it went, under check's random
    actions from ``keyframe`` (``iterations``: solver position iterations, if not the
    scene's)."""
    from robospec.physics.random_actions import limit_excess, random_draws

    draw = random_draws(sim, settings.seed)
    sim.start(keyframe)
    _apply(sim, gains)
    if iterations is not None:
        sim.set_solver_position_iterations(iterations)
    top = np.zeros(len(sim.joint_names))
    excess = np.zeros(len(sim.joint_names))
    lower, upper = sim.limits[:, 0], sim.limits[:, 1]
    for _ in range(int(settings.steps)):
        sim.step(draw())
        qpos, qvel = sim.qpos(), sim.qvel()
        if not np.isfinite(qvel).all() or not np.isfinite(qpos).all():
            broken = np.full(len(sim.joint_names), np.inf)
            return broken, broken
        top = np.maximum(top, np.abs(qvel).max(axis=0))
        excess = np.maximum(excess, limit_excess(qpos, lower, upper))
    return top, excess


def loop_iterations(
    first: Sim,
    driven: Sim,
    checks: Checks,
    keyframe: ResolvedKeyframe,
    loops: tuple[ResolvedLoop, ...],
    found: Refined,
) -> None:
    """Step 4 (the module's doc): the solver position iterations ``loops`` need in ``first``'s
    mode (check's first), into ``found``, where random actions in ``driven``'s (the draft's
    pd_joint_pos) stay inside check's bounds with as many. None where the scene's own hold
    them, where even :data:`MAX_ITERATIONS` do not, or where the iterations that do fling a
    joint (gym-xarm's xArm7 blew up at 3.97e+31 rad): check then says how far they open
    (RS531)."""
    limit = LOOP_SHARE * float(checks.loops.max_gap)
    scene = first.solver_position_iterations()  # what the scene solves it with, as built
    iterations = scene
    while iterations <= MAX_ITERATIONS:
        found.simulations += 1
        if loop_gap(first, checks, keyframe, loops, found.gains, iterations) <= limit:
            if iterations > scene and _calm(driven, checks, keyframe, found, iterations):
                found.solver_position_iterations = iterations
            return
        iterations *= 2


def _calm(
    sim: Sim, checks: Checks, keyframe: ResolvedKeyframe, found: Refined, iterations: int
) -> bool:
    """Whether check's random actions in ``sim``'s mode keep every joint inside check's own
    bounds (``max_joint_speed``, ``joint_limit_tolerance``) with ``iterations``."""
    settings = checks.random_actions
    found.simulations += 1
    speeds, excess = _random_speeds(sim, keyframe, found.gains, settings, iterations)
    return bool(
        np.all(speeds <= float(settings.max_joint_speed))
        and np.all(excess <= float(settings.joint_limit_tolerance))
    )


def loop_gap(
    sim: Sim,
    checks: Checks,
    keyframe: ResolvedKeyframe,
    loops: tuple[ResolvedLoop, ...],
    gains: dict[str, tuple[float, float, float]],
    iterations: int,
) -> float:
    """The widest any loop opens under check's random actions from ``keyframe``, the robot
    solved with ``iterations`` position iterations."""
    from robospec.physics.loops import gaps
    from robospec.physics.random_actions import random_draws

    settings = checks.random_actions
    draw = random_draws(sim, settings.seed)
    sim.start(keyframe)
    _apply(sim, gains)
    sim.set_solver_position_iterations(iterations)
    pin = None if sim.fixed_root else sim.test_stand()
    widest = 0.0
    for _ in range(int(settings.steps)):
        sim.step(draw(), pin)
        now = gaps(sim, loops)
        if not np.isfinite(now).all():
            return float("inf")
        widest = max(widest, float(now.max()))
    return widest
