"""Fit drive stiffness and damping (and, when they do not suffice, joint friction) so that the
replayed response matches the reference.

The error is normalized per joint: the RMS of (simulated - measured) over the RMS of the
measured motion about its mean; the whole fit's error weighs every joint alike (the RMS of the
joints' normalized errors), so a wrist that moves a little counts as much as a shoulder.

Search: ``scipy.optimize.least_squares`` over the logarithms of the gains relative to where it
starts, so a gain of 5 and one of 5000 are searched alike and stay positive. A joint's error
depends mostly on its own gains, so the Jacobian is declared block-diagonal (joint by joint):
scipy then perturbs every joint's stiffness in one replay and every joint's damping in another,
and a Jacobian costs three replays whatever the number of joints. The coupling through the
arm's inertia is real but small; the fit still minimizes the true error, only its steps are
taken with that approximation.

Start: the spec's gains, and a closed-form guess from a second-order model fitted to both the
reference and the spec's replay (:func:`second_order`): the model's K/I and D/I, measured on
each, scale the spec's gains; the better of the two starts is refined.

What a position trajectory cannot tell apart: stiffness, damping and inertia together (the
response depends on K/I and D/I), so armature (rotor inertia, added to I) is not fitted: its
effect is absorbed into K and D. And a joint whose drive is far overdamped (D²/(K I) large)
moves like a first-order lag: only D/K shows; its K and D are reported as ill-determined.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robospec.tune.reference.replay import Drives, Replay

FRICTION_WORTH = 0.8  # friction is kept when it cuts the error to this fraction or less
ILL_CONDITIONED = 1e4  # a joint's (K, D) block of JᵀJ worse than this: only a ratio shows
# The search variable is OFFSET + log(gain / start): scipy's finite-difference step is
# relative to the variable (``diff_step`` times its size; a variable at 0 gets a 1e-8 step, lost
# in float32 physics), so the variables sit near OFFSET and each step is about 1e-3 in log-gain
OFFSET = 10.0
DIFF_STEP = 1e-4
# the coarse search before least squares: decades either side of the best start, then finer
GRID_SPANS = (1.5, 0.3)
GRID_POINTS = 5


def normalized_errors(simulated: np.ndarray, measured: np.ndarray) -> np.ndarray:
    """Per joint: RMS(simulated - measured) / RMS(measured - its mean)."""
    motion = _motion(measured)
    return np.sqrt(np.mean((simulated - measured) ** 2, axis=0)) / motion


def overall(errors: np.ndarray) -> float:
    return float(np.sqrt(np.mean(errors**2)))


def _motion(measured: np.ndarray) -> np.ndarray:
    return np.maximum(np.sqrt(np.mean((measured - measured.mean(axis=0)) ** 2, axis=0)), 1e-12)


def second_order(
    t: np.ndarray, target: np.ndarray, qpos: np.ndarray, implicit: bool = False
) -> tuple[float, float]:
    """``(a, b)`` of ``q'' = a (target - q) - b q' + c`` fitted by linear least squares to one
    joint's samples (finite differences on a uniform resampling): the drive's K/I and D/I. NaN
    where the data do not determine them. ``implicit``: the samples are the steps of an
    implicit integrator (PhysX's drives): the velocity that multiplies D is the step's new one,
    and the damping it sees includes ``K dt`` (taken off again here); else central differences,
    for a continuous response sampled."""
    dt = float(np.median(np.diff(t)))
    grid = np.arange(t[0], t[-1] + dt / 2, dt)
    if grid.size < 5:
        return float("nan"), float("nan")
    q = np.interp(grid, t, qpos)
    u = target[np.clip(np.searchsorted(t, grid + 1e-9, side="right") - 1, 0, None)]
    if implicit:
        velocity = (q[2:] - q[1:-1]) / dt
    else:
        velocity = (q[2:] - q[:-2]) / (2 * dt)
    acceleration = (q[2:] - 2 * q[1:-1] + q[:-2]) / dt**2
    design = np.stack([u[1:-1] - q[1:-1], -velocity, np.ones_like(velocity)], axis=1)
    solution, *_ = np.linalg.lstsq(design, acceleration, rcond=None)
    a, b = float(solution[0]), float(solution[1])
    if implicit:
        b -= a * dt
    return (a if a > 0 else float("nan")), (b if b > 0 else float("nan"))


class _Best:
    """Per joint, the drive parameters that gave it the lowest error so far."""

    def __init__(self, drives: Drives, errors: np.ndarray) -> None:
        self.stiffness = drives.stiffness.copy()
        self.damping = drives.damping.copy()
        self.friction = drives.friction.copy()
        self.errors = np.where(np.isfinite(errors), errors, np.inf)

    def offer(self, drives: Drives, errors: np.ndarray) -> None:
        better = np.isfinite(errors) & (errors < self.errors)
        self.stiffness[better] = drives.stiffness[better]
        self.damping[better] = drives.damping[better]
        self.friction[better] = drives.friction[better]
        self.errors[better] = errors[better]

    @property
    def drives(self) -> Drives:
        return Drives(self.stiffness.copy(), self.damping.copy(), self.friction.copy())


@dataclass
class Fit:
    before: Drives
    after: Drives
    errors_before: np.ndarray  # per joint
    errors_after: np.ndarray
    replays: int
    seconds: float
    friction_fitted: bool
    ill_determined: list[int] = field(default_factory=list)  # joint indices: only D/K shows
    simulated_before: np.ndarray | None = None
    simulated_after: np.ndarray | None = None

    @property
    def error_before(self) -> float:
        return overall(self.errors_before)

    @property
    def error_after(self) -> float:
        return overall(self.errors_after)


def fit(replay: Replay, max_replays: int = 600) -> Fit:
    began = time.perf_counter()
    replays = _Replays(replay)
    measured = replays.measured
    spec = replay.spec_drives
    simulated_before = replays.simulate(spec)
    errors_before = normalized_errors(simulated_before, measured)
    base = _coarse_search(replays, spec, simulated_before, errors_before)
    scale = _LogGains.around(base, len(replay.slots))
    gains = _fit_gains(replays, scale, max_replays)
    after = scale.drives(gains.x)
    simulated_after = replays.simulate(after)
    errors_after = normalized_errors(simulated_after, measured)
    friction_fitted = False
    if overall(errors_after) > 0.02 and replays.count < max_replays - 10:
        # friction: tried only when the gains leave a visible error (a stiction offset, a
        # slow creep); kept only when it pays
        with_friction = _fit_gains_and_friction(replays, scale, gains.x, max_replays)
        n = scale.n
        candidate = scale.drives(with_friction.x[: 2 * n], with_friction.x[2 * n :])
        simulated = replays.simulate(candidate)
        errors = normalized_errors(simulated, measured)
        if overall(errors) <= FRICTION_WORTH * overall(errors_after):
            after, simulated_after, errors_after = candidate, simulated, errors
            friction_fitted = True
            gains = with_friction
    return Fit(
        before=spec,
        after=after,
        errors_before=errors_before,
        errors_after=errors_after,
        replays=replays.count,
        seconds=time.perf_counter() - began,
        friction_fitted=friction_fitted,
        ill_determined=_ill_determined(gains.jac, scale.n),
        simulated_before=simulated_before,
        simulated_after=simulated_after,
    )


class _Replays:
    """The replay, counting its runs (the fit's budget), and the residual it minimizes."""

    def __init__(self, replay: Replay) -> None:
        self.replay = replay
        self.measured = replay.reference.qpos
        shape = self.measured.shape
        self.weights = 1.0 / (_motion(self.measured) * np.sqrt(shape[0] * shape[1]))
        self.count = 0

    def simulate(self, drives: Drives) -> np.ndarray:
        self.count += 1
        return self.replay.run(drives)

    def residual(self, simulated: np.ndarray) -> np.ndarray:
        out = (simulated - self.measured) * self.weights
        return np.where(np.isfinite(out), out, 1e3).T.ravel()  # joint by joint; NaN: far off


@dataclass(frozen=True)
class _LogGains:
    """The least-squares variables: OFFSET + log(gain / base) per joint, stiffness then
    damping (then friction, as it is, when that is fitted too)."""

    stiffness: np.ndarray  # the base gains, kept off zero so that their logarithm exists
    damping: np.ndarray
    friction: np.ndarray
    n: int  # joints

    @classmethod
    def around(cls, base: Drives, n: int) -> _LogGains:
        return cls(
            np.maximum(base.stiffness, 1e-9), np.maximum(base.damping, 1e-9), base.friction, n
        )

    def drives(self, x: np.ndarray, friction: np.ndarray | None = None) -> Drives:
        n = self.n
        return Drives(
            self.stiffness * np.exp(x[:n] - OFFSET),
            self.damping * np.exp(x[n : 2 * n] - OFFSET),
            self.friction if friction is None else friction,
        )


def _coarse_search(
    replays: _Replays, spec: Drives, simulated_before: np.ndarray, errors_before: np.ndarray
) -> Drives:
    """The closed-form starts, then a grid of decades about the best: each joint's best."""
    measured = replays.measured
    # every start and grid point is one replay with all joints set at once; each joint then
    # takes what suited it best (its error depends mostly on its own gains)
    best = _Best(spec, errors_before)
    for candidate in _closed_form_starts(replays.replay, spec, simulated_before):
        best.offer(candidate, normalized_errors(replays.simulate(candidate), measured))
    for span in GRID_SPANS:
        center = best.drives
        for dk in np.linspace(-span, span, GRID_POINTS):
            for dd in np.linspace(-span, span, GRID_POINTS):
                if dk == 0 and dd == 0:
                    continue
                candidate = Drives(
                    center.stiffness * 10**dk, center.damping * 10**dd, center.friction
                )
                best.offer(candidate, normalized_errors(replays.simulate(candidate), measured))
    return best.drives


def _fit_gains(replays: _Replays, scale: _LogGains, max_replays: int) -> Any:
    """Least squares over stiffness and damping, from the coarse search's best."""
    from scipy.optimize import least_squares

    budget = max(max_replays - replays.count, 10)
    return least_squares(
        lambda x: replays.residual(replays.simulate(scale.drives(x))),
        np.full(2 * scale.n, OFFSET),
        jac_sparsity=None,
        diff_step=DIFF_STEP,
        x_scale=1.0,
        max_nfev=budget,
        xtol=1e-8,
        ftol=1e-10,
    )


def _fit_gains_and_friction(
    replays: _Replays, scale: _LogGains, gains: np.ndarray, max_replays: int
) -> Any:
    """Least squares over stiffness, damping and (non-negative) joint friction, from the
    fitted gains."""
    from scipy.optimize import least_squares

    n = scale.n
    return least_squares(
        lambda x: replays.residual(replays.simulate(scale.drives(x[: 2 * n], x[2 * n :]))),
        np.concatenate([gains, scale.friction]),
        jac_sparsity=None,
        diff_step=DIFF_STEP,
        bounds=(
            np.r_[np.full(2 * n, -np.inf), np.zeros(n)],
            np.r_[np.full(2 * n, np.inf), np.full(n, np.inf)],
        ),
        max_nfev=max(max_replays - replays.count, 10),
        xtol=1e-8,
        ftol=1e-10,
    )


def _closed_form_starts(replay: Replay, spec: Drives, simulated: np.ndarray) -> list[Drives]:
    """Starts from a second-order model of each joint fitted to the reference, ``K/I`` and
    ``D/I``: times the joint's effective inertia in the simulation (the mass matrix's diagonal
    at the start: exact for one joint alone, close for a chain); and, the same model fitted to
    the spec's own replay, as a ratio that scales the spec's gains (its discretization error
    cancels out). Joints the model does not fit keep the spec's gains."""
    reference = replay.reference
    inertia = replay.inertia()
    starts = []
    for implicit in (False, True):
        absolute = [spec.stiffness.copy(), spec.damping.copy()]
        ratio = [spec.stiffness.copy(), spec.damping.copy()]
        for k in range(len(replay.slots)):
            args = (reference.t, reference.target[:, k])
            model = second_order(*args, reference.qpos[:, k], implicit)
            own = second_order(*args, simulated[:, k], implicit)
            for i in (0, 1):
                if np.isfinite(model[i]):
                    absolute[i][k] = model[i] * inertia[k]
                    if np.isfinite(own[i]) and ratio[i][k] > 0:
                        ratio[i][k] *= model[i] / own[i]
        starts += [Drives(k, d, spec.friction) for k, d in (absolute, ratio)]
    return starts


def _ill_determined(jacobian: object, n: int) -> list[int]:
    """Joints whose (log K, log D) block of JᵀJ is near singular: the response pins down a
    combination (D/K) and not each."""
    dense = jacobian.toarray() if hasattr(jacobian, "toarray") else np.asarray(jacobian)
    out = []
    for k in range(n):
        columns = dense[:, [k, n + k]]
        block = columns.T @ columns
        singular = np.linalg.svd(block, compute_uv=False)
        if singular[0] <= 0 or singular[-1] <= singular[0] / ILL_CONDITIONED:
            out.append(k)
    return out
