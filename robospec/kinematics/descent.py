"""Damped least squares over a chain's joints: the search both ``new``'s ready pose (on the
description's kinematics) and ``solve``'s downward reach (on SAPIEN's Pinocchio model) run to
put a grasp at a point, pointing down.

Each step solves the damped normal equations of a finite-difference Jacobian of ``error``,
caps the largest joint change at ``step``, keeps the joints within their limits, and halves a
step that does not lower the error's norm up to ``halvings`` times; a step that never helps
ends the search (held at a limit, or at a minimum that is no solution).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np


@dataclass(frozen=True)
class Descent:
    """Where the search ended: the joints, their error, whether ``converged`` held there
    (checked before each step) and whether it stalled (no step helped)."""

    joints: np.ndarray
    error: np.ndarray
    converged: bool
    stalled: bool


def damped_descent(
    error: Callable[[np.ndarray], np.ndarray],
    start: np.ndarray,
    low: np.ndarray,
    high: np.ndarray,
    converged: Callable[[np.ndarray], bool],
    *,
    iterations: int,
    damping: float,
    step: float,
    halvings: int,
    difference: float,
) -> Descent:
    """Descend ``error`` (a residual to bring to zero) from ``start`` within [low, high]."""
    import numpy as np

    joints = start
    now = error(joints)
    for _ in range(iterations):
        if converged(now):
            return Descent(joints, now, True, False)
        jacobian = np.empty((len(now), len(joints)))
        for i in range(len(joints)):
            nudged = joints.copy()
            nudged[i] += difference
            jacobian[:, i] = (error(nudged) - now) / difference
        square = jacobian @ jacobian.T + damping**2 * np.eye(len(now))
        delta = -jacobian.T @ np.linalg.solve(square, now)
        largest = float(np.max(np.abs(delta)))
        if largest > step:
            delta *= step / largest
        for _ in range(halvings):
            tried = np.clip(joints + delta, low, high)
            after = error(tried)
            if np.linalg.norm(after) < np.linalg.norm(now):
                joints, now = tried, after
                break
            delta = delta / 2
        else:
            return Descent(joints, now, False, True)
    return Descent(joints, now, False, False)
