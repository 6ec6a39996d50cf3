"""Composed descriptions: a robot and the parts mounted on it (a gripper, a hand), written as
one description.

Design. A spec's ``parts:`` mount other robots — each a spec of its own or a bare description —
at links of its robot. This stage is pure: it takes the texts of the descriptions (each
already expanded and mended by the derive stage, :mod:`robospec.derive`) and writes the
combined text, URDF with URDF (:mod:`robospec.compose.urdf`), MJCF with MJCF
(:mod:`robospec.compose.mjcf`). Names of a part that the robot (or a part mounted before it)
already has get the part's prefix; the others are kept, so a part's names read as they do in
its own file. Every element of the combined text remembers the file and line it came from
(:class:`Origins`), so whatever a later stage reports about it points at the user's file — the
arm's, the hand's, or, for the joint that mounts a part, the spec's ``parts:`` entry.

The result goes the way every derived description goes: the resolve stage parses it
(:func:`robospec.resolve.description_files.load_spec_description`) and hands its text on in
the robot's ``FileRef``, so ``register``, ``build`` (self-contained, with copies of the meshes),
``check``, ``tune``, ``optimize`` and the language server load the combined description.
What comes along from a part's spec (controllers, keyframes, tcp, ...) is merged after
resolution, by :mod:`robospec.resolve.parts`.

Only lxml and the standard library are imported here: composing runs on the validate path.
"""

from __future__ import annotations

from collections.abc import Sequence

from robospec.compose.model import (
    BaseSource,
    Composed,
    Kind,
    Mounted,
    Origins,
    PartSource,
    Problem,
    relocate,
)
from robospec.compose.order import mount_order
from robospec.diagnostics.codes import MIXED_FORMATS

__all__ = [
    "BaseSource",
    "Composed",
    "Kind",
    "Mounted",
    "Origins",
    "PartSource",
    "Problem",
    "compose",
    "mixed_formats",
    "mount_order",
    "relocate",
]


def compose(base: BaseSource, parts: Sequence[PartSource]) -> Composed:
    """Mount ``parts`` on ``base`` (in an order where each part's link exists when it is
    mounted), as one description of ``base``'s kind."""
    mixed = [p for p in parts if p.kind != base.kind]
    if mixed:
        problems = tuple(mixed_formats(base.kind, p.name, p.kind, p.key) for p in mixed)
        return Composed(base.kind, None, Origins(()), problems=problems)
    if base.kind == "urdf":
        from robospec.compose.urdf import compose_urdf

        return compose_urdf(base, parts)
    from robospec.compose.mjcf import compose_mjcf

    return compose_mjcf(base, parts)


def mixed_formats(base: Kind, name: str, kind: str, key: str) -> Problem:
    """RS735: a part of the other kind. URDF has no form for an MJCF body's several joints, its
    geoms' defaults or its sites, and ManiSkill's MJCF loader reads no URDF element; robospec
    writes no converter between the two that would keep every mass, limit and shape."""
    if base == "urdf":
        why = (
            f"part '{name}' is MJCF and this robot is URDF: robospec writes a combined URDF "
            "from URDF parts only (an MJCF body may carry several joints, and its defaults, "
            "geoms and masses have no URDF form robospec writes)"
        )
        hint = "mount a URDF of the part (or describe this robot in MJCF)"
    else:
        why = (
            f"part '{name}' is URDF and this robot is MJCF: robospec writes a combined MJCF "
            "from MJCF parts only (ManiSkill's MJCF loader reads no URDF element, and robospec "
            "writes no URDF-to-MJCF conversion that keeps every inertia and shape)"
        )
        hint = "mount an MJCF of the part (or describe this robot in URDF)"
    del kind
    return Problem(("parts", name, key), MIXED_FORMATS, why, hint)
