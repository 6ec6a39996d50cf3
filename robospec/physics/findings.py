"""What a physics check reports: one :class:`Finding` per check, mode and subject.

A finding that fails carries a located, coded :class:`~robospec.diagnostics.Diagnostic` (the
same record ``validate`` prints), so ``robospec check`` output points at the spec line to
change. Metrics are plain numbers and strings, rounded when reported, so JSON output is stable.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from robospec.diagnostics import Diagnostic, Severity

Metric = float | int | str | bool | None


class Status(str, enum.Enum):
    PASS = "pass"
    FAIL = "fail"
    SKIP = "skip"
    INFO = "info"


@dataclass(frozen=True)
class Finding:
    check: str  # keyframe_hold, random_actions, step_response, self_contact, action_layout
    mode: str | None
    subject: str  # a keyframe, a group, "60 steps", ...
    status: Status
    summary: str  # one line for the text table
    metrics: Mapping[str, Metric] = field(default_factory=dict)
    diagnostics: tuple[Diagnostic, ...] = ()
    details: tuple[Mapping[str, Metric], ...] = ()  # e.g. one row per action dimension

    @property
    def failed(self) -> bool:
        return self.status is Status.FAIL or any(
            d.severity is Severity.ERROR for d in self.diagnostics
        )


# significant digits of a number robospec reports or writes: a metric in check's output (so JSON
# does not flicker in the last bits of a float), a gain that new and tune write into a spec
METRIC_DIGITS = 6
GAIN_DIGITS = 3


def significant(value: float, digits: int = GAIN_DIGITS) -> float:
    """``value`` to ``digits`` significant digits (0, infinities and NaN as they are)."""
    if value == 0 or not math.isfinite(value):
        return value
    return float(f"{value:.{digits}g}")


def metrics(**values: Metric) -> dict[str, Metric]:
    return {
        k: significant(v, METRIC_DIGITS) if isinstance(v, float) else v for k, v in values.items()
    }
