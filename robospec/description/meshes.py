"""The files a URDF's visuals and collisions name: found, readable, and where SAPIEN finds them.

SAPIEN's URDF loader never says that a mesh is missing or unreadable: it hands the name to
PhysX, which fails, and the link silently loads without that collision shape (a visual just
shows nothing). So robospec looks for every file first, on lxml and ``os`` alone (this runs in
``validate``):

- a ``<collision>`` mesh that is missing (RS056) or unreadable (RS057) is an error, a
  ``<visual>`` mesh or texture a warning (physics does not need it);
- ``package://NAME/...`` is resolved the ROS way (robospec.description.packages); a package
  found nowhere is RS058, once per package;
- each file records where SAPIEN's own loader would find it from the description's folder, so
  that a description whose files SAPIEN finds elsewhere (or not at all) can be carried with
  its paths rewritten (robospec.output.modules).
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Literal

from lxml import etree

from robospec.description.facts import MeshFile
from robospec.description.mesh_formats import unreadable_reason
from robospec.description.packages import (
    FILE_SCHEME,
    PACKAGE_SCHEME,
    PackageFinder,
    sapien_mesh_path,
)
from robospec.description.source_columns import element_at
from robospec.description.urdf_values import Findings
from robospec.diagnostics import Diagnostic, error, warning
from robospec.diagnostics.codes import (
    MESH_NOT_FOUND,
    MESH_UNREADABLE,
    MIRRORED_MESH,
    PACKAGE_NOT_FOUND,
)

Role = Literal["collision", "visual", "texture"]


@dataclass(frozen=True)
class _Named:
    """One file reference in the XML: the element, what it is for, and for whom."""

    element: etree._Element
    uri: str
    role: Role
    owner: str  # "link 'x'" or "material 'm'": for messages


def check_mesh_files(
    root: etree._Element,
    path: str,
    packages: Mapping[str, str] | None = None,
) -> tuple[tuple[MeshFile, ...], list[Diagnostic]]:
    """Every mesh and texture file the URDF ``root`` (read from ``path``) names, looked for.

    Relative names are taken against ``path``'s folder, as SAPIEN does; ``packages`` maps
    package names to absolute folders (the spec's ``description.packages``).
    """
    base_dir = os.path.dirname(os.path.abspath(path))
    finder = PackageFinder(base_dir, packages)
    found_all = Findings()
    files: list[MeshFile] = []
    unknown_packages: dict[str, list[_Named]] = {}
    for named in file_references(root):
        if named.role == "collision" and _mirrored(named.element):
            found_all.add(
                error(
                    element_at(path, named.element),
                    MIRRORED_MESH,
                    f"collision mesh '{named.uri}' of {named.owner} is mirrored "
                    f'(scale="{named.element.get("scale")}"): PhysX cannot build a mirrored '
                    "convex mesh, and SAPIEN's process dies in native code at its first "
                    "contact with another",
                    "`description: {mend: {mirrors: copies}}` names a mirrored copy of the file "
                    "instead (docs/mends.md)",
                ),
                fold_as="more mirrored collision meshes",
            )
        found, problem = locate(named.uri, base_dir, finder)
        if problem is not None:
            unknown_packages.setdefault(problem, []).append(named)
        elif found is None:
            # a whole folder of meshes not there (not unpacked, not downloaded) is one finding
            folder = os.path.dirname(named.uri)
            where = f" in '{folder}'" if folder else ""
            found_all.add(
                _not_found(path, named, _looked_for(named.uri, base_dir)),
                fold_as=f"more {_what(named, plural=True)}{where} not found",
            )
        elif named.role != "texture":  # an image, which the mesh checks do not apply to
            reason = unreadable_reason(found)
            if reason is not None:
                found_all.add(
                    _report(
                        path,
                        named,
                        MESH_UNREADABLE,
                        f"{_what(named)} '{named.uri}' of {named.owner}: SAPIEN cannot read "
                        f"it: {reason}",
                        _LOST[named.role],
                    )
                )
                found = None
        line = named.element.sourceline or 1
        # SAPIEN takes a plain path as robospec does; only URIs can lead it elsewhere
        loader_path = sapien_mesh_path(named.uri, base_dir) if "://" in named.uri else found
        files.append(MeshFile(named.uri, named.role, line, found, loader_path))
    for package, uses in unknown_packages.items():
        found_all.add(_unknown_package(path, package, uses))
    return tuple(files), found_all.result()


def file_references(root: etree._Element) -> Iterator[_Named]:
    """The ``filename``s SAPIEN's loader reads: link meshes, and material textures (those of
    a link's visuals and the top-level ones its visuals name)."""
    for link in root.iterfind("link"):
        owner = f"link '{link.get('name')}'"
        for role in ("visual", "collision"):
            for mesh in link.iterfind(f"{role}/geometry/mesh"):
                uri = mesh.get("filename")
                if uri:  # a mesh without one is a structure error (robospec.description.urdf)
                    yield _Named(mesh, uri, role, owner)
        for texture in link.iterfind("visual/material/texture"):
            if texture.get("filename"):
                yield _Named(texture, texture.get("filename", ""), "texture", owner)
    for texture in root.iterfind("material/texture"):
        if texture.get("filename"):
            owner = f"material '{texture.getparent().get('name')}'"  # type: ignore[union-attr]
            yield _Named(texture, texture.get("filename", ""), "texture", owner)


def locate(uri: str, base_dir: str, finder: PackageFinder) -> tuple[str | None, str | None]:
    """(the file, None), (None, None) when it is not there, or (None, package name) when the
    package itself is not found."""
    if uri.startswith(PACKAGE_SCHEME):
        found = finder.resolve(uri)
        if found.root is None:
            return None, found.package
        return found.path, None
    if uri.startswith(FILE_SCHEME):
        uri = uri[len(FILE_SCHEME) :]
    elif "://" in uri:
        return None, None  # another scheme (http://, model://): SAPIEN reads local files
    candidate = os.path.join(base_dir, uri)
    return (candidate if os.path.isfile(candidate) else None), None


def _looked_for(uri: str, base_dir: str) -> str:
    if uri.startswith(PACKAGE_SCHEME):
        return ""
    if "://" in uri and not uri.startswith(FILE_SCHEME):
        return "SAPIEN reads files on disk only: name the mesh by a path or a package:// URI"
    plain = uri[len(FILE_SCHEME) :] if uri.startswith(FILE_SCHEME) else uri
    return f"looked for {os.path.normpath(os.path.join(base_dir, plain))}"


def _what(named: _Named, *, plural: bool = False) -> str:
    noun = "texture" if named.role == "texture" else f"{named.role} mesh"
    return noun + ("es" if plural and noun.endswith("mesh") else "s" if plural else "")


# What a missing or unreadable file costs in SAPIEN, by what it is for.
_LOST: dict[Role, str] = {
    "collision": "the link loads without this collision shape",
    "visual": "the link loads without this visual (physics is not affected)",
    "texture": "the visual loads without this texture (physics is not affected)",
}


def _report(path: str, named: _Named, code: str, message: str, hint: str | None) -> Diagnostic:
    where = element_at(path, named.element)
    report = error if named.role == "collision" else warning
    return report(where, code, message, hint)


def _not_found(path: str, named: _Named, looked: str) -> Diagnostic:
    hint = "; ".join(part for part in (_LOST[named.role], looked) if part)
    if named.uri.startswith(PACKAGE_SCHEME):
        package = named.uri[len(PACKAGE_SCHEME) :].partition("/")[0]
        hint = f"{_LOST[named.role]}; package '{package}' has no such file"
    return _report(
        path,
        named,
        MESH_NOT_FOUND,
        f"{_what(named)} '{named.uri}' of {named.owner} not found",
        hint,
    )


def _unknown_package(path: str, package: str, uses: list[_Named]) -> Diagnostic:
    """One diagnostic per package found nowhere, at its first collision use (else first use)."""
    first = next((u for u in uses if u.role == "collision"), uses[0])
    others = len(uses) - 1
    more = f" and {others} more file{'s' if others != 1 else ''}" if others else ""
    if not package:
        return _report(
            path,
            first,
            PACKAGE_NOT_FOUND,
            f"'{first.uri}' names no package (three slashes after 'package:'){more}",
            "write package://NAME/path/in/package",
        )
    return _report(
        path,
        first,
        PACKAGE_NOT_FOUND,
        f"ROS package '{package}' not found for {_what(first)} '{first.uri}' of "
        f"{first.owner}{more}",
        f"say where it is in the spec: `description: {{packages: {{{package}: FOLDER}}}}` "
        f"(no package.xml names it, and no folder '{package}' holds these files, from the "
        "description's folder up)",
    )


def _mirrored(mesh: etree._Element) -> bool:
    """Whether a mesh's scale has a negative factor (it is drawn mirrored)."""
    try:
        return any(float(v) < 0 for v in (mesh.get("scale") or "").split())
    except ValueError:
        return False  # not numbers: the loader rules say so
