"""Commanded targets that show a drive's stiffness and damping: per joint, a square wave of a
small step about where the joint starts (away from its nearer limit), each joint with its own
half-period so that no two joints always move together (their responses stay apart in the
fit). Steps excite the whole response: its rise shows K/I, its overshoot and decay D/I."""

from __future__ import annotations

import numpy as np

from robospec.model.thresholds import PRISMATIC_STEP, STEP  # check's step response's

DURATION = 2.0  # s


def square_waves(
    start: np.ndarray,
    limits: np.ndarray,
    prismatic: np.ndarray,
    dt: float,
    duration: float = DURATION,
) -> tuple[np.ndarray, np.ndarray]:
    """Sample times ``(T,)`` from 0 every ``dt`` and targets ``(T, J)`` for joints starting at
    ``start`` with ``limits`` ``(J, 2)``."""
    t = np.arange(round(duration / dt) + 1) * dt
    size = np.where(prismatic, PRISMATIC_STEP, STEP)
    lower, upper = limits[:, 0], limits[:, 1]
    direction = np.where(upper - start >= start - lower, 1.0, -1.0)
    half_period = 0.3 + 0.07 * (np.arange(start.size) % 5)
    # on for the first half-period (after a short rest), off for the next, ...
    phase = np.floor(np.maximum(t[:, None] - 0.05, 0.0) / half_period[None, :])
    on = (t[:, None] >= 0.05) & (phase % 2 == 0)
    return t, start[None, :] + on * (direction * size)[None, :]
