"""RS502: the state goes NaN or infinite under random actions. RS503: a joint goes past its
limit. RS504: a joint or the robot (its centre of mass) runs away. Each control mode gets
``checks.random_actions.steps`` uniformly random actions within its action space (bounds of ±1
where a bound is infinite),
once from the state the robot is loaded in (qpos 0, where an environment that sets no keyframe
leaves it; clamped into the joint limits) and once from the first keyframe.

A NaN names the joints it appeared in and, when the robot's description gives a joint a URDF
``<mimic>`` tag that no ``pd_joint_pos_mimic`` controller drives in that mode, says that this
is the cause: SAPIEN turns the tag into a PhysX mimic joint, which alone goes NaN within a few
CPU steps.

A joint carried past its limit (or flung past ``max_joint_speed``) while the floor presses on a
link it moves is a warning, not a failure, where the same actions with the robot held clear of
the floor on a test stand keep it inside: random targets drive a mounted arm into its floor,
and topple a free-standing robot onto links never made to carry it (TALOS lands on a 26 g
fingertip, and its weight pushes the joint 1.5 rad through its limit). The links a free robot
stands on at the start excuse nothing: a knee buckling under the robot's weight is its failure.

Passing: every mode of the Panda: 60 random actions keep every joint finite, inside its limits
and slower than ``max_joint_speed``.
Failing: ``fixed_inspire_hand_right``: its URDF gives the finger joints ``<mimic>`` tags and no
mimic controller drives them, so the hand goes NaN within a few steps (RS502, naming them).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import JOINT_LIMIT_VIOLATED, NAN_STATE, RUNAWAY_VELOCITY
from robospec.physics import ground
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.nan_cause import nan_cause
from robospec.physics.sim import Sim
from robospec.resolve.resolved import ResolvedKeyframe

if TYPE_CHECKING:
    from robospec.model.check_settings import RandomActions

NAME = "random_actions"


def check(run: CheckRun) -> list[Finding]:
    starts: list[ResolvedKeyframe | None] = [None, *run.context.robot.keyframes[:1]]
    if ground.load_skipped(run, None):
        starts = starts[1:]
    return [_run_mode(run, run.sim(mode), start) for mode in run.modes for start in starts]


@dataclass
class _Trace:
    """What one run of random actions did to each joint (arrays of shape ``(J,)``)."""

    steps_run: int
    past_limit: np.ndarray  # how far past its limit (+ tolerance) each joint went
    top_speed: np.ndarray
    top_root_speed: float
    nan_step: int | None
    nan_joints: list[str]
    grounded: np.ndarray  # each joint's worst excess came while the floor pressed on it
    flung: np.ndarray  # each joint's top speed (past max_joint_speed) did


def random_draws(sim: Sim, seed: int) -> Callable[[], np.ndarray]:
    """Check's random actions for ``sim``, one batch a call: uniform within its action space
    (±1 where a bound is infinite), one row per environment, drawn from ``seed`` — what
    random_actions, the loops check and new's refinement all send."""
    rng = np.random.default_rng(seed)
    low = np.where(np.isfinite(sim.action_low), sim.action_low, -1.0)
    high = np.where(np.isfinite(sim.action_high), sim.action_high, 1.0)
    return lambda: rng.uniform(low, high, size=(sim.backend.num_envs, low.size))


def _drive_randomly(
    run: CheckRun, sim: Sim, start: ResolvedKeyframe | None, on_stand: bool = False
) -> _Trace:
    """The random actions of ``checks.random_actions`` from ``start``; ``on_stand``: with the
    robot lifted clear of the floor, a free root held there (``Sim.test_stand``)."""
    settings = run.settings.random_actions
    draw = random_draws(sim, settings.seed)
    sim.start(start)
    pin = sim.test_stand() if on_stand else None
    lower = sim.limits[:, 0] - settings.joint_limit_tolerance
    upper = sim.limits[:, 1] + settings.joint_limit_tolerance
    n_joints = len(sim.joint_names)
    trace = _Trace(
        steps_run=0,
        past_limit=np.zeros(n_joints),
        top_speed=np.zeros(n_joints),
        top_root_speed=0.0,
        nan_step=None,
        nan_joints=[],
        grounded=np.zeros(n_joints, dtype=bool),
        flung=np.zeros(n_joints, dtype=bool),
    )
    # what a joint does while the floor presses on a link it moves may be the floor's doing
    floor = ground.FloorPress(sim, [sim.moved_by(name) for name in sim.joint_names], not on_stand)
    for step in range(settings.steps):
        sim.step(draw(), pin)
        trace.steps_run = step + 1
        qpos, qvel = sim.qpos(), sim.qvel()
        bad = ~(np.isfinite(qpos) & np.isfinite(qvel)).all(axis=0)
        if bad.any() or not np.isfinite(sim.root_position()).all():
            trace.nan_step = step + 1
            trace.nan_joints = [name for name, b in zip(sim.joint_names, bad, strict=True) if b]
            break
        excess = limit_excess(qpos, lower, upper)
        worse = excess > trace.past_limit
        speed = np.abs(qvel).max(axis=0)
        faster = (speed > trace.top_speed) & (speed > settings.max_joint_speed)
        pressed = floor.pressed(worse | faster)
        for j, on_floor in pressed.items():
            if worse[j]:
                trace.grounded[j] = on_floor
            if faster[j]:
                trace.flung[j] = on_floor
        trace.past_limit = np.maximum(trace.past_limit, excess)
        trace.top_speed = np.maximum(trace.top_speed, speed)
        if not sim.fixed_root and pin is None:
            trace.top_root_speed = max(trace.top_root_speed, float(sim.root_speed().max()))
    return trace


def _run_mode(run: CheckRun, sim: Sim, start: ResolvedKeyframe | None) -> Finding:
    settings = run.settings.random_actions
    trace = _drive_randomly(run, sim, start)
    held = None
    if trace.nan_step is None and (trace.grounded.any() or trace.flung.any()):
        # the floor is blamed only where the simulation confirms it: the same actions, the
        # robot held clear of the floor on a test stand, keep the joint inside its limits
        # (and slow enough); where they do not, the joint fails on its own
        held = _drive_randomly(run, sim, start, on_stand=True)
        ok = held.nan_step is None
        trace.grounded &= ok & (held.past_limit <= 0)
        trace.flung &= ok & (held.top_speed <= settings.max_joint_speed)
    fastest = int(np.argmax(trace.top_speed))
    values = metrics(
        steps=trace.steps_run,
        seed=settings.seed,
        nan_step=trace.nan_step,
        nan_joints=", ".join(trace.nan_joints) if trace.nan_joints else None,
        max_joint_speed=float(trace.top_speed[fastest]),
        fastest_joint=sim.joint_names[fastest],
        max_limit_excess=float(max(trace.past_limit.max(), 0.0)),
        max_root_speed=trace.top_root_speed,
    )
    origin = f"from {start.name}" if start is not None else "from load"
    diagnostics = _problems(run, sim, origin, start, trace, held)
    if trace.nan_step is not None:
        where = ", ".join(trace.nan_joints) or "the root pose"
        summary = f"NaN at step {trace.nan_step} in {where}"
    else:
        summary = (
            f"{trace.steps_run} steps: fastest {sim.joint_names[fastest]} "
            f"{trace.top_speed[fastest]:.3g}/s, limits kept within "
            f"{settings.joint_limit_tolerance:g}"
        )
    errors = any(d.is_error for d in diagnostics)
    status = Status.FAIL if errors else Status.INFO if diagnostics else Status.PASS
    if diagnostics and trace.nan_step is None:
        summary = "; ".join(d.message.split(": ", 1)[-1] for d in diagnostics)
    return Finding(NAME, sim.mode, origin, status, summary, values, diagnostics)


@dataclass(frozen=True)
class Runaway:
    """A bound of ``checks.random_actions`` that random actions broke: a joint carried past its
    limit by more than ``joint_limit_tolerance`` (RS503), a joint faster than
    ``max_joint_speed`` or a floating robot's centre of mass faster than ``max_root_speed``
    (RS504). What check fails a robot for, and scripts/demo tells."""

    code: str  # RS503 or RS504
    joint: int | None  # the joint's index; None: the robot's centre of mass
    value: float  # how far past the limit (the tolerance included), or how fast
    bound: float  # the tolerance, or the speed counted as a runaway

    def unit(self, prismatic: Sequence[bool]) -> str:
        if self.joint is None:
            return "m/s"
        length = "m" if prismatic[self.joint] else "rad"
        return length if self.code == JOINT_LIMIT_VIOLATED else f"{length}/s"

    def brief(self, names: Sequence[str], prismatic: Sequence[bool]) -> str:
        """``joint_14.0 at 3.48e+04 rad/s``, ``joint_15.0 1.62e+03 rad past its limit``."""
        unit = self.unit(prismatic)
        if self.joint is None:
            return f"centre of mass at {self.value:.3g} {unit}"
        if self.code == JOINT_LIMIT_VIOLATED:
            return f"{names[self.joint]} {self.value:.3g} {unit} past its limit"
        return f"{names[self.joint]} at {self.value:.3g} {unit}"

    def said(self, names: Sequence[str], prismatic: Sequence[bool]) -> str:
        """:meth:`brief`, with the bound it broke: ``... (max_joint_speed 200 rad/s)``."""
        unit = self.unit(prismatic)
        setting = {JOINT_LIMIT_VIOLATED: "joint_limit_tolerance"}.get(self.code, "max_joint_speed")
        if self.joint is None:
            setting = "max_root_speed"
        return f"{self.brief(names, prismatic)} ({setting} {self.bound:g} {unit})"


def runaways(
    past_limit: np.ndarray,
    top_speed: np.ndarray,
    top_root_speed: float,
    settings: RandomActions,
    excused_limit: np.ndarray | None = None,
    excused_speed: np.ndarray | None = None,
) -> list[Runaway]:
    """What ``checks.random_actions`` (``settings``) counts as running away, worst first of
    each kind: the joint furthest past its limit (``past_limit``: beyond the tolerance), the
    fastest joint, the centre of mass. A joint the floor ``excused`` comes after the robot's
    own failures (check then warns about it instead of failing the robot)."""
    tolerance = settings.joint_limit_tolerance
    none = np.zeros(len(past_limit), dtype=bool)
    found = []
    worst = _worst(past_limit, none if excused_limit is None else excused_limit, 0.0)
    if len(past_limit) and past_limit[worst] > 0:
        found.append(
            Runaway(JOINT_LIMIT_VIOLATED, worst, float(past_limit[worst]) + tolerance, tolerance)
        )
    bound = settings.max_joint_speed
    fastest = _worst(top_speed, none if excused_speed is None else excused_speed, bound)
    if len(top_speed) and top_speed[fastest] > bound:
        found.append(Runaway(RUNAWAY_VELOCITY, fastest, float(top_speed[fastest]), bound))
    if top_root_speed > settings.max_root_speed:
        found.append(
            Runaway(RUNAWAY_VELOCITY, None, float(top_root_speed), settings.max_root_speed)
        )
    return found


def limit_excess(qpos: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """How far each joint is past its limits, shape ``(J,)`` from ``qpos`` ``(num_envs, J)``:
    above its upper limit or below its lower one, the worst environment; 0 inside (and for an
    unbounded side)."""
    excess = np.maximum(qpos - upper, lower - qpos).max(axis=0)
    return np.maximum(np.where(np.isfinite(excess), excess, 0.0), 0.0)


def _worst(values: np.ndarray, excused: np.ndarray, threshold: float) -> int:
    """The joint with the largest of ``values``: of those the floor does not excuse, where
    one of them passes ``threshold`` (the robot's own failure is reported first)."""
    own = np.where(excused, 0.0, values)
    return int(np.argmax(own if own.max() > threshold else values))


def _floor_warning(run: CheckRun, sim: Sim, code: str, what: str, did: str) -> Diagnostic:
    """``what`` happened to a joint while the floor pressed on a link it moves: a warning that
    says how it came there (random targets drove a mounted robot into its floor, or toppled a
    free one onto a link not made to carry it) and that the robot has nothing to mend."""
    if sim.fixed_root:
        why = (
            " while the links it moves pressed on the ground: random targets drove the mounted "
            f"robot into the floor, which {did}"
        )
        hint = (
            "nothing to fix in the robot if it is mounted higher in its tasks; a keyframe pose "
            "that lifts it (pose: {p: [0, 0, h]}) keeps it off the floor"
        )
    else:
        why = (
            " while a link it moves, not one the robot stands on, pressed on the ground: random "
            f"actions toppled the free robot onto it, and the floor {did}"
        )
        hint = (
            "nothing to fix in the robot: its weight landed on a link not made to carry it; "
            "step_response and keyframe_hold check its drives with the root held"
        )
    confirmed = "; held clear of the floor on a test stand, the same actions do not"
    return warning(run.at(("control_modes", sim.mode)), code, what + why + confirmed, hint)


@dataclass(frozen=True)
class _Judging:
    """What each problem of one run of random actions reads."""

    run: CheckRun
    sim: Sim
    origin: str  # "from load" or "from <keyframe>"
    buried: str  # ground.note's words on a start buried in the floor ("" where it is not)
    held: _Trace | None  # the same actions on a test stand, where the floor was in question
    # the joints whose excess (speed) the floor excuses: the robot's own failures come first
    floor_limit: np.ndarray
    floor_speed: np.ndarray

    @property
    def where(self) -> tuple[str, str]:
        return ("control_modes", self.sim.mode)


def _problems(
    run: CheckRun,
    sim: Sim,
    origin: str,
    start: ResolvedKeyframe | None,
    trace: _Trace,
    held: _Trace | None,
) -> tuple[Diagnostic, ...]:
    """What ``trace`` (and ``held``, the same actions on a test stand, where the floor was
    in question) found."""
    settings = run.settings.random_actions
    buried = ground.note(run, start)
    if trace.nan_step is not None:
        return (_went_nan(run, sim, origin, trace, buried),)
    # the robot's own failures first: the floor's excuse covers only the joints it moved
    floor_limit = trace.grounded & (not buried)
    floor_speed = trace.flung & (not buried)
    judging = _Judging(run, sim, origin, buried, held, floor_limit, floor_speed)
    found: list[Diagnostic] = []
    for runaway in runaways(
        trace.past_limit, trace.top_speed, trace.top_root_speed, settings, floor_limit, floor_speed
    ):
        if runaway.joint is None:
            found.append(_root_ran_away(judging, runaway))
        elif runaway.code == JOINT_LIMIT_VIOLATED:
            found.append(_past_limit(judging, runaway, runaway.joint))
        else:
            found.append(_joint_ran_away(judging, runaway, runaway.joint))
    return tuple(found)


def _went_nan(run: CheckRun, sim: Sim, origin: str, trace: _Trace, buried: str) -> Diagnostic:
    """RS502: the state went NaN, with its cause where :func:`nan_cause` knows it."""
    known = nan_cause(run.context, sim.mode, [(g.name, g.controller) for g in sim.groups()])
    if known is not None:
        cause, hint = f"; the cause is {known.cause}", known.hint
    else:
        cause = ""
        hint = (
            "look for drives far stiffer than the links' inertia allows at the simulation "
            "frequency, zero-mass links, or joints without limits driven by large actions"
        )
    joints = ", ".join(trace.nan_joints) if trace.nan_joints else "the root pose"
    return run.fail(
        ("control_modes", sim.mode),
        NAN_STATE,
        f"mode {sim.mode} ({origin}): random actions made the state NaN at step "
        f"{trace.nan_step} (joints: {joints}){cause}{buried}",
        hint,
    )


def _root_ran_away(judging: _Judging, runaway: Runaway) -> Diagnostic:
    """RS504: the centre of mass of a floating robot ran away."""
    j = judging
    return j.run.fail(
        j.where,
        RUNAWAY_VELOCITY,
        f"mode {j.sim.mode} ({j.origin}): the robot ran away: its centre of mass reached "
        f"{runaway.value:.3g} m/s (max_root_speed {runaway.bound:g}){j.buried}",
        "check the root's mass and the forces the controllers can apply",
    )


def _past_limit(judging: _Judging, runaway: Runaway, joint: int) -> Diagnostic:
    """RS503: ``joint`` went past its limit (a warning where the floor pushed it there)."""
    j = judging
    tolerance = j.run.settings.random_actions.joint_limit_tolerance
    went = (
        f"mode {j.sim.mode} ({j.origin}): joint '{j.sim.joint_names[joint]}' went "
        f"{runaway.value:.3g} past its limit (tolerance {tolerance:g})"
    )
    if j.floor_limit[joint]:
        return _floor_warning(
            j.run, j.sim, JOINT_LIMIT_VIOLATED, went, "pushed the joint through its limit"
        )
    if j.held is not None and j.held.past_limit[joint] > 0:
        went += (
            "; held clear of the floor on a test stand, the same actions still take it "
            f"{j.held.past_limit[joint] + tolerance:.3g} past"
        )
    return j.run.fail(
        j.where,
        JOINT_LIMIT_VIOLATED,
        went + j.buried,
        "the joint is carried past its limit: add damping to its controller (a "
        "random target across its range flings it), lower its force_limit, or "
        "narrow the controller's lower/upper to the joint's range",
    )


def _joint_ran_away(judging: _Judging, runaway: Runaway, joint: int) -> Diagnostic:
    """RS504: ``joint`` ran faster than max_joint_speed (a warning where the floor flung it)."""
    j = judging
    ran_away = (
        f"mode {j.sim.mode} ({j.origin}): joint '{j.sim.joint_names[joint]}' ran away at "
        f"{runaway.value:.3g}/s (max_joint_speed {runaway.bound:g})"
    )
    if j.floor_speed[joint]:
        return _floor_warning(j.run, j.sim, RUNAWAY_VELOCITY, ran_away, "flung the joint")
    if (
        j.held is not None
        and j.held.top_speed[joint] > j.run.settings.random_actions.max_joint_speed
    ):
        ran_away += (
            "; held clear of the floor on a test stand, the same actions still run it "
            f"at {j.held.top_speed[joint]:.3g}/s"
        )
    return j.run.fail(
        j.where,
        RUNAWAY_VELOCITY,
        ran_away + j.buried,
        "add damping to the joint's controller, or lower its force_limit",
    )
