"""Read a robot description file named on the command line (URDF, xacro or MJCF), by suffix.

The parsing and xacro expansion are the resolver's own (:mod:`robospec.description`), so a
malformed file gets exactly the located diagnostics ``robospec validate`` gives.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from robospec.description import RobotDescription, load_description
from robospec.diagnostics import Diagnostic, Location, error

FileKind = Literal["urdf", "xacro", "mjcf"]

_SUFFIXES: dict[str, FileKind] = {
    ".urdf": "urdf",
    ".xacro": "xacro",
    ".xml": "mjcf",
    ".mjcf": "mjcf",
}


@dataclass(frozen=True)
class DescriptionFile:
    path: Path  # as given
    kind: FileKind
    description: RobotDescription
    robot_name: str | None  # <robot name=...> / <mujoco model=...>


def file_kind(path: Path) -> FileKind | None:
    return _SUFFIXES.get(path.suffix.lower())


def read_description_file(path: Path) -> tuple[DescriptionFile | None, list[Diagnostic]]:
    """The parsed description, or None and located diagnostics (never raises on bad input)."""
    kind = file_kind(path)
    if kind is None:
        return None, [
            error(
                Location(str(path)),
                "RS600",
                f"'{path.name}' is not a robot description robospec reads",
                "give a .urdf, .urdf.xacro/.xacro or MJCF .xml file",
            )
        ]
    text: str | bytes | None = None
    diagnostics: list[Diagnostic] = []
    if kind == "xacro":
        from robospec.description.xacro import expand_xacro

        text, diagnostics = expand_xacro(str(path), {})
        if text is None:
            return None, diagnostics
    description, more = load_description(str(path), "mjcf" if kind == "mjcf" else "urdf", text)
    diagnostics.extend(more)
    if description is None or any(d.is_error for d in diagnostics):
        return None, diagnostics
    if text is None:
        text = path.read_bytes()
    return DescriptionFile(path, kind, description, _robot_name(text)), diagnostics


def _robot_name(text: str | bytes) -> str | None:
    """The root element's name (URDF) or model (MJCF); the file parsed already, so it is XML."""
    from robospec.description.urdf import parse_xml

    root, _ = parse_xml(text, "")
    if root is None:
        return None
    name = root.get("name") or root.get("model")
    return name.strip() or None if name else None
