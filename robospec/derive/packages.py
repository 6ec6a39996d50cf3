"""Mend class ``packages: resolve`` (RS703): mesh URIs SAPIEN would not resolve as robospec does.

A ``package:///path`` URI names no package (three slashes: TALOS names 93 meshes so), and
SAPIEN resolves ``package://NAME/...`` only by looking for ``NAME/...`` above the URDF's folder,
not the way ROS (and robospec, robospec.description.packages) finds packages: either way the
collision shapes are silently left out (RS058, RS056). Each such URI is written as the path,
relative to the description's folder, of the file robospec found for it; a three-slash URI is
found the only way it can mean, below the description's folder or a folder above it.
"""

from __future__ import annotations

import os
from typing import Literal

from robospec.derive.document import Document
from robospec.description.meshes import file_references
from robospec.description.packages import (
    FILE_SCHEME,
    PACKAGE_SCHEME,
    PackageFinder,
    find_up,
    sapien_mesh_path,
)
from robospec.diagnostics.codes import (
    CANNOT_MEND,
    MENDED_MESH_URIS,
    MESH_NOT_FOUND,
    PACKAGE_NOT_FOUND,
)

NAME = "packages"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_MESH_URIS
FIXES = (PACKAGE_NOT_FOUND, MESH_NOT_FOUND)
WHY = "mesh URIs name no package (package:///...) or a file SAPIEN would not find"


def apply(document: Document, policy: str) -> None:
    base_dir = os.path.dirname(os.path.abspath(document.source.path))
    finder = PackageFinder(base_dir, document.source.packages)
    for named in file_references(document.tree):
        uri = named.uri
        if not uri.startswith((PACKAGE_SCHEME, FILE_SCHEME)):
            continue
        found = _found(uri, base_dir, finder)
        if found is None:
            if uri.startswith(PACKAGE_SCHEME + "/"):
                document.refuse(
                    named.element,
                    CANNOT_MEND,
                    f"mend 'packages' cannot resolve '{uri}' of {named.owner}: no folder from "
                    "the description's up holds that path",
                    "write package://NAME/path/in/package, or say where the files are",
                )
            continue  # a package found nowhere: RS058 says which, with where to say it
        loader = sapien_mesh_path(uri, base_dir)
        if loader is not None and os.path.samefile(loader, found):
            continue  # SAPIEN finds the same file: nothing to mend
        relative = os.path.relpath(found, base_dir).replace(os.sep, "/")
        named.element.set("filename", relative)
        document.changed(named.element, f"{named.owner} {named.role} file", uri, relative)


def _found(uri: str, base_dir: str, finder: PackageFinder) -> str | None:
    if uri.startswith(PACKAGE_SCHEME + "/"):
        return find_up(uri[len(PACKAGE_SCHEME) :], base_dir)
    if uri.startswith(PACKAGE_SCHEME):
        return finder.resolve(uri).path
    path = os.path.join(base_dir, uri[len(FILE_SCHEME) :])
    return path if os.path.isfile(path) else None


def suggest(document: Document) -> str | None:
    """Only where a URI names no package: other URIs robospec resolves by itself (the files
    are carried with the robot), and a package it cannot find needs the user's word."""
    if not any(
        named.uri.startswith(PACKAGE_SCHEME + "/") for named in file_references(document.tree)
    ):
        return None
    return "resolve" if document.would_change(apply, "resolve") else None
