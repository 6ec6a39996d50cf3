"""Step responses as pictures: one PNG per controller, each joint's response against the target
(``robospec check --plot DIR`` and ``robospec tune --plot DIR``; the robot card links them).

The file is ``DIR/<uid>/<controller>.png``: a panel per series (``check``: the response;
``tune``: before and after), each joint's response as a fraction of the step over time, the
target (1), the settling band around it and, where given, the tuning targets (the overshoot
allowed, the settling time). matplotlib draws with its Agg backend: no display needed.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes


class StepTrace(Protocol):
    """What a plot reads of a measured step (``robospec.physics.step_response.StepTrace``,
    frozen: read-only properties)."""

    @property
    def kind(self) -> str: ...
    @property
    def joints(self) -> tuple[str, ...]: ...
    @property
    def dt(self) -> float: ...
    @property
    def fraction(self) -> np.ndarray: ...
    @property
    def size(self) -> np.ndarray: ...


LEGEND_JOINTS = 12  # more joints than this: no legend (the lines would hide the plot)


@dataclass(frozen=True)
class Limits:
    """What a response is held to, drawn on the plot."""

    settling_band: float
    max_overshoot: float | None = None
    max_settling_time: float | None = None


def plot_path(folder: Path, uid: str, controller: str) -> Path:
    return folder / uid / f"{controller}.png"


def plot_controller(
    folder: Path,
    uid: str,
    controller: str,
    series: Sequence[tuple[str, StepTrace]],
    limits: Limits,
) -> Path:
    """Write ``controller``'s step response(s) to :func:`plot_path`; returns the path.
    ``series`` is ``[(title, trace), ...]``, one panel each, side by side."""
    return write_plot(plot_path(folder, uid, controller), f"{uid}: {controller}", series, limits)


def write_plot(
    path: Path, title: str, series: Sequence[tuple[str, StepTrace]], limits: Limits
) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    figure = Figure(figsize=(5.5 * len(series), 4.0), layout="constrained")
    axes = figure.subplots(1, len(series), squeeze=False, sharey=True)[0]
    for ax, (label, trace) in zip(axes, series, strict=True):
        _panel(ax, label, trace, limits)
    values = np.concatenate([t.fraction[np.isfinite(t.fraction)] for _, t in series])
    top = max(1.0 + limits.settling_band, float(values.max()) if values.size else 1.0)
    bottom = min(0.0, float(values.min()) if values.size else 0.0)
    axes[0].set_ylim(max(bottom, -2.0) - 0.05, min(top, 3.0) + 0.05)  # shared by the panels
    figure.suptitle(title)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, staging = tempfile.mkstemp(prefix=".robospec-", suffix=".png", dir=path.parent)
    os.close(handle)
    try:
        figure.savefig(staging, format="png", dpi=90)
        os.chmod(staging, 0o644)  # as a file the user wrote (mkstemp makes it private)
        os.replace(staging, path)
    except BaseException:
        Path(staging).unlink(missing_ok=True)
        raise
    return path


def _panel(ax: Axes, label: str, trace: StepTrace, limits: Limits) -> None:
    times = (np.arange(trace.fraction.shape[0]) + 1) * trace.dt
    for k, joint in enumerate(trace.joints):
        if trace.size[k] == 0:  # held, not stepped
            continue
        ax.plot(times, trace.fraction[:, k], linewidth=1.0, label=joint)
    ax.axhline(1.0, color="black", linewidth=1.2, label="target")
    band = limits.settling_band
    ax.axhspan(1.0 - band, 1.0 + band, color="tab:green", alpha=0.12, label="settling band")
    if limits.max_overshoot is not None:
        ax.axhline(
            1.0 + limits.max_overshoot,
            color="tab:red",
            linestyle="--",
            linewidth=0.8,
            label="max overshoot",
        )
    if limits.max_settling_time is not None:
        ax.axvline(
            limits.max_settling_time,
            color="tab:red",
            linestyle=":",
            linewidth=0.8,
            label="max settling time",
        )
    unit = "velocity" if trace.kind == "velocity" else "position"
    ax.set_title(label)
    ax.set_xlabel("time after the step (s)")
    ax.set_ylabel(f"{unit} (fraction of the step)")
    ax.set_xlim(0.0, float(times[-1]))
    ax.grid(True, alpha=0.3)
    if len(trace.joints) <= LEGEND_JOINTS:
        ax.legend(fontsize="x-small", loc="lower right")
