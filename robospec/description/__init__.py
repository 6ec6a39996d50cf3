"""Robot descriptions (URDF, MJCF) read into located, frozen facts.

Everything here imports only lxml and the standard library: it is on the fast validation path.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Literal

from robospec.description.facts import Joint, Link, Mimic, RobotDescription
from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import DESCRIPTION_NOT_FOUND, INTERNAL_ERROR

__all__ = [
    "Joint",
    "Link",
    "Mimic",
    "RobotDescription",
    "load_description",
]


def load_description(
    path: str,
    kind: Literal["urdf", "mjcf"],
    text: str | bytes | None = None,
    packages: Mapping[str, str] | None = None,
    *,
    beside_file: bool | None = None,
) -> tuple[RobotDescription | None, list[Diagnostic]]:
    """Parse the description at ``path`` (or ``text``, when given, located as ``path``).

    ``beside_file`` says whether the text stands for the file at ``path`` (a derived copy of
    it: its SRDF is read) or for another (a xacro expansion: none is); by default, whether no
    ``text`` was given.

    A file that cannot be read is RS050 at ``path:1:1``; nothing here raises on bad input.
    A URDF file's SRDF (``robot.srdf`` beside ``robot.urdf``), which SAPIEN reads by itself,
    gives the description's ``loader_collision_bits``. A URDF's meshes and textures are looked
    for beside ``path`` (``package://`` URIs with ``packages``, name -> absolute folder, first).
    Inside :func:`robospec.description.memo.remembering` an unchanged file is parsed once.
    """
    from robospec.description.memo import active_memo

    memo = active_memo()
    if memo is not None:
        return memo.load(
            path,
            kind,
            text,
            packages,
            lambda: _load_description(path, kind, text, packages, beside_file),
            beside_file,
        )
    return _load_description(path, kind, text, packages, beside_file)


def _load_description(
    path: str,
    kind: Literal["urdf", "mjcf"],
    text: str | bytes | None,
    packages: Mapping[str, str] | None,
    beside_file: bool | None = None,
) -> tuple[RobotDescription | None, list[Diagnostic]]:
    given_text = text is not None
    if beside_file is None:
        beside_file = not given_text
    if text is None:
        from robospec.description.urdf import read_file_bytes

        try:
            text = read_file_bytes(path)  # a regular file only: a FIFO would block the read
        except OSError as exc:
            reason = exc.strerror or type(exc).__name__
            return None, [
                error(
                    Location(path, 1, 1),
                    DESCRIPTION_NOT_FOUND,
                    f"cannot read robot description '{path}': {reason}",
                )
            ]
    if kind == "urdf":
        from robospec.description.urdf import parse_urdf

        description, diagnostics = parse_urdf(text, path, look_for_files=True, packages=packages)
        if description is not None and beside_file:
            # SAPIEN reads the SRDF beside a URDF file (not beside a xacro expansion)
            from robospec.description.srdf import read_srdf_bits

            bits, srdf_diagnostics = read_srdf_bits(path, description)
            diagnostics.extend(srdf_diagnostics)
            if bits:
                description = dataclasses.replace(description, loader_collision_bits=bits)
        return description, diagnostics
    if kind == "mjcf":
        from robospec.description.mjcf import parse_mjcf

        return parse_mjcf(text, path)
    return None, [error(Location(path, 1, 1), INTERNAL_ERROR, f"unknown description kind {kind!r}")]
