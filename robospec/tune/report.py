"""``robospec tune`` output: a before/after table per controller, or stable JSON for tools."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence

from robospec.diagnostics import Severity, sort_key
from robospec.tune.results import ControllerTuning, Gains, Timing, TuneReport

COLUMNS = ("joint", "stiffness", "damping", "force_limit", "overshoot", "settling", "error")
STATUS_WORDS = {
    "met": "meets its targets as it is: unchanged",
    "tuned": "tuned: meets its targets",
    "failed": "FAILED: cannot meet its targets",
    "skipped": "skipped",
}


def _number(value: float) -> str:
    if not math.isfinite(value):
        return "nan" if math.isnan(value) else "inf"
    if value >= 1e9:
        return "none"  # ManiSkill's "no force limit" (1e10)
    return format(float(f"{value:.3g}"), "g")  # 1760, not 1.76e+03


def _seconds(value: float | None) -> str:
    return "never" if value is None else f"{value:.2f}s"


def _percent(value: float) -> str:
    return "nan" if not math.isfinite(value) else f"{value:.1%}"


def _change(before: str, after: str) -> str:
    return before if before == after else f"{before} -> {after}"


def _rows(tuning: ControllerTuning) -> list[tuple[str, ...]]:
    assert tuning.before is not None and tuning.after is not None
    rows: list[tuple[str, ...]] = []
    for k, joint in enumerate(tuning.joints):
        b, a = tuning.before_timings[k], tuning.after_timings[k]
        rows.append(
            (
                joint,
                _change(_number(tuning.before.stiffness[k]), _number(tuning.after.stiffness[k])),
                _change(_number(tuning.before.damping[k]), _number(tuning.after.damping[k])),
                _change(
                    _number(tuning.before.force_limit[k]), _number(tuning.after.force_limit[k])
                ),
                _change(_percent(b.overshoot), _percent(a.overshoot)),
                _change(_seconds(b.settling_time), _seconds(a.settling_time)),
                _change(_percent(b.steady_state_error), _percent(a.steady_state_error)),
            )
        )
    return rows


def _table(rows: Sequence[tuple[str, ...]]) -> list[str]:
    widths = [max(len(COLUMNS[i]), *(len(r[i]) for r in rows)) for i in range(len(COLUMNS))]
    return [
        "  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip()
        for row in (COLUMNS, *rows)
    ]


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}{'' if number == 1 else 's'}"


def render_text(report: TuneReport) -> str:
    lines = [f"{report.spec}: {report.uid or 'not compiled'}"]
    for tuning in report.controllers:
        head = (
            f"  {tuning.controller} ({tuning.mode}/{tuning.group}): {STATUS_WORDS[tuning.status]}"
        )
        if tuning.status == "skipped":
            lines.append(f"{head} ({tuning.kind} controller: no step)")
            continue
        if tuning.targets is not None:
            t = tuning.targets
            head += (
                f" (overshoot <= {t.max_overshoot:.0%}, settling <= {t.max_settling_time:g} s, "
                f"error <= {t.max_steady_state_error:.0%}; "
                f"{_count(tuning.simulations, 'simulation')}, {tuning.seconds:.1f} s)"
            )
        lines.append(head)
        lines.extend("    " + row for row in _table(_rows(tuning)))
        for joint, why in tuning.reasons:
            lines.append(f"    {joint}: {why}")
    if report.messages:
        lines.append("  ManiSkill and SAPIEN said, each message once:")
        lines.extend(f"    {m.describe()}" for m in report.messages)
    if report.written:
        lines.append(f"wrote the new gains to {report.spec}")
    lines.extend(f"wrote {path}" for path in report.plots)
    problems = sorted(report.diagnostics, key=sort_key)
    lines.extend(d.format_text() for d in problems)
    counts = summary(report)
    lines.append(
        f"{counts['controllers']} controller(s): {counts['met']} met their targets as they "
        f"were, {counts['tuned']} tuned, {counts['failed']} failed, {counts['skipped']} "
        f"skipped; {counts['errors']} error(s), {counts['warnings']} warning(s)"
    )
    return "\n".join(lines)


def summary(report: TuneReport) -> dict[str, int]:
    statuses = [c.status for c in report.controllers]
    return {
        "controllers": len(statuses),
        "met": statuses.count("met"),
        "tuned": statuses.count("tuned"),
        "failed": statuses.count("failed"),
        "skipped": statuses.count("skipped"),
        "errors": sum(d.severity is Severity.ERROR for d in report.diagnostics),
        "warnings": sum(d.severity is Severity.WARNING for d in report.diagnostics),
    }


def _strict(value: float | None) -> float | str | None:
    if value is None:
        return None
    if not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return float(f"{value:.6g}")


def _side(gains: Gains | None, timing: Timing | None, k: int) -> dict[str, object]:
    side: dict[str, object] = {}
    if gains is not None:
        side |= {
            "stiffness": _strict(gains.stiffness[k]),
            "damping": _strict(gains.damping[k]),
            "force_limit": _strict(gains.force_limit[k]),
        }
    if timing is not None:
        side |= {
            "overshoot": _strict(timing.overshoot),
            "settling_time": _strict(timing.settling_time),
            "steady_state_error": _strict(timing.steady_state_error),
            "rise_time": _strict(timing.rise_time),
        }
    return side


def _controller_json(tuning: ControllerTuning) -> dict[str, object]:
    joints = []
    for k, joint in enumerate(tuning.joints):
        entry: dict[str, object] = {"joint": joint}
        if tuning.before_timings:
            entry["before"] = _side(tuning.before, tuning.before_timings[k], k)
            entry["after"] = _side(tuning.after, tuning.after_timings[k], k)
        joints.append(entry)
    targets = tuning.targets
    return {
        "controller": tuning.controller,
        "mode": tuning.mode,
        "group": tuning.group,
        "kind": tuning.kind,
        "status": tuning.status,
        "targets": None
        if targets is None
        else {
            "max_overshoot": targets.max_overshoot,
            "max_settling_time": targets.max_settling_time,
            "max_steady_state_error": targets.max_steady_state_error,
            "keep_force_limit": targets.keep_force_limit,
        },
        "joints": joints,
        "reasons": [{"joint": j, "why": why} for j, why in tuning.reasons],
        "simulations": tuning.simulations,
    }


def render_json(report: TuneReport) -> str:
    return json.dumps(
        {
            "spec": report.spec,
            "uid": report.uid,
            "status": "fail" if report.failed else "pass",
            "controllers": [_controller_json(c) for c in report.controllers],
            "written": report.written,
            "plots": report.plots,
            "diagnostics": [d.to_json() for d in sorted(report.diagnostics, key=sort_key)],
            "messages": [m.to_json() for m in report.messages],
            "summary": summary(report),
        },
        indent=2,
        allow_nan=False,
    )
