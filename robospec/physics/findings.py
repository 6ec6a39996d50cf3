"""What a physics check reports: one :class:`Finding` per check, mode and subject.

A finding that fails carries a located, coded :class:`~robospec.diagnostics.Diagnostic` (the
same record ``validate`` prints), so ``robospec check`` output points at the spec line to
change. Metrics are plain numbers and strings, rounded when reported, so JSON output is stable.
"""

from __future__ import annotations

import enum
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


def rounded(value: float, digits: int = 6) -> float:
    """``value`` to ``digits`` significant digits, so JSON output does not flicker in the last
    bits of a float."""
    if value == 0 or value != value or value in (float("inf"), float("-inf")):
        return value
    return float(f"{value:.{digits}g}")


def metrics(**values: Metric) -> dict[str, Metric]:
    return {k: rounded(v) if isinstance(v, float) else v for k, v in values.items()}
