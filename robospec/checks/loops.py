"""RS340: a closed loop joins two links that can move against each other.

A loop's drive holds a point of one link on a point of the other: it closes a cycle of joints
(a four-bar's crank, coupler and follower). Between two links of one rigid body (welded by
fixed joints) it closes nothing, and between a link and its parent or child it locks the one
joint between them.

Passing (the Robotiq 2F-85's left four-bar: knuckle and inner finger, on two branches)::

    loops:
      left: {links: [left_inner_knuckle, left_inner_finger],
             at: [[0, 0.0376, 0.043], [0, -0.0179, 0.0065]]}

Failing (the inner finger and its pad are welded)::

    loops:
      left: {links: [left_inner_finger, left_inner_finger_pad], at: [[0, 0, 0], [0, 0, 0]]}

That the two points meet at rest, and stay together while the robot moves, is for the
simulation to say: ``robospec check`` (RS530, RS531).
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import LOOP_BETWEEN_RIGID_LINKS
from robospec.resolve.mechanisms import tree_path

_HINT = (
    "a loop joins two links on different branches of the tree that meet at one point, as a "
    "four-bar's coupler meets its follower: name those two links"
)


def check(context: CheckContext) -> Iterator[Diagnostic]:
    description = context.description
    for loop in context.robot.loops:
        first, second = loop.links
        where = context.value(("loops", loop.name, "links"))
        if first == second:
            yield error(
                where,
                LOOP_BETWEEN_RIGID_LINKS,
                f"loop '{loop.name}' joins link '{first}' to itself",
                _HINT,
            )
            continue
        moving = [
            j
            for j in tree_path(description, first, second)
            if (joint := description.joint(j)) and joint.is_active
        ]
        if not moving:
            yield error(
                where,
                LOOP_BETWEEN_RIGID_LINKS,
                f"loop '{loop.name}' joins '{first}' and '{second}', which fixed joints weld "
                "into one rigid body: it closes nothing",
                _HINT,
            )
        elif len(moving) == 1:
            yield error(
                where,
                LOOP_BETWEEN_RIGID_LINKS,
                f"loop '{loop.name}' joins '{first}' and '{second}', which only joint "
                f"'{moving[0]}' moves against each other: it would lock that joint",
                _HINT,
            )
