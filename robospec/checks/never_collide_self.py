"""RS322: never_collide does nothing when ``loader.disable_self_collisions`` is true.

``disable_self_collisions`` sets bit 29 of collision group 2 on every link, so no two of the
robot's links collide at all; the bits never_collide would pack are not set.

Passing::

    loader: {disable_self_collisions: false}
    never_collide: [[panda_link5, panda_hand]]

Failing (warning)::

    loader: {disable_self_collisions: true}
    never_collide: [[panda_link5, panda_hand]]
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import NEVER_COLLIDE_WITHOUT_EFFECT


def check(context: CheckContext) -> Iterator[Diagnostic]:
    record = context.robot.never_collide
    if record is None or not record.skipped:
        return
    yield warning(
        context.key(("never_collide",)),
        NEVER_COLLIDE_WITHOUT_EFFECT,
        "never_collide has no effect: loader.disable_self_collisions already keeps every pair "
        "of the robot's links from colliding",
        "remove never_collide, or set disable_self_collisions to false to choose the pairs",
    )
