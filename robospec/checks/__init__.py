"""Stage 4: semantic checks over a resolved robot. One module per rule, each a function
``check(context) -> Iterable[Diagnostic]`` registered in :data:`CHECKS`."""

from __future__ import annotations

from collections.abc import Callable, Iterable

from robospec.checks import (
    collision_bits,
    controller_gains,
    mimic_joints,
    mode_coverage,
    never_collide_bits,
    never_collide_self,
    unbounded_normalization,
)
from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic

CHECKS: tuple[Callable[[CheckContext], Iterable[Diagnostic]], ...] = (
    mode_coverage.check,
    mimic_joints.check,
    collision_bits.check,
    controller_gains.check,
    unbounded_normalization.check,
    never_collide_bits.check,
    never_collide_self.check,
)


def run_checks(context: CheckContext) -> list[Diagnostic]:
    return [d for check in CHECKS for d in check(context)]


__all__ = ["CHECKS", "CheckContext", "run_checks"]
