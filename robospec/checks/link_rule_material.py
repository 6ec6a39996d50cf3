"""RS312: every link rule names a material.

Passing::

    materials:
      grip: {static_friction: 2.0, dynamic_friction: 2.0, restitution: 0.0}
    links:
      "panda_*finger": {material: grip, patch_radius: 0.1, min_patch_radius: 0.1}

Failing (RS312: contact patches but no material)::

    links:
      "panda_*finger": {patch_radius: 0.1, min_patch_radius: 0.1}

ManiSkill 3 reads ``urdf_config``'s link entries only together with a material.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import LINK_RULE_WITHOUT_MATERIAL


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for pattern, rule in context.spec.links.items():
        if rule.material is None:
            yield error(
                context.key(("links", pattern)),
                LINK_RULE_WITHOUT_MATERIAL,
                f"link rule '{pattern}' has no material",
                "ManiSkill 3 requires a material in every link entry of urdf_config",
            )
