"""RS323: ``never_collide`` found a collision-group bit free for each pair it lists.

Passing (the scenes use bits 7-27: bit 28 is free)::

    scene_collision_bits: [7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23,
                           24, 25, 26, 27]

Failing (RS323: panda_v2's SRDF takes bits 0-6 and the scenes 7-28: none is left)::

    scene_collision_bits: [7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23,
                           24, 25, 26, 27, 28]
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import NO_FREE_COLLISION_BIT
from robospec.resolve.collision_packing import FREE_BITS


def check(context: CheckContext) -> Iterator[Diagnostic]:
    record = context.robot.never_collide
    if record is None or not record.uncovered:
        return
    taken = ", ".join(str(b) for b in FREE_BITS if b not in record.available)
    yield error(
        context.value(("never_collide",)),
        NO_FREE_COLLISION_BIT,
        f"no collision-group bit is free for never_collide: bits 0-28 of group 2 are all "
        f"used ({taken}); {len(record.uncovered)} listed pair(s) would still collide",
        "list fewer scene_collision_bits or collision_rules bits; bits the robot "
        "description's loader sets (SRDF pairs, MJCF bodies) cannot be freed",
    )
