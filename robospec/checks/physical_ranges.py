"""RS106: a number no physical robot can have: a negative gain, friction or force limit, a
restitution outside [0, 1], a camera that sees nothing. The schema takes any number there (and
ManiSkill too: a stiffness of -1000 builds, and the joint is pushed away from its target).

Passing::

    arm: {type: pd_joint_pos, joints: arm, stiffness: 1e3, damping: 1e2, force_limit: 100}

Failing (RS106: stiffness must be at least 0)::

    arm: {type: pd_joint_pos, joints: arm, stiffness: -1000, damping: 1e2}
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import OUTSIDE_PHYSICAL_RANGE

# field -> (lowest, highest, whether the lowest itself is allowed, unit and what a value
# outside means)
_DRIVE = {
    "stiffness": (
        0.0,
        math.inf,
        True,
        "a negative stiffness pushes the joint away from its target",
    ),
    "damping": (0.0, math.inf, True, "a negative damping feeds energy into the motion"),
    "force_limit": (0.0, math.inf, True, "a force limit is a magnitude (N or N·m)"),
    "friction": (0.0, math.inf, True, "a negative friction drives the joint"),
}
_MATERIAL = {
    "static_friction": (0.0, math.inf, True, "a friction coefficient is a magnitude"),
    "dynamic_friction": (0.0, math.inf, True, "a friction coefficient is a magnitude"),
    "restitution": (0.0, 1.0, True, "0: no bounce, 1: a perfectly elastic bounce"),
}
_LINK = {
    "density": (0.0, math.inf, False, "a density (kg/m³) is positive"),
    "patch_radius": (0.0, math.inf, True, "a radius is a length"),
    "min_patch_radius": (0.0, math.inf, True, "a radius is a length"),
}


def _range(low: float, high: float, closed: bool) -> str:
    if high == math.inf:
        return f"{'≥' if closed else '>'} {low:g}"
    return f"from {low:g} to {high:g}"


def _outside(value: Any, low: float, high: float, closed: bool) -> list[float]:
    values = value if isinstance(value, (list, tuple)) else [value]
    numbers = [v for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)]
    return [v for v in numbers if v < low or (v == low and not closed) or v > high]


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for controller in context.robot.controllers:
        kwargs = dict(controller.kwargs)
        for field, (low, high, closed, meaning) in _DRIVE.items():
            bad = _outside(kwargs.get(field), low, high, closed)
            if bad:
                yield _error(
                    context,
                    ("controllers", controller.name, field),
                    field,
                    bad,
                    (low, high, closed),
                    meaning,
                )
    config = context.robot.urdf_config
    for name, material in (config.get("_materials") or {}).items():
        for field, (low, high, closed, meaning) in _MATERIAL.items():
            bad = _outside(material.get(field), low, high, closed)
            if bad:
                yield _error(
                    context, ("materials", name, field), field, bad, (low, high, closed), meaning
                )
    for pattern, rule in _link_rules(context):
        for field, (low, high, closed, meaning) in _LINK.items():
            bad = _outside(rule.get(field), low, high, closed)
            if bad:
                yield _error(
                    context, ("links", pattern, field), field, bad, (low, high, closed), meaning
                )
    for camera in context.robot.cameras:
        path = ("cameras", camera.uid)
        if camera.near <= 0:
            yield _error(
                context,
                (*path, "near"),
                "near",
                [camera.near],
                (0.0, math.inf, False),
                "the near plane lies in front of the camera",
            )
        if camera.far <= camera.near:
            yield _error(
                context,
                (*path, "far"),
                "far",
                [camera.far],
                (camera.near, math.inf, False),
                "the far plane lies beyond the near one",
            )
        if camera.fov is not None and not 0 < camera.fov < math.pi:
            yield _error(
                context,
                (*path, "fov"),
                "fov",
                [camera.fov],
                (0.0, math.pi, False),
                "a field of view (radians) is between 0 and pi",
            )


def _link_rules(context: CheckContext) -> list[tuple[str, dict[str, Any]]]:
    rules = []
    for pattern, rule in (context.spec.links or {}).items():
        values = {f: getattr(rule, f, None) for f in _LINK}
        rules.append((pattern, values))
    return rules


def _error(
    context: CheckContext,
    path: tuple[str, ...],
    field: str,
    bad: list[float],
    bounds: tuple[float, float, bool],
    meaning: str,
) -> Diagnostic:
    shown = ", ".join(f"{v:g}" for v in bad)
    return error(
        context.value(path),
        OUTSIDE_PHYSICAL_RANGE,
        f"{field} {shown} is out of range: {field} is {_range(*bounds)}",
        meaning,
    )
