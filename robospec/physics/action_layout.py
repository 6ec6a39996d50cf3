"""The action layout of every control mode: which action index drives which joint or group,
its bounds, and whether the action is normalized to [-1, 1] (then ``low``/``high`` are what -1
and 1 mean). This check never fails: it is the table people otherwise read out of
``_controller_configs`` by hand.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

import numpy as np

from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import ControllerGroup, Sim

if TYPE_CHECKING:
    from gymnasium import spaces

NAME = "action_layout"


def check(run: CheckRun) -> list[Finding]:
    return [_layout(run.sim(mode)) for mode in run.modes]


def _layout(sim: Sim) -> Finding:
    rows = []
    for group in sim.groups():
        rows.extend(_rows(sim, group))
    summary = "; ".join(_describe_group(sim, g) for g in sim.groups())
    return Finding(
        NAME,
        sim.mode,
        f"{len(rows)} dims",
        Status.INFO,
        summary,
        metrics(dims=len(rows)),
        (),
        tuple(rows),
    )


def _bounds(group: ControllerGroup) -> tuple[np.ndarray, np.ndarray, bool]:
    controller = group.controller
    normalized = bool(getattr(controller.config, "normalize_action", False))
    if normalized:
        return (
            controller.action_space_low.cpu().numpy(),
            controller.action_space_high.cpu().numpy(),
            True,
        )
    space = cast("spaces.Box", controller.single_action_space)
    return np.asarray(space.low), np.asarray(space.high), False


def _targets(sim: Sim, group: ControllerGroup) -> list[str]:
    width = group.action_slice.stop - group.action_slice.start
    kind = group.controller_kind
    named = kind.axis_names if kind is not None else ()
    if named and len(named) == width:
        return [f"{group.name}.{axis}" for axis in named]
    names = [sim.joint_names[j] for j in group.action_joint_indices]
    if group.with_velocities and 2 * len(names) == width:
        return names + [f"{name}.vel" for name in names]
    if len(names) == width:
        return names
    return [f"{group.name}[{i}]" for i in range(width)]


def _rows(sim: Sim, group: ControllerGroup) -> list[dict[str, Any]]:
    low, high, normalized = _bounds(group)
    return [
        metrics(
            index=group.action_slice.start + i,
            group=group.name,
            target=target,
            controller=type(group.controller).__name__,
            low=float(low[i]),
            high=float(high[i]),
            normalized=normalized,
        )
        for i, target in enumerate(_targets(sim, group))
    ]


def _describe_group(sim: Sim, group: ControllerGroup) -> str:
    start, stop = group.action_slice.start, group.action_slice.stop
    index = f"[{start}]" if stop - start == 1 else f"[{start}-{stop - 1}]"
    if stop == start:
        return f"{group.name}: no action"
    low, high, normalized = _bounds(group)
    span = f"{low.min():.3g}..{high.max():.3g}"
    return f"{index} {group.name}" + (f" (±1 → {span})" if normalized else f" ({span})")
