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

Passing: every mode of the Panda: 60 random actions keep every joint finite, inside its limits
and slower than ``max_joint_speed``.
Failing: ``fixed_inspire_hand_right``: its URDF gives the finger joints ``<mimic>`` tags and no
mimic controller drives them, so the hand goes NaN within a few steps (RS502, naming them).
"""

from __future__ import annotations

import numpy as np

from robospec.diagnostics import Diagnostic, warning
from robospec.physics import ground
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.nan_cause import nan_cause
from robospec.physics.sim import Sim
from robospec.resolve.resolved import ResolvedKeyframe

NAME = "random_actions"


def check(run: CheckRun) -> list[Finding]:
    starts: list[ResolvedKeyframe | None] = [None, *run.context.robot.keyframes[:1]]
    if ground.load_skipped(run, None):
        starts = starts[1:]
    return [_run_mode(run, run.sim(mode), start) for mode in run.modes for start in starts]


def _run_mode(run: CheckRun, sim: Sim, start: ResolvedKeyframe | None) -> Finding:
    settings = run.settings.random_actions
    rng = np.random.default_rng(settings.seed)
    low = np.where(np.isfinite(sim.action_low), sim.action_low, -1.0)
    high = np.where(np.isfinite(sim.action_high), sim.action_high, 1.0)
    sim.start(start)
    lower = sim.limits[:, 0] - settings.joint_limit_tolerance
    upper = sim.limits[:, 1] + settings.joint_limit_tolerance
    n_joints = len(sim.joint_names)
    past_limit = np.zeros(n_joints)  # how far past its limit (+ tolerance) each joint went
    top_speed = np.zeros(n_joints)
    top_root_speed = 0.0
    nan_step: int | None = None
    nan_joints: list[str] = []
    steps_run = 0
    # a mounted robot's random targets drive it into the floor it stands on: what a joint does
    # while its links press on the ground is the floor's doing (watched on the CPU only)
    watch_ground = sim.fixed_root and not sim.backend.gpu
    grounded = np.zeros(n_joints, dtype=bool)  # each joint's worst excess came with the floor
    moved = [sim.moved_by(name) for name in sim.joint_names] if watch_ground else []
    for step in range(settings.steps):
        sim.step(rng.uniform(low, high, size=(sim.backend.num_envs, low.size)))
        steps_run = step + 1
        qpos, qvel = sim.qpos(), sim.qvel()
        bad = ~(np.isfinite(qpos) & np.isfinite(qvel)).all(axis=0)
        if bad.any() or not np.isfinite(sim.root_position()).all():
            nan_step = step + 1
            nan_joints = [name for name, b in zip(sim.joint_names, bad, strict=True) if b]
            break
        excess = limit_excess(qpos, lower, upper)
        worse = excess > past_limit
        if watch_ground and (worse & (excess > 0)).any():
            touching = {link for link, _, _ in sim.ground_contacts()}
            for j in np.nonzero(worse)[0]:
                grounded[j] = bool(touching & moved[j])
        past_limit = np.maximum(past_limit, excess)
        top_speed = np.maximum(top_speed, np.abs(qvel).max(axis=0))
        if not sim.fixed_root:
            top_root_speed = max(top_root_speed, float(sim.root_speed().max()))
    fastest = int(np.argmax(top_speed))
    values = metrics(
        steps=steps_run,
        seed=settings.seed,
        nan_step=nan_step,
        nan_joints=", ".join(nan_joints) if nan_joints else None,
        max_joint_speed=float(top_speed[fastest]),
        fastest_joint=sim.joint_names[fastest],
        max_limit_excess=float(max(past_limit.max(), 0.0)),
        max_root_speed=top_root_speed,
    )
    origin = f"from {start.name}" if start is not None else "from load"
    diagnostics = _problems(
        run,
        sim,
        origin,
        nan_step,
        nan_joints,
        past_limit,
        top_speed,
        top_root_speed,
        start,
        grounded,
    )
    if nan_step is not None:
        summary = f"NaN at step {nan_step} in {', '.join(nan_joints) or 'the root pose'}"
    else:
        summary = (
            f"{steps_run} steps: fastest {sim.joint_names[fastest]} "
            f"{top_speed[fastest]:.3g}/s, limits kept within {settings.joint_limit_tolerance:g}"
        )
    errors = any(d.is_error for d in diagnostics)
    status = Status.FAIL if errors else Status.INFO if diagnostics else Status.PASS
    if diagnostics and nan_step is None:
        summary = "; ".join(d.message.split(": ", 1)[-1] for d in diagnostics)
    return Finding(NAME, sim.mode, origin, status, summary, values, diagnostics)


def limit_excess(qpos: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """How far each joint is past its limits, shape ``(J,)`` from ``qpos`` ``(num_envs, J)``:
    above its upper limit or below its lower one, the worst environment; 0 inside (and for an
    unbounded side)."""
    excess = np.maximum(qpos - upper, lower - qpos).max(axis=0)
    return np.maximum(np.where(np.isfinite(excess), excess, 0.0), 0.0)


def _problems(
    run: CheckRun,
    sim: Sim,
    origin: str,
    nan_step: int | None,
    nan_joints: list[str],
    past_limit: np.ndarray,
    top_speed: np.ndarray,
    top_root_speed: float,
    start: ResolvedKeyframe | None,
    grounded: np.ndarray | None = None,
) -> tuple[Diagnostic, ...]:
    settings = run.settings.random_actions
    buried = ground.note(run, start)
    where = ("control_modes", sim.mode)
    found: list[Diagnostic] = []
    if nan_step is not None:
        known = nan_cause(run.context, sim.mode, [(g.name, g.controller) for g in sim.groups()])
        if known is not None:
            cause, hint = f"; the cause is {known.cause}", known.hint
        else:
            cause = ""
            hint = (
                "look for drives far stiffer than the links' inertia allows at the simulation "
                "frequency, zero-mass links, or joints without limits driven by large actions"
            )
        joints = ", ".join(nan_joints) if nan_joints else "the root pose"
        found.append(
            run.fail(
                where,
                "RS502",
                f"mode {sim.mode} ({origin}): random actions made the state NaN at step {nan_step} "
                f"(joints: {joints}){cause}{buried}",
                hint,
            )
        )
        return tuple(found)
    worst = int(np.argmax(past_limit))
    if past_limit[worst] > 0:
        went = (
            f"mode {sim.mode} ({origin}): joint '{sim.joint_names[worst]}' went "
            f"{past_limit[worst] + settings.joint_limit_tolerance:.3g} past its limit "
            f"(tolerance {settings.joint_limit_tolerance:g})"
        )
        if grounded is not None and grounded[worst] and not buried:
            # the floor, not the robot: random targets drove the mounted arm into it
            found.append(
                warning(
                    run.at(where),
                    "RS503",
                    went + " while the links it moves pressed on the ground: random targets "
                    "drove the mounted robot into the floor, which pushed the joint through "
                    "its limit",
                    "nothing to fix in the robot if it is mounted higher in its tasks; a "
                    "keyframe pose that lifts it (pose: {p: [0, 0, h]}) keeps it off the floor",
                )
            )
        else:
            found.append(
                run.fail(
                    where,
                    "RS503",
                    went + buried,
                    "the joint is carried past its limit: add damping to its controller (a "
                    "random target across its range flings it), lower its force_limit, or "
                    "narrow the controller's lower/upper to the joint's range",
                )
            )
    fastest = int(np.argmax(top_speed))
    if top_speed[fastest] > settings.max_joint_speed:
        found.append(
            run.fail(
                where,
                "RS504",
                f"mode {sim.mode} ({origin}): joint '{sim.joint_names[fastest]}' ran away at "
                f"{top_speed[fastest]:.3g}/s (max_joint_speed {settings.max_joint_speed:g})"
                f"{buried}",
                "add damping to the joint's controller, or lower its force_limit",
            )
        )
    if top_root_speed > settings.max_root_speed:
        found.append(
            run.fail(
                where,
                "RS504",
                f"mode {sim.mode} ({origin}): the robot ran away: its centre of mass reached "
                f"{top_root_speed:.3g} m/s "
                f"(max_root_speed {settings.max_root_speed:g}){buried}",
                "check the root's mass and the forces the controllers can apply",
            )
        )
    return tuple(found)
