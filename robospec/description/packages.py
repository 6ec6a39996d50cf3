"""Where ``package://NAME/...`` and xacro's ``$(find NAME)`` point: ROS packages found without ROS.

A ROS package is a folder whose ``package.xml`` says ``<name>NAME</name>``; ROS tools find it on
a package path. robospec has no package path, so it looks where a description's packages
usually are, in this order:

1. the spec's ``description.packages`` map (``NAME: folder``), when it names NAME;
2. the folder of the description and each folder above it, for one whose ``package.xml`` names
   NAME (the description lives inside its own package: ``ridgeback_description`` is the folder
   ``clearpath_ridgeback_description``);
3. each of those folders for a sub-folder called NAME that holds the file (the folder name is
   the package name, as in most checkouts and pip packages; this is also the one way SAPIEN's
   URDF loader resolves ``package://`` URIs, see :func:`sapien_mesh_path`).

This module imports only the standard library: the xacro child process loads it by its path to
answer ``$(find NAME)`` the same way (robospec itself is not importable there).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

PACKAGE_SCHEME = "package://"
FILE_SCHEME = "file://"

# <name> of a package.xml (format 1 to 3): the first <name> element, comments removed first.
_COMMENT = re.compile(rb"<!--.*?-->", re.DOTALL)
_NAME = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
# A package.xml is small; reading more than this is not worth it to learn a name.
_PACKAGE_XML_LIMIT = 1 << 16


def package_xml_name(folder: str) -> str | None:
    """The package name ``folder/package.xml`` declares, or None (no such file, no name)."""
    try:
        with open(os.path.join(folder, "package.xml"), "rb") as handle:
            data = handle.read(_PACKAGE_XML_LIMIT)
    except OSError:
        return None
    match = _NAME.search(_COMMENT.sub(b"", data))
    return match.group(1).decode("utf-8", "replace") if match else None


def _folders_up(start: str) -> Iterator[str]:
    """``start`` and every folder above it, up to the file system's root."""
    folder = os.path.abspath(start)
    while True:
        yield folder
        parent = os.path.dirname(folder)
        if parent == folder:
            return
        folder = parent


@dataclass(frozen=True)
class PackageFile:
    """Where a ``package://`` URI points, and how robospec found its package."""

    package: str
    path: str | None  # the file (absolute), None when no package or no file was found
    root: str | None  # the package's folder, None when no package of that name was found
    how: str  # "packages map", "package.xml" or "folder name": for messages


class PackageFinder:
    """Finds ROS packages from one description's folder, with the spec's explicit map.

    ``explicit`` maps package names to absolute folders; lookups are cached per name, so a
    description naming a package a hundred times walks the folders once.
    """

    def __init__(self, start: str, explicit: Mapping[str, str] | None = None) -> None:
        self.start = os.path.abspath(start)
        self.explicit = dict(explicit or {})
        self._declared: dict[str, str | None] = {}

    def declared_root(self, name: str) -> tuple[str | None, str]:
        """The folder of package ``name`` by the map or a ``package.xml`` above the start,
        and how it was found; (None, "") when neither names it."""
        if name in self.explicit:
            return self.explicit[name], "packages map"
        if name not in self._declared:
            self._declared[name] = next(
                (f for f in _folders_up(self.start) if package_xml_name(f) == name), None
            )
        root = self._declared[name]
        return (root, "package.xml") if root is not None else (None, "")

    def find(self, name: str) -> str | None:
        """The package's folder, as ``$(find NAME)`` means it: declared, else the nearest
        folder called NAME beside the description's folder or above it."""
        root, _how = self.declared_root(name)
        if root is not None:
            return root
        return next(
            (os.path.join(f, name) for f in _folders_up(self.start) if _is_dir(f, name)), None
        )

    def resolve(self, uri: str) -> PackageFile:
        """Where ``package://NAME/REST`` points (``uri`` must start with ``package://``)."""
        name, _, rest = uri[len(PACKAGE_SCHEME) :].partition("/")
        root, how = self.declared_root(name) if name else (None, "")
        if root is not None:
            path = os.path.join(root, rest)
            return PackageFile(name, path if os.path.isfile(path) else None, root, how)
        if not name:
            return PackageFile(name, None, None, "")
        # the first folder NAME, from the description's folder up, that holds the file
        nearest: str | None = None
        for folder in _folders_up(self.start):
            if not _is_dir(folder, name):
                continue
            root = os.path.join(folder, name)
            nearest = nearest or root
            path = os.path.join(root, rest)
            if os.path.isfile(path):
                return PackageFile(name, path, root, "folder name")
        return PackageFile(name, None, nearest, "folder name" if nearest else "")


def _is_dir(folder: str, name: str) -> bool:
    return os.path.isdir(os.path.join(folder, name))


def sapien_mesh_path(filename: str, urdf_dir: str) -> str | None:
    """The file SAPIEN 3.0.3's URDF loader opens for ``filename``, or None when it finds none.

    A copy of ``sapien.wrapper.urdf_loader._try_very_hard_to_find_file`` as ManiSkill calls it
    (``package_dir`` is None; SAPIEN's loop overwrites it anyway): ``package://`` is cut off and
    the rest is looked for below the URDF's folder and each folder above it; anything else is
    taken relative to the URDF's folder. A file it does not find is passed on as written, and
    PhysX then fails to load it: the shape is left out without a word.
    """
    if filename.startswith(PACKAGE_SCHEME):
        rest = filename[len(PACKAGE_SCHEME) :]
        for folder in _folders_up(urdf_dir):
            path = os.path.join(folder, rest)
            if os.path.isfile(path):
                return path
        return None
    path = os.path.join(os.path.abspath(urdf_dir), filename)
    return path if os.path.isfile(path) else None


def find_up(rest: str, start: str) -> str | None:
    """The file ``rest`` (a relative path) below ``start`` or the nearest folder above it that
    holds it: where a ``package:///rest`` URI, which names no package, can only mean."""
    rest = rest.lstrip("/")
    if not rest:
        return None
    for folder in _folders_up(start):
        path = os.path.join(folder, rest)
        if os.path.isfile(path):
            return path
    return None
