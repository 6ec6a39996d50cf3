"""RS324: no link rules on an MJCF robot.

ManiSkill applies a spec's link rules (``urdf_config``'s link entries: material, patch radii,
density) through its loader's ``set_link_material`` and friends, which only the URDF loader
has: with an MJCF robot ``gym.make`` fails with ``'MJCFLoader' object has no attribute
'set_link_material'``.

Passing::

    description: {mjcf: robot.xml}
    materials:
      grip: {static_friction: 2.0, dynamic_friction: 2.0, restitution: 0.0}

Failing (RS324: a link rule on an MJCF robot)::

    description: {mjcf: robot.xml}
    materials:
      grip: {static_friction: 2.0, dynamic_friction: 2.0, restitution: 0.0}
    links:
      "finger_*": {material: grip}
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import LINK_RULE_ON_MJCF


def check(context: CheckContext) -> Iterator[Diagnostic]:
    if context.robot.description_kind != "mjcf":
        return
    for pattern in context.spec.links:
        yield error(
            context.key(("links", pattern)),
            LINK_RULE_ON_MJCF,
            f"link rule '{pattern}' on an MJCF robot: ManiSkill's MJCF loader has no "
            "set_link_material (nor patch radius or density setters), so loading fails",
            "set the friction in the MJCF (geom friction=, density=) and remove the rule",
        )
