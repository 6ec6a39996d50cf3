"""Stage 6 for `build` and `register`: turn compiled specs into module files.

One function decides what files a set of robots becomes, so `robospec build` and
`robospec.register` cannot drift apart.
"""

from __future__ import annotations

import keyword
import os
import re
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error
from robospec.emit.generate import UnsafeIdentifier, emit_module
from robospec.emit.package import GENERATED_MARKER, emit_package_init
from robospec.resolve.resolved import FileRef, ResolvedRobot


def module_name_for(uid: str, taken: set[str]) -> str:
    # ASCII letters, digits and underscores only: the name becomes a file and an import
    name = re.sub(r"[^A-Za-z0-9_]", "_", uid).lower().strip("_") or "agent"
    if name[0].isdigit() or keyword.iskeyword(name):
        name = "agent_" + name
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def robot_files(robot: ResolvedRobot, module: str, module_dir: Path) -> dict[str, str]:
    """The files one robot needs beside its module: ``{file name: text}``."""
    files: dict[str, str] = {}
    description_file = None
    if robot.description.carried:
        description_file = f"{module}.urdf"
        files[description_file] = carried_urdf(robot.description, module_dir)
        srdf = _srdf_beside(robot.description)
        if srdf is not None:  # SAPIEN reads the SRDF beside the URDF it loads
            files[f"{module}.srdf"] = srdf
    files[f"{module}.py"] = emit_module(robot, module_dir, description_file)
    return files


def checked_robot_files(
    robot: ResolvedRobot, module: str, module_dir: Path, spec_display: str
) -> dict[str, str] | Diagnostic:
    """:func:`robot_files`, or an RS105 diagnostic at the spec when a name it gives cannot be a
    Python identifier (the generated code would not parse; spec text never becomes code)."""
    try:
        return robot_files(robot, module, module_dir)
    except UnsafeIdentifier as exc:
        return error(
            Location(spec_display),
            "RS105",
            f"{exc}: robospec names a generated class member after it",
            "rename it (Python keywords such as 'class' or 'None' cannot be member names)",
        )


def carried_urdf(ref: FileRef, module_dir: Path) -> str:
    """The URDF a generated package carries beside its module (a xacro expansion, or a URDF
    whose mesh URIs SAPIEN would resolve otherwise), with every mesh and texture robospec
    found named relative to ``module_dir``, and a comment that marks the file as ours."""
    from lxml import etree

    text = ref.generated_text if ref.generated_text is not None else ref.absolute.read_text()
    root = etree.fromstring(text.encode())
    found = dict(ref.mesh_paths)
    for element in root.iter("mesh", "texture"):
        filename = element.get("filename")
        if filename in found:
            moved = os.path.relpath(found[filename], module_dir)
            element.set("filename", Path(moved).as_posix())
    root.addprevious(etree.Comment(f" {GENERATED_MARKER} from {ref.relative}: do not edit "))
    text = etree.tostring(root.getroottree(), encoding="unicode", xml_declaration=False)
    return text if text.endswith("\n") else text + "\n"


def _srdf_beside(ref: FileRef) -> str | None:
    """The SRDF SAPIEN reads beside a URDF file (not beside a xacro expansion), if any."""
    if ref.generated_text is not None:
        return None
    from robospec.description.srdf import srdf_path

    srdf = Path(srdf_path(str(ref.absolute)))
    return srdf.read_text() if srdf.is_file() else None


def package_init(modules: list[tuple[str, str, str]]) -> str:
    """``__init__.py`` importing every module (importing registers the agents)."""
    return emit_package_init(modules)
