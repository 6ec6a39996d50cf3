"""RS505: a controller group tracks a small step too slowly (or never). RS506: it overshoots or
keeps oscillating. RS507: it settles too far from the target.

Each controller of the spec is stepped once, in the first mode that uses it: from the first
keyframe, with every other drive holding still, its joints' drive targets jump by
``checks.step_response.step`` (rad, or ``prismatic_step`` m; away from the nearer limit, or the
other way where a self-contact blocks that: :func:`step_trace`; never past the limit, so a
narrow range gets a smaller step, and a joint whose range leaves no room for a tenth of the step
is not stepped and is named in the finding) — or, for velocity controllers, its velocity
targets do. Every joint's response is timed: rise time
(10 % → 90 % of the step), overshoot, settling time (last exit from ``settling_band``) and the
steady-state error at the end of ``duration``, all measured from where the joint had settled
after half a second of holding (so a sag under gravity is not counted twice). This measures
the drives ManiSkill sets from the controller's stiffness, damping, force_limit and friction,
which every mode of that controller shares; passive groups and controllers that drive no joint
directly are skipped. The robot is lifted clear of the floor for the step (a floating robot held
by its root there), so the drives are timed as on a test stand: a floor an arm is mounted on
would block half its steps.

Passing: the Panda's arm (stiffness 1e3, damping 1e2) reaches 90 % of a 0.1 rad step in well
under 0.5 s and settles on it.
Failing: the same arm with ``stiffness: 1``: after 1 s the joints have covered only a few
percent of the step (RS505, with the numbers).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from robospec.diagnostics import Diagnostic
from robospec.diagnostics.codes import SETTLES_OFF_TARGET, TRACKS_TOO_SLOWLY, UNDERDAMPED
from robospec.physics import mimic_limits, rating
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Metric, Status, metrics
from robospec.physics.sim import ControllerGroup, Sim
from robospec.resolve.resolved import ResolvedKeyframe

if TYPE_CHECKING:
    from mani_skill.utils.structs import Pose

    from robospec.model.check_settings import StepResponse

NAME = "step_response"
SETTLE_TIME = 0.5  # seconds of holding before the step
# a joint whose range leaves less than this share of the step (towards its farther limit) is
# not stepped: a step that small is lost in the sag and the noise it is measured against
MIN_STEP_SHARE = 0.1


class StepSettings(Protocol):
    """What the measurement reads of ``checks.step_response`` (for one controller)."""

    @property
    def step(self) -> float: ...
    @property
    def prismatic_step(self) -> float: ...
    @property
    def duration(self) -> float: ...
    @property
    def settling_band(self) -> float: ...


@dataclass(frozen=True)
class Response:
    """One joint's response to a step, times in seconds, sizes as fractions of the step."""

    joint: str
    rise_time: float | None  # None: never reached 90 %
    overshoot: float
    settling_time: float | None  # None: still outside the band at the end
    steady_state_error: float
    reached: float  # the largest fraction of the step covered
    # not stepped: its range leaves no room for a measurable step (the other values mean
    # nothing then)
    no_room: bool = False


def measure(
    trace: np.ndarray, dt: float, band: float
) -> tuple[float | None, float, float | None, float, float]:
    """Rise time, overshoot, settling time, steady-state error and the largest fraction reached,
    from ``trace``: the response as a fraction of the step (0 at the start, 1 on target), one
    value per physics step."""
    times = (np.arange(trace.size) + 1) * dt
    above_10 = np.nonzero(trace >= 0.1)[0]
    above_90 = np.nonzero(trace >= 0.9)[0]
    rise = float(times[above_90[0]] - times[above_10[0]]) if above_90.size else None
    overshoot = max(float(trace.max()) - 1.0, 0.0)
    outside = np.nonzero(np.abs(trace - 1.0) > band)[0]
    if outside.size == 0:
        settling: float | None = 0.0
    elif outside[-1] == trace.size - 1:
        settling = None
    else:
        settling = float(times[outside[-1] + 1])
    tail = trace[-max(trace.size // 10, 1) :]
    steady = abs(1.0 - float(tail.mean()))
    return rise, overshoot, settling, steady, float(trace.max())


def check(run: CheckRun) -> list[Finding]:
    findings = []
    seen: set[str] = set()
    for mode in run.modes:
        sim = run.sim(mode)
        for group in sim.groups():
            controller = run.controller_name(mode, group.name)
            if controller in seen:
                continue
            seen.add(controller)
            subject = f"{group.name} ({controller})" if controller != group.name else group.name
            if group.kind not in ("position", "velocity") or not group.joint_indices:
                findings.append(
                    Finding(NAME, mode, subject, Status.SKIP, f"{group.kind} controller: no step")
                )
                continue
            findings.append(_step(run, sim, group, controller, subject))
    return findings


def _step(
    run: CheckRun, sim: Sim, group: ControllerGroup, controller: str, subject: str
) -> Finding:
    settings = run.settings.step_response.for_controller(controller)
    trace = step_trace(sim, group.name, run.keyframes[0], settings)
    if run.plot_dir is not None:
        from robospec.physics.plot import Limits, plot_controller

        limits = Limits(float(settings.settling_band))
        plot_controller(run.plot_dir, run.uid, controller, [("step response", trace)], limits)
    return _finding(
        run, sim, sim.group(group.name), controller, subject, list(trace.responses), trace
    )


@dataclass(frozen=True)
class Drive:
    """Drive gains to measure with instead of the controller's, one value per joint of the
    group (``force_limit`` None: the controller's)."""

    stiffness: np.ndarray
    damping: np.ndarray
    force_limit: np.ndarray | None = None


@dataclass(frozen=True)
class StepTrace:
    """One step of a controller group, as measured: every joint's trace and its timings."""

    kind: str  # "position" or "velocity"
    joints: tuple[str, ...]
    dt: float  # seconds per sample (a physics step)
    fraction: np.ndarray  # (samples, joints): the response as a fraction of the step
    size: np.ndarray  # (joints,): the step, in rad or m (rad/s or m/s), signed
    target: np.ndarray  # (joints,): the commanded position (or velocity)
    position: np.ndarray  # (samples, joints): joint positions
    velocity: np.ndarray  # (samples, joints): joint velocities
    responses: tuple[Response, ...]
    # joints stepped towards their nearer limit: the other way, a self-contact blocked them
    reversed: tuple[str, ...] = ()


@dataclass(frozen=True)
class _Plan:
    """The step one group's joints are given, one value per joint of the group."""

    signed: np.ndarray  # the step, signed (0: not stepped)
    no_room: np.ndarray  # bool: the range leaves no room for a measurable step
    origin: np.ndarray  # where the joint settled (position, or velocity): the step's zero
    target: np.ndarray  # the drive target the step sets


def step_trace(
    sim: Sim,
    group_name: str,
    keyframe: ResolvedKeyframe | None,
    settings: StepSettings,
    drive: Drive | None = None,
    stepped: np.ndarray | None = None,
    reverse: np.ndarray | None = None,
) -> StepTrace:
    """Step controller group ``group_name`` of ``sim`` and time each of its joints: the one
    measurement of ``robospec check`` and ``robospec tune``. From ``keyframe`` in a fresh scene,
    every drive holds still for :data:`SETTLE_TIME` (a floating robot held by its root, lifted
    clear of the floor), then the group's drive targets jump by ``settings.step`` (rad, or
    ``prismatic_step`` m, away from the nearer limit, at most to the farther one: a joint
    with less room than :data:`MIN_STEP_SHARE` of the step holds, its response marked
    ``no_room``) and the joints are watched for
    ``settings.duration``. ``drive`` gives the group other gains first (``Sim.set_drive``);
    ``stepped`` (one bool per joint of the group) steps only some joints, the rest holding.

    A joint whose step a self-contact blocks (it stays short of 90 % while a link it moves
    touches one it does not) is stepped again the other way where its limits leave room
    (``reverse``, one bool per joint): the step asks how fast the drive is, and a pose whose
    links just clear each other (a humanoid's feet side by side) blocks a step one way only.
    The trace that reaches further is the answer; it names the joints it reversed."""
    start = sim.start(keyframe)
    group = sim.group(group_name)  # the controller of the scene start() built
    if drive is not None:
        sim.set_drive(group, drive.stiffness, drive.damping, drive.force_limit)
    sim.hold_drive_targets()
    joints = list(group.joint_indices)
    # on a test stand: lifted clear of the ground (a floating root held there), so nothing
    # but the drives shapes the step — an arm mounted on the floor would hit it half the time
    pin = sim.test_stand()
    # settle first: under gravity a holding drive sags to an equilibrium; the step is measured
    # from there, so the sag itself (keyframe_hold's business) is not counted as step error
    for _ in range(round(SETTLE_TIME * sim.sim_freq)):
        sim.sim_step(pin)
    plan = _plan_step(sim, group, start[joints], settings, stepped, reverse)
    sim.set_joint_targets(group, plan.target)
    position, velocity = _watch(sim, pin, joints, settings.duration)
    measured = position if group.kind == "position" else velocity
    with np.errstate(divide="ignore", invalid="ignore"):
        fraction = (measured - plan.origin) / np.where(plan.signed != 0, plan.signed, np.nan)
    fraction = np.where(np.isfinite(fraction), fraction, np.nan)
    trace = StepTrace(
        kind="velocity" if group.kind == "velocity" else "position",
        joints=tuple(sim.joint_names[j] for j in joints),
        dt=sim.sim_dt,
        fraction=fraction,
        size=plan.signed,
        target=np.asarray(plan.target, dtype=np.float64),
        position=position,
        velocity=velocity,
        responses=_responses(sim, joints, fraction, plan.no_room, stepped, settings),
        reversed=tuple(
            sim.joint_names[j] for k, j in enumerate(joints) if reverse is not None and reverse[k]
        ),
    )
    if reverse is not None or group.kind != "position" or sim.backend.gpu:
        return trace
    blocked = _blocked_joints(sim, trace, start[joints], plan.signed)
    if not blocked.any():
        return trace
    again = step_trace(sim, group_name, keyframe, settings, drive, stepped, reverse=blocked)
    return again if _reached(again) > _reached(trace) else trace


def _plan_step(
    sim: Sim,
    group: ControllerGroup,
    start: np.ndarray,
    settings: StepSettings,
    stepped: np.ndarray | None,
    reverse: np.ndarray | None,
) -> _Plan:
    """The step of :func:`step_trace` for ``group``'s joints, which start at ``start`` (the
    keyframe) and have settled where the sim now holds them."""
    joints = list(group.joint_indices)
    size = np.where(sim.prismatic[joints], settings.prismatic_step, settings.step)
    lower, upper = sim.limits[joints, 0], sim.limits[joints, 1]
    direction = step_direction(start, lower, upper)
    if reverse is not None:
        direction = np.where(reverse, -direction, direction)
    no_room = np.zeros(len(joints), dtype=bool)
    if group.kind == "position":
        # the target stays within the joint's limits (a ±0.06 rad ankle is not given a 0.1 rad
        # step, then called too slow for not reaching past its stop); a range with no room for
        # a measurable share of the step leaves the joint unstepped, and the trace says so
        room = np.where(direction > 0, upper - start, start - lower)
        no_room = room < MIN_STEP_SHARE * size
        size = np.where(no_room, 0.0, np.minimum(size, room))
    signed = direction * size
    if stepped is not None:
        signed = np.where(stepped, signed, 0.0)
        no_room &= stepped
    if group.kind == "position":
        origin = sim.qpos()[0, joints]
        # the joints not stepped (or without room for a step) hold where they settled
        target = np.where(signed != 0, start + signed, origin)
    else:
        origin = sim.qvel()[0, joints]
        target = signed
    return _Plan(signed, no_room, origin, target)


def _watch(
    sim: Sim, pin: Pose | None, joints: list[int], duration: float
) -> tuple[np.ndarray, np.ndarray]:
    """The positions and velocities of ``joints`` (samples, joints), one sample per physics
    step for ``duration`` seconds (at least two), the root held at ``pin``."""
    n_steps = max(round(duration * sim.sim_freq), 2)
    position = np.empty((n_steps, len(joints)))
    velocity = np.empty((n_steps, len(joints)))
    for i in range(n_steps):
        sim.sim_step(pin)
        position[i] = sim.qpos()[0, joints]
        velocity[i] = sim.qvel()[0, joints]
    return position, velocity


def _responses(
    sim: Sim,
    joints: list[int],
    fraction: np.ndarray,
    no_room: np.ndarray,
    stepped: np.ndarray | None,
    settings: StepSettings,
) -> tuple[Response, ...]:
    """Each stepped joint's timings, from ``fraction`` (samples, joints)."""
    responses = []
    for k, joint in enumerate(joints):
        name = sim.joint_names[joint]
        if stepped is not None and not stepped[k]:
            continue
        if no_room[k]:
            responses.append(Response(name, None, 0.0, None, 0.0, 0.0, no_room=True))
            continue
        if np.isnan(fraction[:, k]).any():
            responses.append(Response(name, None, float("nan"), None, float("nan"), float("nan")))
            continue
        rise, overshoot, settling, steady, reached = measure(
            fraction[:, k], sim.sim_dt, settings.settling_band
        )
        responses.append(Response(name, rise, overshoot, settling, steady, reached))
    return tuple(responses)


def _blocked_joints(
    sim: Sim, trace: StepTrace, start: np.ndarray, signed: np.ndarray
) -> np.ndarray:
    """The joints of ``trace`` (one bool each) that have room for the step the other way and
    either are short of 90 % of their step with a contact holding them back, or move a link of
    such a contact: the joints of a group step together, and the one held back is often not
    the one that drove its link into the other (DeepMimic's right hip turned the leg into the
    left one, and its ankle came up short: turning the ankle back alone found the leg still
    pressed against the other whichever way the ankle went)."""
    joints = [sim.joint_names.index(name) for name in trace.joints]
    lower, upper = sim.limits[joints, 0], sim.limits[joints, 1]
    room = np.where(signed > 0, start - signed >= lower, start - signed <= upper)
    short = {r.joint for r in trace.responses if not r.reached >= 0.9}
    held = {name: _blocking_contacts(sim, name) for name in trace.joints if name in short}
    pairs = {pair for found in held.values() for pair in found}

    def drives_into(name: str) -> bool:
        moved = sim.moved_by(name)
        return any((a in moved) != (b in moved) for a, b in pairs)

    return np.array(
        [
            bool(room[k]) and signed[k] != 0 and (bool(held.get(name)) or drives_into(name))
            for k, name in enumerate(trace.joints)
        ],
        dtype=bool,
    )


def _reached(trace: StepTrace) -> float:
    """How far a trace's joints got, all told (NaN counts as nothing)."""
    return float(sum(min(np.nan_to_num(r.reached, nan=0.0), 1.0) for r in trace.responses))


def step_direction(start: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """+1 or -1 per joint: a step goes away from the nearer limit (towards the farther one),
    so that a joint resting near a limit is stepped where it has room to move."""
    return np.where(upper - start >= start - lower, 1.0, -1.0)


@dataclass(frozen=True)
class _Verdict:
    """What each verdict of one controller's step finding reads."""

    run: CheckRun
    sim: Sim
    group: ControllerGroup
    controller: str
    kind: str  # "position" or "velocity"
    settings: StepResponse  # for this controller
    trace: StepTrace | None

    @property
    def where(self) -> tuple[str, str]:
        return ("controllers", self.controller)


@dataclass(frozen=True)
class _Extremes:
    """The joints that decide the finding: each the worst of the group at one measure."""

    slowest: Response
    wildest: Response
    furthest: Response


class _Bound:
    """Whether gravity holds a joint at its rating through the step (RS534, said once for the
    finding instead of a verdict on its gains); each RS534 goes into ``problems`` as found."""

    def __init__(self, verdict: _Verdict, problems: list[Diagnostic]) -> None:
        self.verdict = verdict
        self.problems = problems
        self.rated: dict[str, Diagnostic | None] = {}

    def __call__(self, joint: str) -> bool:
        v = self.verdict
        if joint not in self.rated:
            rated = _rated(v.run, v.sim, v.group, v.controller, v.trace, joint, v.kind)
            self.rated[joint] = rated
            if rated is not None:
                self.problems.append(rated)
        return self.rated[joint] is not None


def _finding(
    run: CheckRun,
    sim: Sim,
    group: ControllerGroup,
    controller: str,
    subject: str,
    responses: list[Response],
    trace: StepTrace | None = None,
) -> Finding:
    settings = run.settings.step_response.for_controller(controller)
    kind = "velocity" if group.kind == "velocity" else "position"
    verdict = _Verdict(run, sim, group, controller, kind, settings, trace)
    cramped = [r.joint for r in responses if r.no_room]
    responses = [r for r in responses if not r.no_room]
    unstepped = (
        f"; not stepped, their range leaves no room for a step: {', '.join(cramped)}"
        if cramped
        else ""
    )
    if not responses:
        return Finding(NAME, sim.mode, subject, Status.SKIP, f"no {kind} step{unstepped}")
    broken = [r.joint for r in responses if not np.isfinite(r.reached)]
    if broken:
        return _nan_finding(verdict, subject, broken)
    slowest = max(responses, key=lambda r: (r.rise_time is None, r.rise_time or 0.0, -r.reached))
    wildest = max(
        responses, key=lambda r: (np.nan_to_num(r.overshoot, nan=np.inf), r.settling_time is None)
    )
    furthest = max(responses, key=lambda r: np.nan_to_num(r.steady_state_error, nan=np.inf))
    extremes = _Extremes(slowest, wildest, furthest)
    values, details, summary = _measures(kind, responses, extremes, unstepped)
    problems: list[Diagnostic] = []
    bound = _Bound(verdict, problems)
    for judge in (_too_slow, _underdamped, _off_target):
        problem = judge(verdict, extremes, bound)
        if problem is not None:
            problems.append(problem)
    status = Status.FAIL if any(p.is_error for p in problems) else Status.PASS
    return Finding(NAME, sim.mode, subject, status, summary, values, tuple(problems), details)


def _nan_finding(verdict: _Verdict, subject: str, broken: list[str]) -> Finding:
    """RS506 for a step that made the state NaN (joints ``broken``)."""
    v = verdict
    diagnostic = v.run.fail(
        v.where,
        UNDERDAMPED,
        f"controller '{v.controller}' ({v.sim.mode}/{v.group.name}) is unstable: given a "
        f"{v.kind} step, the state went NaN (joints: {', '.join(broken)})",
        "see the random_actions findings of this robot for the cause",
    )
    return Finding(NAME, v.sim.mode, subject, Status.FAIL, f"{v.kind} step: NaN", {}, (diagnostic,))


def _measures(
    kind: str, responses: list[Response], extremes: _Extremes, unstepped: str
) -> tuple[dict[str, Metric], tuple[dict[str, Metric], ...], str]:
    """The finding's metrics (the group's worst), one set per joint, and its summary line."""
    slowest, wildest, furthest = extremes.slowest, extremes.wildest, extremes.furthest
    settled = [r.settling_time for r in responses]
    values = metrics(
        kind=kind,
        rise_time=slowest.rise_time,
        slowest_joint=slowest.joint,
        overshoot=wildest.overshoot,
        settling_time=None if None in settled else max(s for s in settled if s is not None),
        steady_state_error=furthest.steady_state_error,
    )
    details = tuple(
        metrics(
            joint=r.joint,
            rise_time=r.rise_time,
            overshoot=r.overshoot,
            settling_time=r.settling_time,
            steady_state_error=r.steady_state_error,
        )
        for r in responses
    )
    rise = f"{slowest.rise_time:.3g} s" if slowest.rise_time is not None else "never"
    settle = f"{values['settling_time']:.3g} s" if values["settling_time"] is not None else "never"
    summary = (
        f"{kind} step: rise {rise}, overshoot {wildest.overshoot:.0%}, settle {settle}, "
        f"error {furthest.steady_state_error:.1%}{unstepped}"
    )
    return values, details, summary


def _too_slow(verdict: _Verdict, extremes: _Extremes, bound: _Bound) -> Diagnostic | None:
    """RS505: the slowest joint rose too slowly, or never (unless gravity bounds it)."""
    v, settings, slowest = verdict, verdict.settings, extremes.slowest
    if not (slowest.rise_time is None or slowest.rise_time > settings.max_rise_time):
        return None
    took = (
        f"took {slowest.rise_time:.3g} s to rise from 10% to 90%"
        if slowest.rise_time is not None
        else f"covered only {slowest.reached:.0%} of it in {settings.duration:g} s"
    )
    # gravity takes the rating (RS534): the robot as rated, not its gains
    if bound(slowest.joint):
        return None
    cause, hint = _slow_cause(v.sim, v.group, v.trace, slowest.joint, v.kind)
    contradicted = mimic_limits.contradiction_words(v.run, slowest.joint)
    if contradicted is not None:  # a mimic joint its relation holds past its limits
        cause, hint = contradicted, mimic_limits.HINT
    return v.run.fail(
        v.where,
        TRACKS_TOO_SLOWLY,
        f"controller '{v.controller}' ({v.sim.mode}/{v.group.name}) is too slow: given a "
        f"{v.kind} step, joint '{slowest.joint}' {took} (max_rise_time "
        f"{settings.max_rise_time:g} s){cause}",
        hint,
    )


def _underdamped(verdict: _Verdict, extremes: _Extremes, bound: _Bound) -> Diagnostic | None:
    """RS506: the wildest joint overshot, or never settled (unless gravity bounds it)."""
    v, settings, wildest = verdict, verdict.settings, extremes.wildest
    kind = v.kind
    if not (
        (
            not np.isfinite(wildest.overshoot)
            or wildest.overshoot > settings.max_overshoot
            or (wildest.settling_time is None and extremes.slowest.rise_time is not None)
        )
        and not (np.isfinite(wildest.overshoot) and bound(wildest.joint))
    ):
        return None
    if np.isfinite(wildest.overshoot) and wildest.overshoot <= settings.max_overshoot:
        # it failed by never settling: say that, not an overshoot within the threshold
        what = (
            f"never settled within {settings.settling_band:.0%} of a {kind} step in "
            f"{settings.duration:g} s (its overshoot, {wildest.overshoot:.0%}, is within "
            f"max_overshoot {settings.max_overshoot:.0%})"
        )
    else:
        what = (
            f"overshot a {kind} step by {wildest.overshoot:.0%}"
            + ("" if wildest.settling_time is not None else " and never settled")
            + f" (max_overshoot {settings.max_overshoot:.0%})"
        )
    return v.run.fail(
        v.where,
        UNDERDAMPED,
        f"controller '{v.controller}' ({v.sim.mode}/{v.group.name}) is unstable or "
        f"underdamped: joint '{wildest.joint}' {what}",
        "raise its damping relative to its stiffness"
        + (
            " (a velocity drive: lower its damping's share of force_limit)"
            if kind == "velocity"
            else ""
        ),
    )


def _off_target(verdict: _Verdict, extremes: _Extremes, bound: _Bound) -> Diagnostic | None:
    """RS507: the furthest joint settled too far from its target (unless gravity bounds it)."""
    v, settings, furthest = verdict, verdict.settings, extremes.furthest
    if not (
        furthest.steady_state_error > settings.max_steady_state_error
        and extremes.slowest.rise_time is not None
        and not bound(furthest.joint)
    ):
        return None
    return v.run.fail(
        v.where,
        SETTLES_OFF_TARGET,
        f"controller '{v.controller}' ({v.sim.mode}/{v.group.name}): joint '{furthest.joint}' "
        f"settles {furthest.steady_state_error:.0%} of a {v.kind} step away from its "
        f"target (max_steady_state_error {settings.max_steady_state_error:.0%})",
        "raise its stiffness or force_limit, or lower its friction",
    )


def _saturation(
    group: ControllerGroup, trace: StepTrace | None, joint: str, kind: str
) -> tuple[float, float] | None:
    """``joint``'s force limit and the share of the step its drive was held there (what it
    was asked for, from the trace); None where the trace does not have it."""
    if trace is None or joint not in trace.joints:
        return None
    k = trace.joints.index(joint)
    count = len(trace.joints)
    config = group.pd_config
    force_limit = float(np.broadcast_to(np.asarray(config.force_limit, float), count)[k])
    stiffness = float(
        np.broadcast_to(np.asarray(getattr(config, "stiffness", 0.0), float), count)[k]
    )
    damping = float(np.broadcast_to(np.asarray(config.damping, float), count)[k])
    if kind == "position":
        asked = (
            stiffness * (trace.target[k] - trace.position[:, k]) - damping * trace.velocity[:, k]
        )
    else:
        asked = damping * (trace.target[k] - trace.velocity[:, k])
    asked = np.nan_to_num(np.abs(asked), nan=0.0)
    return force_limit, float(np.mean(asked >= force_limit * 0.999))


def _rated(
    run: CheckRun,
    sim: Sim,
    group: ControllerGroup,
    controller: str,
    trace: StepTrace | None,
    joint: str,
    kind: str,
) -> Diagnostic | None:
    """RS534 (robospec.physics.rating) when ``joint`` is held back by gravity at its rating."""
    held = _saturation(group, trace, joint, kind) if kind == "position" else None
    if held is None:
        return None
    prismatic = bool(sim.prismatic[sim.joint_names.index(joint)])
    return rating.gravity_bound(run, sim, controller, joint, held[0], held[1], prismatic)


def _slow_cause(
    sim: Sim, group: ControllerGroup, trace: StepTrace | None, joint: str, kind: str
) -> tuple[str, str]:
    """Why a joint is slow, as far as the trace tells, and the hint that fixes that."""
    stiffer = (
        "raise its stiffness (robospec tune finds gains)"
        if kind == "position"
        else "raise its damping (a velocity drive's gain)"
    )
    held = _saturation(group, trace, joint, kind)
    if held is None:
        return "", stiffer + ", or its force_limit"
    force_limit, saturated = held
    blocking = _blocking_contacts(sim, joint) if not sim.backend.gpu else []
    if blocking:
        pairs = ", ".join(f"{a} + {b}" for a, b in blocking)
        rule = ", ".join(f"[{a}, {b}]" for a, b in blocking)
        return (
            f"; links {pairs} touch: the contact blocks it",
            "move the keyframe so that they are apart, or declare the contact with "
            f"never_collide: [{rule}] if it is not meant to happen",
        )
    if saturated > 0.5:
        return (
            f"; its drive was held at force_limit {force_limit:g} for {saturated:.0%} of the step",
            "raise its force_limit if the motor gives more; if that is its rating, the joint is "
            "as fast as its motor: relax checks.step_response for this controller",
        )
    return "", stiffer + ", or its force_limit"


def _blocking_contacts(sim: Sim, joint: str) -> list[tuple[str, str]]:
    """Pairs of links touching now (within half a millimetre) of which one moves with
    ``joint`` and the other does not: a contact that holds the joint back."""
    moved = sim.moved_by(joint)
    return [
        (a, b)
        for (a, b), depth in sorted(sim.self_contacts().items())
        if depth >= -0.0005 and ((a in moved) != (b in moved))
    ]
