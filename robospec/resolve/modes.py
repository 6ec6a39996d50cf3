"""Control modes: each names one controller, or one controller per joint group."""

from __future__ import annotations

from robospec.diagnostics.codes import INVALID_VALUE, MISSING_FIELD, UNKNOWN_CONTROLLER
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath
from robospec.resolve.carried import part_controllers
from robospec.resolve.context import ResolveContext
from robospec.resolve.resolved import ResolvedMode


def resolve_modes(context: ResolveContext) -> list[ResolvedMode]:
    modes: list[ResolvedMode] = []
    for mode_name, mode in context.spec.control_modes.items():
        path: KeyPath = ("control_modes", mode_name)
        if isinstance(mode, str):
            _known_controller(context, mode, path)
            modes.append(ResolvedMode(mode_name, None, controller=mode))
            continue
        groups: list[tuple[str, str]] = []
        balance: bool | None = None
        for key, value in mode.items():
            if key == "balance_passive_force":
                if not isinstance(value, bool):
                    context.err(
                        (*path, key), INVALID_VALUE, "balance_passive_force must be true or false"
                    )
                else:
                    balance = value
                continue
            if not isinstance(value, str):
                context.err((*path, key), INVALID_VALUE, f"'{key}' must name a controller")
                continue
            _known_controller(context, value, (*path, key))
            groups.append((key, value))
        if not groups:
            context.err(path, MISSING_FIELD, f"control mode '{mode_name}' has no controllers")
        modes.append(ResolvedMode(mode_name, tuple(groups), balance_passive_force=balance))
    return modes


def _known_controller(context: ResolveContext, name: str, path: KeyPath) -> None:
    """A controller of the spec's, or one a part brings (robospec.resolve.carried)."""
    known = [*context.spec.controllers, *part_controllers(context)]
    if name not in known:
        context.err(
            path, UNKNOWN_CONTROLLER, f"unknown controller '{name}'", did_you_mean(name, known)
        )
