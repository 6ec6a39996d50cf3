"""RS307: collision-group bits that ManiSkill itself uses.

Bit 29 of group 2 is what ``disable_self_collisions`` sets; bits 30 and 31 of group 2 are, by
ManiSkill's convention, set on the ground by its scenes (so links with them ignore the floor,
which is what a mobile base's wheels want — and what nothing else wants).

Passing::

    collision_rules: [{links: [l_wheel_link], group: 2, bit: 12}]

Failing (warning)::

    collision_rules: [{links: [l_wheel_link], group: 2, bit: 29}]
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import RESERVED_COLLISION_BIT
from robospec.maniskill.scenes import GROUND_BITS

RESERVED = {
    29: "bit 29 of group 2 is the one disable_self_collisions sets on every link",
    **{
        bit: f"bit {bit} of group 2 is set on the ground by ManiSkill's scenes: these links will "
        "not collide with the floor"
        for bit in GROUND_BITS
    },
}


def check(context: CheckContext) -> Iterator[Diagnostic]:
    # the spec's own rules; those never_collide adds after them use bits below 29 only
    own = context.robot.collision_rules[: len(context.spec.collision_rules)]
    for index, rule in enumerate(own):
        if rule.group == 2 and rule.bit in RESERVED:
            yield warning(
                context.value(("collision_rules", index, "bit")),
                RESERVED_COLLISION_BIT,
                RESERVED[rule.bit],
                "intended for a mobile base over the ground; otherwise pick a bit below 29",
            )
