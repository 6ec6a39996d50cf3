"""RS321: never_collide needed more collision-group bits than were free, so it also keeps pairs
of links it does not list from colliding.

Each bit of collision group 2 keeps every link carrying it from colliding with every other
(robospec packs ``never_collide`` into the fewest such cliques). Bits 0-28 are all there is,
less the bits the robot description's loader sets (SRDF pairs, MJCF bodies), the spec's own
``collision_rules`` and ``scene_collision_bits``. When the cliques outnumber the free bits,
robospec merges the two whose union disables the fewest other pairs, until they fit, and
lists every pair disabled that way.

Passing::

    never_collide: [[panda_link5, panda_hand], "panda_*finger"]

Failing (warning): panda_v2's SRDF takes bits 0-6, the scenes 7-27, leaving bit 28 alone::

    scene_collision_bits: [7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24,
                           25, 26, 27]
    never_collide: [[panda_link1, panda_link3], [panda_link2, panda_link6]]
    # one bit on links 1, 2, 3 and 6: link1/link6 and link3/link6 stop colliding too
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import NEVER_COLLIDE_OVERREACHES


def check(context: CheckContext) -> Iterator[Diagnostic]:
    record = context.robot.never_collide
    if record is None:
        return
    for index, pairs in record.side_effects:
        shown = ", ".join(f"{a}/{b}" for a, b in pairs)
        yield warning(
            context.value(("never_collide", index)),
            NEVER_COLLIDE_OVERREACHES,
            f"not enough free collision-group bits ({len(record.available)}): never_collide "
            f"also keeps {len(pairs)} pair(s) it does not list from colliding: {shown}",
            "free bits (fewer scene_collision_bits or collision_rules bits), or list these "
            "pairs in never_collide if they may pass through each other",
        )
