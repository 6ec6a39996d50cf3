"""Read a robot description file named on the command line (URDF, xacro or MJCF), by suffix.

The loading is the resolver's own (:mod:`robospec.resolve.description_loading`), so a
malformed file gets exactly the located diagnostics ``robospec validate`` gives.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from robospec.description import RobotDescription
from robospec.diagnostics import Diagnostic, Location, error, has_errors
from robospec.diagnostics.codes import NOT_A_DESCRIPTION

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
    # the spec's mobile_base section the description was read with (``new``'s planar base:
    # robospec.authoring.new.mobile_base), and why the robot has one; None: none
    mobile_base: dict[str, Any] | None = None
    mobile_base_why: str | None = None
    # an MJCF compiled by MuJoCo (``loader: mujoco``): the description and ``text`` are the
    # URDF written from MuJoCo's model, ``mjcf`` the file's own bytes, ``why`` what ManiSkill's
    # MJCF loader would get wrong for it (robospec.authoring.mjcf_route)
    loader: str | None = None
    mjcf: bytes = b""
    why: str = ""


def file_kind(path: Path) -> FileKind | None:
    return _SUFFIXES.get(path.suffix.lower())


def read_description_file(
    path: Path,
    *,
    keep_errors: bool = False,
    sections: Mapping[str, Any] | None = None,
    compile_mjcf: bool = False,
) -> tuple[DescriptionFile | None, list[Diagnostic]]:
    """The parsed description, or None and located diagnostics (never raises on bad input).

    Read as a spec's description is (:mod:`robospec.resolve.description_loading`: a path
    relative to the working folder or starting with ``{maniskill_assets}``, xacro expanded),
    with the mends it needs to load. ``keep_errors`` keeps a description whose kinematic tree
    is intact although robospec found errors in it (a bad mimic target; what ManiSkill's loader
    would make of an MJCF: a mesh 1000 times too large, a frame turned): ``inspect`` shows such
    a robot and its errors both. ``sections``: what a spec's sections change in the derived
    copy (section -> settings, robospec.derive.SECTIONS: ``new``'s planar base), read as the
    spec that has them will read it. ``compile_mjcf`` (``new``): an MJCF MuJoCo compiles is
    read as the URDF written from MuJoCo's model (``loader: mujoco``); one it refuses as
    ManiSkill's MJCF loader reads it."""
    from robospec.resolve.description_loading import (
        DescriptionEntry,
        Loaded,
        Reader,
        load,
    )

    text = str(path)
    kind = file_kind(path)
    if kind is None:
        return None, [
            error(
                Location(text),
                NOT_A_DESCRIPTION,
                f"'{path.name}' is not a robot description robospec reads",
                "give a .urdf, .urdf.xacro/.xacro or MJCF .xml file",
            )
        ]
    if kind == "mjcf" and compile_mjcf:
        compiled, found = read_compiled_mjcf(path, sections)
        if compiled is not None:
            return compiled, found
    # the command line names the file itself: its problems are shown at the path as given
    reader = Reader(Path(""), Path(""), lambda _: Location(text), entry_is_file=True)
    loaded = load(reader, DescriptionEntry(text, kind, mends=None, sections=sections or {}))
    diagnostics = reader.diagnostics
    if not isinstance(loaded, Loaded) or (has_errors(diagnostics) and not keep_errors):
        return None, diagnostics
    ref = loaded.ref
    data = ref.read_bytes()
    if loaded.prepared.expanded:  # a URDF whose content is xacro (RS092): a spec names it so
        kind = "xacro"
    given = path if ref.kind == "file" else ref.absolute
    robot_name = _robot_name(data)
    return (
        DescriptionFile(given, kind, loaded.description, robot_name, data, loaded.prepared.mends),
        diagnostics,
    )


def read_compiled_mjcf(
    path: Path, sections: Mapping[str, Any] | None = None
) -> tuple[DescriptionFile | None, list[Diagnostic]]:
    """The MJCF at ``path`` as MuJoCo compiles it (``loader: mujoco``), with what ``sections``
    change in the derived copy (a planar base); None, with the diagnostics that say why, where
    MuJoCo refuses it (or the URDF written from it has errors)."""
    from robospec.authoring.mjcf_route import (
        maniskill_reading,
        mujoco_mends,
        why_mujoco,
        with_file_facts,
    )
    from robospec.derive import Source, mended_bytes
    from robospec.resolve.description_loading import DescriptionEntry, Loaded, Reader, load

    text = str(path)
    as_maniskill = maniskill_reading(text)
    # with the mends that change what MuJoCo itself reads (robospec.authoring.mjcf_route)
    reader = Reader(Path(""), Path(""), lambda _: Location(text), entry_is_file=True)
    mends = mujoco_mends(as_maniskill)
    entry = DescriptionEntry(text, "mjcf", mends=mends, sections=sections or {}, loader="mujoco")
    loaded = load(reader, entry)
    if not isinstance(loaded, Loaded) or has_errors(reader.diagnostics):
        return None, reader.diagnostics
    ref = loaded.ref
    mjcf: bytes | None = ref.absolute.read_bytes()
    mended = loaded.prepared.mends
    if mended:  # the MJCF MuJoCo compiled: the file with the same mends
        mjcf = mended_bytes(Source(str(ref.absolute), text, "mjcf", mjcf or b""), mended)
        if mjcf is None:
            return None, reader.diagnostics
    assert mjcf is not None
    given = path if ref.kind == "file" else ref.absolute
    description, maniskill = with_file_facts(loaded.description, as_maniskill)
    found = DescriptionFile(
        given,
        "mjcf",
        description,
        _robot_name(mjcf),
        ref.read_bytes(),
        mended,
        loader="mujoco",
        mjcf=mjcf,
        why=why_mujoco(mjcf, ref.absolute, maniskill),
    )
    return found, reader.diagnostics


def _robot_name(text: str | bytes) -> str | None:
    """The root element's name (URDF) or model (MJCF); the file parsed already, so it is XML."""
    from robospec.description.urdf import parse_xml

    root, _ = parse_xml(text, "")
    if root is None:
        return None
    name = root.get("name") or root.get("model")
    return name.strip() or None if name else None
