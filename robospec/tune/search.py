"""The search for one controller's gains, in simulation (the worker process runs it).

Every candidate is measured as ``robospec check`` measures a controller
(:func:`~robospec.physics.step_response.step_trace`: from the first keyframe, settled, a
floating robot held by its root), with the candidate's gains set on the live robot
(``Sim.set_drive``): no recompiling.

1. The controller's own gains first: when every joint meets the targets they stay.
2. Joints that meet the targets keep their gains. The others start critically damped, from
   their effective inertia ``I`` (the mass-matrix diagonal plus armature at the keyframe; for
   joints coupled to others of the controller — an off-diagonal entry of the mass matrix at
   least :data:`COUPLED` of the geometric mean of the two diagonal ones, so that stepping one
   pushes the other — the row's sum of magnitudes, the inertia it meets when they all move
   at once: coupled joints are tuned together), never softer than they were: natural frequency
   ``w = OMEGA_PER_SETTLING / max_settling_time``, ``stiffness = max(stiffness, I w²)``,
   ``damping = 2 zeta sqrt(stiffness I)`` with ``zeta`` at least 1 (velocity drives:
   ``damping = max(damping, I w)``).
3. Bounded rounds, each joint on its own measurement (all joints step together, as in check):
   overshoot or ringing raises its damping ratio; steady-state error (gravity, friction, the
   other joints pushing) or a slow response raises its stiffness; a drive that saturates
   raises its force_limit (unless ``keep_force_limit``), never past the joint's rating in the
   description (``force_caps``): a joint that needs more is reported
   (:attr:`ControllerTuning.over_rating`). Gains are rounded to 3 significant digits before
   they are measured, so what is measured is what ``--write`` writes.
4. A joint that still misses is explained (one whose range leaves no room for a step is not
   stepped, and misses nothing: step_trace keeps every target within the limits): its
   drive saturates at a kept force_limit or at its rating, it meets the targets when stepped
   alone (coupling between the joints: the joints that push it are named), or its stiffness
   bound was reached.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np

from robospec.physics.findings import significant
from robospec.physics.sim import Sim
from robospec.physics.step_response import Drive, Response, StepSettings, StepTrace, step_trace
from robospec.resolve.resolved import ResolvedKeyframe
from robospec.tune.results import ControllerTuning, Gains, Targets, Timing

OMEGA_PER_SETTLING = 8.0  # w * T: twice what a critically damped joint needs to settle in T
MAX_ROUNDS = 14  # simulations after the controller's own gains, at most
MAX_ZETA = 6.0
STIFFNESS_STEP = 2.5  # factor a joint's stiffness rises by per round that needs it
ZETA_STEP = 1.5
MAX_OMEGA_PER_SIM_FREQ = 1.0  # the stiffest joint: w up to sim_freq (rad/s), i.e. w dt <= 1
FORCE_MARGIN = 1.5  # a raised force_limit: this much above the largest torque asked for
UNLIMITED = 1e9  # a force_limit at or above this is no limit (ManiSkill's default is 1e10)
# |M_ij| / sqrt(M_ii M_jj) at or above this: stepping joint j pushes joint i
COUPLED = 0.2


def _round(values: np.ndarray) -> np.ndarray:
    return np.array([significant(float(v)) for v in values])


def failures(response: Response, targets: Targets) -> set[str]:
    """Which targets a joint misses: ``unstable``, ``overshoot``, ``settling``, ``steady``."""
    if response.no_room:  # not stepped: nothing to tune it by
        return set()
    if not math.isfinite(response.reached):
        return {"unstable"}
    missed = set()
    if response.overshoot > targets.max_overshoot:
        missed.add("overshoot")
    if response.settling_time is None or response.settling_time > targets.max_settling_time:
        missed.add("settling")
    if response.steady_state_error > targets.max_steady_state_error:
        missed.add("steady")
    return missed


def timings(trace: StepTrace) -> tuple[Timing, ...]:
    return tuple(
        Timing(r.joint, r.overshoot, r.settling_time, r.steady_state_error, r.rise_time)
        for r in trace.responses
    )


def controller_gains(sim: Sim, group_name: str) -> Gains:
    """The gains the controller gives its joints (as configured), one value per joint."""
    group = sim.group(group_name)
    config = group.pd_config
    n = len(group.joint_indices)

    def per_joint(value: object) -> tuple[float, ...]:
        array = np.broadcast_to(np.asarray(value if value is not None else 0.0, float), n)
        return tuple(float(v) for v in array)

    stiffness = getattr(config, "stiffness", 0.0)
    return Gains(per_joint(stiffness), per_joint(config.damping), per_joint(config.force_limit))


class Search:
    """One controller's search: ``run()`` gives its :class:`ControllerTuning`."""

    def __init__(
        self,
        sim: Sim,
        group_name: str,
        controller: str,
        keyframe: ResolvedKeyframe | None,
        settings: StepSettings,
        targets: Targets,
        on_simulation: Callable[[int], None] | None = None,
        force_caps: np.ndarray | None = None,
        initial: Gains | None = None,
    ) -> None:
        """``force_caps``: the most force each joint's motor is rated for (inf: unrated), in
        the group's joint order; the search never raises a force limit past it. ``initial``:
        the gains to start from (default: the controller's own)."""
        self.sim = sim
        self.group_name = group_name
        self.controller = controller
        self.keyframe = keyframe
        self.settings = settings
        self.targets = targets
        self.on_simulation = on_simulation
        self.force_caps = force_caps
        self.initial = initial
        self.simulations = 0
        self.over_rating: dict[int, float] = {}  # joint index -> the most it asked for
        self.coupled: dict[int, list[int]] = {}  # joint index -> the joints that push it

    def measure(self, gains: Gains, stepped: np.ndarray | None = None) -> StepTrace:
        self.simulations += 1
        if self.on_simulation is not None:
            self.on_simulation(self.simulations)
        drive = Drive(
            np.array(gains.stiffness), np.array(gains.damping), np.array(gains.force_limit)
        )
        return step_trace(self.sim, self.group_name, self.keyframe, self.settings, drive, stepped)

    def missed(self, trace: StepTrace) -> list[set[str]]:
        return [failures(r, self.targets) for r in trace.responses]

    def run(self) -> ControllerTuning:
        started = time.perf_counter()
        before = self.initial or controller_gains(self.sim, self.group_name)
        before_trace = self.measure(before)
        kind = before_trace.kind
        result = ControllerTuning(
            controller=self.controller,
            mode=self.sim.mode,
            group=self.group_name,
            kind=kind,
            joints=before_trace.joints,
            status="met",
            targets=self.targets,
            before=before,
            after=before,
            before_timings=timings(before_trace),
            after_timings=timings(before_trace),
            before_trace=before_trace,
            after_trace=before_trace,
        )
        if not any(self.missed(before_trace)):
            result.simulations = self.simulations
            result.seconds = time.perf_counter() - started
            return result
        gains, trace = self._search(before, before_trace)
        result.after, result.after_trace = gains, trace
        result.after_timings = timings(trace)
        missed = self.missed(trace)
        caps = self._caps(len(gains.force_limit))
        # over its rating: a joint the search would have given more than its rating and whose
        # tuned gains still ask for more (the force asked for is that of the gains written, so
        # the warning never says "asks for 17, more than its rating of 20")
        asked = self._demand(gains, trace)
        result.over_rating = tuple(
            (trace.joints[j], float(asked[j]), float(caps[j]))
            for j in sorted(self.over_rating)
            if asked[j] > caps[j]
        )
        if any(missed):
            result.status = "failed"
            result.reasons = self._explain(gains, trace, missed)
        else:
            result.status = "tuned"
        result.simulations = self.simulations
        result.seconds = time.perf_counter() - started
        return result

    # -- the search ------------------------------------------------------------------------

    def _caps(self, n: int) -> np.ndarray:
        if self.force_caps is None:
            return np.full(n, np.inf)
        return np.asarray(self.force_caps, dtype=np.float64)

    def _inertia(self) -> np.ndarray:
        """Each joint's inertia to tune for: the mass-matrix diagonal, or for a joint coupled
        to others the row's sum of magnitudes (:data:`COUPLED`)."""
        mass = self.sim.mass_matrix(self.group_name)
        diagonal = np.maximum(np.diag(mass), 1e-9)
        scale = np.sqrt(np.outer(diagonal, diagonal))
        coupling = np.abs(mass) / scale
        np.fill_diagonal(coupling, 0.0)
        inertia = diagonal.copy()
        for i in range(len(diagonal)):
            partners = [int(j) for j in np.nonzero(coupling[i] >= COUPLED)[0]]
            if partners:
                self.coupled[i] = partners
                inertia[i] = float(np.abs(mass[i]).sum())
        return inertia

    def _search(self, before: Gains, before_trace: StepTrace) -> tuple[Gains, StepTrace]:
        self.sim.start(self.keyframe)
        inertia = self._inertia()
        caps = self._caps(len(before.stiffness))
        velocity = before_trace.kind == "velocity"
        omega = OMEGA_PER_SETTLING / self.targets.max_settling_time
        omega_max = MAX_OMEGA_PER_SIM_FREQ * self.sim.sim_freq
        original_k = np.array(before.stiffness, dtype=np.float64)
        original_d = np.array(before.damping, dtype=np.float64)
        force_limit = np.array(before.force_limit, dtype=np.float64)
        # joints that meet the targets keep their gains; the others start critically damped,
        # never softer than they were
        touched = np.array([bool(m) for m in self.missed(before_trace)])
        stiffness = np.maximum(original_k, inertia * omega**2)
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.nan_to_num(original_d / (2.0 * np.sqrt(original_k * inertia)), nan=1.0)
        zeta = np.clip(zeta, 1.0, MAX_ZETA)
        damping_v = np.maximum(original_d, inertia * omega)  # velocity drives
        best: tuple[int, Gains, StepTrace] | None = None
        for _ in range(MAX_ROUNDS):
            if velocity:
                k = original_k
                d = np.where(touched, _round(damping_v), original_d)
            else:
                k = np.where(touched, _round(stiffness), original_k)
                d = np.where(touched, _round(2.0 * zeta * np.sqrt(stiffness * inertia)), original_d)
            gains = Gains(
                tuple(float(v) for v in k),
                tuple(float(v) for v in d),
                tuple(float(v) for v in force_limit),
            )
            trace = self.measure(gains)
            missed = self.missed(trace)
            count = sum(bool(m) for m in missed)
            if best is None or count <= best[0]:
                best = (count, gains, trace)
            if count == 0:
                return gains, trace
            demand = self._demand(gains, trace)
            for j, miss in enumerate(missed):
                if not miss:
                    continue
                if not touched[j]:  # a joint the others disturb now: tune it from here
                    touched[j] = True
                    stiffness[j], damping_v[j] = original_k[j], original_d[j]
                    continue
                at_cap = False
                if demand[j] >= force_limit[j] * 0.999 and not self.targets.keep_force_limit:
                    wanted = significant(FORCE_MARGIN * demand[j])
                    if wanted > caps[j]:
                        # a rated motor gives no more: never a silent raise past its rating
                        self.over_rating[j] = max(self.over_rating.get(j, 0.0), float(demand[j]))
                        wanted = max(float(caps[j]), force_limit[j])
                        at_cap = force_limit[j] >= caps[j] * 0.999
                    force_limit[j] = wanted
                response = trace.responses[j]
                ringing = (
                    "overshoot" in miss
                    or "unstable" in miss
                    or ("settling" in miss and response.reached > 1.0 + self.settings.settling_band)
                )
                if velocity:
                    damping_v[j] = min(damping_v[j] * STIFFNESS_STEP, inertia[j] * omega_max)
                elif ringing and zeta[j] < MAX_ZETA:
                    zeta[j] = min(zeta[j] * ZETA_STEP, MAX_ZETA)
                elif miss & {"steady", "settling"} and not at_cap:
                    # (a drive held at its rating gets no faster with more stiffness)
                    cap = max(inertia[j] * omega_max**2, original_k[j])
                    stiffness[j] = min(stiffness[j] * STIFFNESS_STEP, cap)
                    if "settling" in miss and zeta[j] > 1.0 and not ringing:
                        zeta[j] = max(zeta[j] / ZETA_STEP, 1.0)
        assert best is not None
        return best[1], best[2]

    def _demand(self, gains: Gains, trace: StepTrace) -> np.ndarray:
        """The largest force each drive was asked for during the step (before its limit)."""
        stiffness = np.array(gains.stiffness)
        damping = np.array(gains.damping)
        if trace.kind == "velocity":
            asked = damping * (trace.target - trace.velocity)
        else:
            asked = stiffness * (trace.target - trace.position) - damping * trace.velocity
        return np.nan_to_num(np.abs(asked), nan=0.0).max(axis=0)

    # -- why a joint misses ------------------------------------------------------------------

    def _explain(
        self, gains: Gains, trace: StepTrace, missed: list[set[str]]
    ) -> tuple[tuple[str, str], ...]:
        group = self.sim.group(self.group_name)
        joints = list(group.joint_indices)
        demand = self._demand(gains, trace)
        reasons = []
        for k, miss in enumerate(missed):
            if not miss:
                continue
            what = ", ".join(sorted(miss))
            joint = trace.joints[k]
            if demand[k] >= gains.force_limit[k] * 0.999 and gains.force_limit[k] < UNLIMITED:
                rated = (
                    ", its rating in the description"
                    if gains.force_limit[k] >= self._caps(len(joints))[k] * 0.999
                    else ""
                )
                why = (
                    f"force limit: the drive asks for {demand[k]:.3g} and is held at "
                    f"force_limit {gains.force_limit[k]:.3g}{rated} ({what})"
                )
            elif len(joints) > 1 and not self._alone_misses(gains, k):
                pushers = [trace.joints[j] for j in self.coupled.get(k, [])]
                by = f" (pushed by {', '.join(repr(p) for p in pushers)})" if pushers else ""
                why = (
                    "coupling between joints: stepped alone it meets the targets, stepped "
                    f"with the others it does not{by} ({what})"
                )
            else:
                why = (
                    f"no gains found within {MAX_ROUNDS} simulations and the stiffness bound "
                    f"({what}: overshoot {trace.responses[k].overshoot:.0%}, error "
                    f"{trace.responses[k].steady_state_error:.1%})"
                )
            reasons.append((joint, why))
        return tuple(reasons)

    def _alone_misses(self, gains: Gains, index: int) -> bool:
        stepped = np.zeros(len(gains.stiffness), dtype=bool)
        stepped[index] = True
        trace = self.measure(gains, stepped)
        return bool(failures(trace.responses[0], self.targets))
