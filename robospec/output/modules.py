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
from robospec.diagnostics.codes import INVALID_IDENTIFIER
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


def robot_files(
    robot: ResolvedRobot, module: str, module_dir: Path, *, self_contained: bool = False
) -> dict[str, str | bytes]:
    """The files one robot needs beside its module: ``{file name: text or bytes}``.

    ``self_contained`` (``build``): a description robospec derived is written with a copy of
    every mesh and texture it names, so the package loads where the original folder is absent;
    otherwise (``register``'s cache, on the machine that has the originals) it names them where
    they are."""
    files: dict[str, str | bytes] = {}
    description_file = None
    ref = robot.description
    if ref.carried and robot.description_kind == "mjcf":
        description_file = f"{module}.xml"
        files.update(_carried_mjcf(ref, module, module_dir, description_file, self_contained))
    elif ref.carried:
        description_file = f"{module}.urdf"
        found = sorted({path for _uri, path in ref.mesh_paths})
        copies = _copies(found, module) if self_contained and ref.derived else {}
        files[description_file] = carried_urdf(ref, module_dir, copies)
        for source, name in copies.items():
            files[name] = Path(source).read_bytes()
        srdf = _srdf_beside(ref)
        if srdf is not None:  # SAPIEN reads the SRDF beside the URDF it loads
            files[f"{module}.srdf"] = srdf
    files[f"{module}.py"] = emit_module(robot, module_dir, description_file)
    return files


def checked_robot_files(
    robot: ResolvedRobot,
    module: str,
    module_dir: Path,
    spec_display: str,
    *,
    self_contained: bool = False,
) -> dict[str, str | bytes] | Diagnostic:
    """:func:`robot_files`, or an RS105 diagnostic at the spec when a name it gives cannot be a
    Python identifier (the generated code would not parse; spec text never becomes code)."""
    try:
        return robot_files(robot, module, module_dir, self_contained=self_contained)
    except UnsafeIdentifier as exc:
        return error(
            Location(spec_display),
            INVALID_IDENTIFIER,
            f"{exc}: robospec names a generated class member after it",
            "rename it (Python keywords such as 'class' or 'None' cannot be member names)",
        )


def _carried_mjcf(
    ref: FileRef, module: str, module_dir: Path, name: str, self_contained: bool
) -> dict[str, str | bytes]:
    """A derived MJCF and (``self_contained``) a copy of each file it names, beside the
    module (robospec.derive.mjcf_files)."""
    from lxml import etree

    from robospec.derive.mjcf_files import carried_text, named_files

    assert ref.generated_text is not None
    root = etree.fromstring(ref.generated_text.encode("utf-8"))
    found = sorted({path for _element, path in named_files(root, str(ref.absolute))})
    copies = _copies([p for p in found if os.path.isfile(p)], module) if self_contained else {}

    def name_of(path: str) -> str:
        return copies.get(path) or Path(os.path.relpath(path, module_dir)).as_posix()

    text = carried_text(ref.generated_text, str(ref.absolute), name_of)
    how = f"with {', '.join(ref.parts)} mounted" if ref.parts else "mended"
    files: dict[str, str | bytes] = {
        name: f"<!-- {GENERATED_MARKER} from {ref.relative}, {how}: do not edit -->\n{text}"
    }
    for source, copy in copies.items():
        files[copy] = Path(source).read_bytes()
    return files


def _copies(found: list[str], module: str) -> dict[str, str]:
    """A file name beside the module for each file the description names: ``{found: name}``,
    ``<module>.<file name>`` (numbered when two files share a name), in a stable order."""
    copies: dict[str, str] = {}
    taken: set[str] = set()
    for source in found:
        stem, suffix = os.path.splitext(os.path.basename(source))
        stem = re.sub(r"[^A-Za-z0-9_.\-]", "_", stem) or "file"
        name, n = f"{module}.{stem}{suffix}", 1
        while name.lower() in taken:  # case-insensitive file systems too
            n += 1
            name = f"{module}.{stem}_{n}{suffix}"
        taken.add(name.lower())
        copies[source] = name
    return copies


def carried_urdf(ref: FileRef, module_dir: Path, copies: dict[str, str] | None = None) -> str:
    """The URDF a generated package carries beside its module (a xacro expansion, a derived
    description, or a URDF whose mesh URIs SAPIEN would resolve otherwise), with every mesh
    and texture robospec found named relative to ``module_dir`` (or by its copy's name there,
    from ``copies``), and a comment that marks the file as ours."""
    from lxml import etree

    text = ref.read_text()
    root = etree.fromstring(text.encode())
    found = dict(ref.mesh_paths)
    copies = copies or {}
    for element in root.iter("mesh", "texture"):
        filename = element.get("filename")
        if filename in found:
            copied = copies.get(found[filename])
            moved = copied if copied is not None else os.path.relpath(found[filename], module_dir)
            element.set("filename", Path(moved).as_posix())
    how = ", mended" if ref.derived else ""
    if ref.parts:
        how = f", with {', '.join(ref.parts)} mounted"
    root.addprevious(etree.Comment(f" {GENERATED_MARKER} from {ref.relative}{how}: do not edit "))
    text = etree.tostring(root.getroottree(), encoding="unicode")  # text: no XML declaration
    return text if text.endswith("\n") else text + "\n"


def _srdf_beside(ref: FileRef) -> str | None:
    """The SRDF SAPIEN reads beside a URDF file (not beside a xacro expansion), if any."""
    if not ref.has_srdf_beside:
        return None
    from robospec.description.srdf import srdf_path

    srdf = Path(srdf_path(str(ref.absolute)))
    return srdf.read_text() if srdf.is_file() else None


def package_init(modules: list[tuple[str, str, str]]) -> str:
    """``__init__.py`` importing every module (importing registers the agents)."""
    return emit_package_init(modules)
