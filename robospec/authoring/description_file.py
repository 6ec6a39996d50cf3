"""Read a robot description file named on the command line (URDF, xacro or MJCF), by suffix.

The parsing and xacro expansion are the resolver's own (:mod:`robospec.description`), so a
malformed file gets exactly the located diagnostics ``robospec validate`` gives.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from robospec.description import RobotDescription, load_description

if TYPE_CHECKING:
    from robospec.derive import Derived
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
    # the XML the description was read from (a xacro file's expansion): ``new`` reads the
    # joint frames and, for MJCF, the keyframes and actuators from it; the derived copy when
    # the description needs mends
    text: bytes = b""
    # the mends it needs to load (robospec.derive): class -> policy, in the order they run
    mends: dict[str, Any] = field(default_factory=dict)


def file_kind(path: Path) -> FileKind | None:
    return _SUFFIXES.get(path.suffix.lower())


def read_description_file(
    path: Path, *, keep_errors: bool = False
) -> tuple[DescriptionFile | None, list[Diagnostic]]:
    """The parsed description, or None and located diagnostics (never raises on bad input).

    ``keep_errors`` keeps a description whose kinematic tree is intact although robospec found
    errors in it (a bad mimic target; what ManiSkill's loader would make of an MJCF: a mesh 1000
    times too large, a frame turned): ``inspect`` shows such a robot and its errors both."""
    path, problem = _placeholders_expanded(path)
    if problem is not None:
        return None, [problem]
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
    description_kind: Literal["urdf", "mjcf"] = "mjcf" if kind == "mjcf" else "urdf"
    mends, derived = _mended(path, description_kind, text, diagnostics)
    if derived is not None:
        text = derived.text
    description, more = load_description(
        str(path), description_kind, text, beside_file=kind != "xacro"
    )
    diagnostics.extend(derived.located(more, str(path)) if derived is not None else more)
    if description is None or (any(d.is_error for d in diagnostics) and not keep_errors):
        return None, diagnostics
    if text is None:
        text = path.read_bytes()
    data = text.encode("utf-8") if isinstance(text, str) else text
    robot_name = _robot_name(text)
    return DescriptionFile(path, kind, description, robot_name, data, mends), diagnostics


def _mended(
    path: Path,
    kind: Literal["urdf", "mjcf"],
    text: str | bytes | None,
    diagnostics: list[Diagnostic],
) -> tuple[dict[str, Any], Derived | None]:
    """The mends the description needs to load, and the derived copy (None when it needs
    none); the notes of what they change join ``diagnostics``."""
    from robospec.derive import Source, suggest_mends
    from robospec.description.urdf import read_file_bytes

    try:
        data = read_file_bytes(str(path)) if text is None else None
    except OSError:
        return {}, None  # the description's own load says why
    if data is None:
        data = text.encode("utf-8") if isinstance(text, str) else text or b""
    mends, derived = suggest_mends(Source(str(path), str(path), kind, data))
    if not mends:
        return {}, None
    diagnostics.extend(derived.notes)
    diagnostics.extend(derived.refusals)
    return mends, derived


def _placeholders_expanded(path: Path) -> tuple[Path, Diagnostic | None]:
    """``path`` with ``{maniskill_assets}`` or ``{maniskill_data}`` replaced by the folder it
    names, as a spec's description path is read (so ``robospec new
    "{maniskill_assets}/robots/panda/panda_v2.urdf"`` works as the spec would)."""
    from robospec.resolve.paths import (
        ASSETS_PLACEHOLDER,
        maniskill_assets_dir,
        maniskill_data_dir,
        split_assets,
        split_data,
    )

    text = str(path)
    inside = split_assets(text)
    if inside is not None:
        assets = maniskill_assets_dir()
        if assets is None:
            return path, error(
                Location(text),
                "RS050",
                f"{ASSETS_PLACEHOLDER} is ManiSkill's asset folder, and ManiSkill is not installed",
                "pip install 'robospec[maniskill]', or give the file's own path",
            )
        return assets / inside, None
    inside = split_data(text)
    if inside is not None:
        return maniskill_data_dir() / inside, None
    return path, None


def _robot_name(text: str | bytes) -> str | None:
    """The root element's name (URDF) or model (MJCF); the file parsed already, so it is XML."""
    from robospec.description.urdf import parse_xml

    root, _ = parse_xml(text, "")
    if root is None:
        return None
    name = root.get("name") or root.get("model")
    return name.strip() or None if name else None
