"""RS326: the keyframe each episode resets to sets the joints' positions.

Passing::

    keyframes:
      rest: {qpos: {arm: [0, pi/8, 0, -5*pi/8, 0, 3*pi/4, pi/4], gripper: 0.04}}
    reset: {keyframe: rest}

Failing (RS326: ``mounted`` places the root only)::

    keyframes:
      mounted: {pose: {p: [0, 0, 0.5]}}
    reset: {keyframe: mounted}

Without ``reset.keyframe`` the agent resets to the first keyframe where that one sets joint
positions, and keeps ManiSkill's behaviour (joints left where they are) where it does not.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import RESET_WITHOUT_QPOS


def check(context: CheckContext) -> Iterator[Diagnostic]:
    name = context.spec.reset.keyframe
    frame = context.spec.keyframes.get(name) if name is not None else None
    if frame is not None and frame.qpos is None:
        yield error(
            context.value(("reset", "keyframe")),
            RESET_WITHOUT_QPOS,
            f"keyframe '{name}' sets no joint positions to reset to",
            f"give keyframe '{name}' a qpos, or name one that has one",
        )
