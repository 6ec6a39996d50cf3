"""``robospec demo``: ManiSkill's own robot viewer (``mani_skill.examples.demo_robot``) for a
spec, so people with a screen can look at the robot the way ManiSkill's docs suggest."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, SpecError, error
from robospec.diagnostics.codes import NO_VIEWER


def _no_screen() -> str | None:
    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        return "no display: neither DISPLAY nor WAYLAND_DISPLAY is set"
    return None


def run_demo(
    spec: Path, control_mode: str | None, keyframe: str | None, actions: str
) -> list[Diagnostic]:
    """Register ``spec``'s agent and open the viewer; the diagnostics when it cannot."""
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    if not compiled.ok or compiled.robot is None:
        return compiled.diagnostics
    robot = compiled.robot
    modes = [m.name for m in robot.modes]
    names = [k.name for k in robot.keyframes]
    wrong = []
    if control_mode is not None and control_mode not in modes:
        wrong.append(f"control mode '{control_mode}' is not one of: {', '.join(modes)}")
    if keyframe is not None and keyframe not in names:
        wrong.append(f"keyframe '{keyframe}' is not one of: {', '.join(names) or '(none)'}")
    if actions == "keyframe" and not names:
        wrong.append("--keyframe-actions needs a keyframe and the spec has none")
    screen = _no_screen()
    if screen is not None:
        wrong.append(f"the viewer needs a screen: {screen}")
    if wrong:
        hint = "robospec check runs the same robot headless, with numbers"
        return [error(Location(str(spec)), NO_VIEWER, w, hint) for w in wrong]

    from robospec.output.register import register

    try:
        register(spec)
    except SpecError as exc:
        return list(exc.diagnostics)
    from mani_skill.examples import demo_robot

    args = demo_robot.Args(
        robot_uid=robot.uid,
        control_mode=control_mode or modes[0],
        keyframe=keyframe,
        random_actions=actions == "random",
        keyframe_actions=actions == "keyframe",
    )
    try:
        demo_robot.main(args)
    except RuntimeError as exc:  # SAPIEN: no render device / window
        return [error(Location(str(spec)), NO_VIEWER, f"the viewer cannot open: {exc}")]
    except KeyboardInterrupt:
        pass
    return []
