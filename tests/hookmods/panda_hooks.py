"""Hook functions named by the extends/hooks example specs (tests/specs/*/hooks_*.yaml)."""

from __future__ import annotations

from typing import Any

CALLS: list[tuple[str, str]] = []


def after_loading(agent: Any) -> None:
    CALLS.append(("after_loading_articulation", agent.uid))


def after_init(agent: Any) -> None:
    CALLS.append(("after_init", agent.uid))
    agent.hooked = True


def gripper_opening(self: Any) -> Any:
    """An extra method: the distance between the fingers."""
    return self.robot.get_qpos()[..., -2:].sum(dim=-1)


def no_arguments() -> None:
    """Not a hook: it cannot take the agent."""


LIMIT = 0.04
