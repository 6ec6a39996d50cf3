"""The collision-group bits SAPIEN's URDF loader takes from an SRDF beside the URDF.

SAPIEN 3.0.3 (``sapien/wrapper/urdf_loader.py``, which ManiSkill's loader inherits) reads
``<the URDF path minus "urdf">srdf`` whenever that file exists. For each
``<disable_collisions link1=... link2=... reason=.../>`` whose reason is "Default" (any case;
other reasons are ignored) and whose links are not parent and child, it sets the next bit of
collision group 2 — 0, 1, 2, ... in file order — on both links: one bit per pair, and it fails
at the 32nd. ``never_collide`` must leave those bits alone; the pairs themselves are already
non-colliding.

Only the standard library and lxml: this is on the validation path.
"""

from __future__ import annotations

import os

from robospec.description.facts import RobotDescription
from robospec.description.urdf import at, parse_xml
from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import DESCRIPTION_NOT_FOUND, INVALID_STRUCTURE
from robospec.diagnostics.suggest import did_you_mean

MAX_SRDF_BITS = 31  # SAPIEN raises "Too many collision groups" at the 32nd pair


def srdf_path(urdf_path: str) -> str:
    """Where SAPIEN looks for the SRDF of ``urdf_path`` (its ``urdf_file[:-4] + "srdf"``)."""
    return urdf_path[:-4] + "srdf"


def srdf_collision_bits(
    path: str, text: str | bytes, description: RobotDescription
) -> tuple[tuple[tuple[int, tuple[str, str]], ...], list[Diagnostic]]:
    """The bits SAPIEN sets from the SRDF ``text`` (read from ``path``): ``(bit, (link1,
    link2))`` in bit order, and what would make SAPIEN's loader fail, located in the SRDF."""
    root, diagnostics = parse_xml(text, path)
    if root is None:
        return (), diagnostics
    adjacent = description.adjacent_pairs()
    bits: list[tuple[int, tuple[str, str]]] = []
    for element in root.findall("disable_collisions"):
        reason = element.get("reason")
        first, second = element.get("link1"), element.get("link2")
        if reason is None or first is None or second is None:
            missing = [
                n for n, v in (("reason", reason), ("link1", first), ("link2", second)) if v is None
            ]
            diagnostics.append(
                error(
                    at(path, element),
                    INVALID_STRUCTURE,
                    f"<disable_collisions> without {', '.join(missing)}: SAPIEN's loader fails",
                )
            )
            continue
        if reason.lower() != "default":
            continue
        unknown = [n for n in (first, second) if description.link(n) is None]
        if unknown:
            diagnostics.append(
                error(
                    at(path, element),
                    INVALID_STRUCTURE,
                    f"unknown link '{unknown[0]}' in the SRDF: SAPIEN's loader fails",
                    did_you_mean(unknown[0], list(description.link_names)),
                )
            )
            continue
        if first == second:
            diagnostics.append(
                error(
                    at(path, element),
                    INVALID_STRUCTURE,
                    f"<disable_collisions> pairs link '{first}' with itself: SAPIEN's loader fails",
                )
            )
            continue
        pair = (min(first, second), max(first, second))
        if pair in adjacent:
            continue  # parent and child never collide anyway; SAPIEN spends no bit on them
        if len(bits) == MAX_SRDF_BITS:
            diagnostics.append(
                error(
                    at(path, element),
                    INVALID_STRUCTURE,
                    "more than 31 'Default' <disable_collisions> pairs that are not parent and "
                    "child: SAPIEN's loader fails with 'Too many collision groups'",
                )
            )
            break
        bits.append((len(bits), pair))
    return tuple(bits), diagnostics


def read_srdf_bits(
    urdf_path: str, description: RobotDescription
) -> tuple[tuple[tuple[int, tuple[str, ...]], ...], list[Diagnostic]]:
    """The SRDF bits of the URDF at ``urdf_path``; none when it has no SRDF beside it."""
    path = srdf_path(urdf_path)
    if not os.path.isfile(path):
        return (), []
    try:
        with open(path, "rb") as handle:
            text = handle.read()
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        # SAPIEN checks isfile, then opens: it fails the same way
        return (), [
            error(
                Location(path, 1, 1), DESCRIPTION_NOT_FOUND, f"cannot read SRDF '{path}': {reason}"
            )
        ]
    return srdf_collision_bits(path, text, description)
