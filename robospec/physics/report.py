"""``robospec check`` output: a readable table per robot, or stable JSON for CI; and the progress
line shown on a terminal while the checks run."""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Sequence
from typing import TextIO

from robospec.diagnostics import Diagnostic, Severity, sort_key
from robospec.physics.action_layout import NAME as ACTION_LAYOUT
from robospec.physics.batch import RobotReport
from robospec.physics.findings import Finding, Status
from robospec.physics.results import LOAD
from robospec.reporting.text import plain_lines

COLUMNS = ("check", "mode", "subject", "result", "details")


def robot_status(report: RobotReport) -> str:
    if report.failed and all(f.check == LOAD for f in report.findings):
        return "error"  # the spec did not compile, or the robot could not be loaded
    return "fail" if report.failed else "pass"


def summary(reports: Sequence[RobotReport], extra: Sequence[Diagnostic]) -> dict[str, int]:
    diagnostics = [d for r in reports for d in r.all_diagnostics] + list(extra)
    statuses = [robot_status(r) for r in reports]
    return {
        "robots": len(reports),
        "passed": statuses.count("pass"),
        "failed": statuses.count("fail"),
        "not_checked": statuses.count("error"),
        "errors": sum(d.severity is Severity.ERROR for d in diagnostics),
        "warnings": sum(d.severity is Severity.WARNING for d in diagnostics),
    }


def _strict(value: object) -> object:
    """``value`` with infinite and NaN floats as the strings "inf", "-inf" and "nan": JSON has
    no such numbers, and CI tools parse strictly."""
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, dict):
        return {k: _strict(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_strict(v) for v in value]
    return value


def render_json(reports: Sequence[RobotReport], extra: Sequence[Diagnostic]) -> str:
    return json.dumps(
        {
            "robots": [
                {
                    "spec": r.spec,
                    "uid": r.uid,
                    "status": robot_status(r),
                    "findings": [_strict(_finding_json(f)) for f in r.findings],
                    "diagnostics": [d.to_json() for d in sorted(r.all_diagnostics, key=sort_key)],
                    "messages": [m.to_json() for m in r.messages],
                }
                for r in reports
            ],
            "diagnostics": [d.to_json() for d in sorted(extra, key=sort_key)],
            "summary": summary(reports, extra),
        },
        indent=2,
        allow_nan=False,
    )


def _finding_json(finding: Finding) -> dict[str, object]:
    return {
        "check": finding.check,
        "mode": finding.mode,
        "subject": finding.subject,
        "status": finding.status.value,
        "summary": finding.summary,
        "metrics": dict(finding.metrics),
        "details": [dict(d) for d in finding.details],
        "codes": [d.code for d in finding.diagnostics],
    }


def render_text(reports: Sequence[RobotReport], extra: Sequence[Diagnostic]) -> str:
    lines: list[str] = []
    for report in reports:
        status = robot_status(report)
        # a spec that does not compile has no uid: its diagnostics below say why
        uid = report.uid or "not compiled"
        lines.append(f"{report.spec}: {uid}: {status.upper()}")
        table = [f for f in report.findings if f.check != ACTION_LAYOUT]
        if table:
            lines.extend("  " + row for row in _table(table))
        layouts = [f for f in report.findings if f.check == ACTION_LAYOUT]
        if layouts:
            lines.append("  action layout:")
            lines.extend(f"    {f.mode} ({f.subject}): {f.summary}" for f in layouts)
        if report.messages:
            lines.append("  ManiSkill and SAPIEN said, each message once:")
            lines.extend(f"    {m.describe()}" for m in report.messages)
        lines.append("")
    problems = sorted([d for r in reports for d in r.all_diagnostics] + list(extra), key=sort_key)
    # with the source line and its caret, as validate shows them
    lines.extend(line for d in problems for line in plain_lines(d))
    counts = summary(reports, extra)
    lines.append(
        f"{counts['robots']} robot(s) checked: {counts['passed']} passed, "
        f"{counts['failed']} failed, {counts['not_checked']} not checked; "
        f"{counts['errors']} error(s), {counts['warnings']} warning(s)"
    )
    return "\n".join(lines)


def _table(findings: Sequence[Finding]) -> list[str]:
    rows = [
        (
            f.check,
            f.mode or "-",
            f.subject,
            f.status.value.upper() if f.status is Status.FAIL else f.status.value,
            f.summary,
        )
        for f in findings
    ]
    widths = [max(len(COLUMNS[i]), *(len(r[i]) for r in rows)) for i in range(4)]

    def line(cells: Sequence[str]) -> str:
        return "  ".join(c.ljust(w) for c, w in zip(cells[:4], widths, strict=True)) + (
            "  " + cells[4]
        )

    return [line(COLUMNS), *(line(r) for r in rows)]


class ProgressLine:
    """A one-line progress bar on a terminal (nothing when output is piped, as in CI)."""

    WIDTH = 24

    def __init__(self, stream: TextIO | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = self.stream.isatty()
        self._shown = 0

    def __call__(self, done: int, total: int, label: str) -> None:
        if not self.enabled or total <= 0:
            return
        filled = self.WIDTH * done // total
        text = f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] {done}/{total} {label}"
        self.stream.write("\r" + text.ljust(self._shown))
        self._shown = len(text)
        self.stream.flush()

    def close(self) -> None:
        if self.enabled and self._shown:
            self.stream.write("\r" + " " * self._shown + "\r")
            self.stream.flush()
