"""The files a spec names — its robot description above all — found and loaded, through the
one description service (:mod:`robospec.resolve.description_loading`), with the spec's keys
as the places its problems are shown.

A path in a spec is relative to the spec file, or starts with ``{maniskill_assets}`` or
``{maniskill_data}`` (ManiSkill's folders). The description is parsed here, once (xacro
expanded first), and its diagnostics are shown under the path the user wrote, never this
machine's absolute path.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import Any, Literal

from robospec.description.facts import RobotDescription
from robospec.diagnostics.codes import (
    DESCRIPTION_NOT_FOUND,
    NOT_DOWNLOADED,
    UNUSABLE_PYTHON_REFERENCE,
)
from robospec.load.source_map import KeyPath
from robospec.resolve.context import ResolveContext
from robospec.resolve.description_loading import (
    DescriptionEntry,
    Prepared,
    Reader,
    find_file,
    parse,
    prepare,
)
from robospec.resolve.paths import maniskill_assets_dir
from robospec.resolve.resolved import FileRef


def reader(context: ResolveContext, entry: KeyPath = ()) -> Reader:
    """The spec as a reader of descriptions: its paths against its folder, the problems of the
    description entry at ``entry`` at its keys (into the context's diagnostics)."""
    return Reader(
        context.spec_file.parent,
        Path(context.loaded.path).parent,
        lambda where: context.at_value((*entry, *where)),
        context.diagnostics,
    )


def file_ref(
    context: ResolveContext, text: str, path: KeyPath, *, may_be_missing: bool = False
) -> FileRef | None:
    """The file ``text`` (at ``path`` in the spec) names; RS050 (and None) when it is not a
    readable file."""
    return find_file(reader(context), text, path, may_be_missing=may_be_missing)


def shown_path(context: ResolveContext, ref: FileRef) -> str:
    """How diagnostics name ``ref``: as the spec wrote it, relative to where robospec ran."""
    return reader(context).shown(ref)


def load_spec_description(context: ResolveContext, mount: Mount | None = None) -> FileRef | None:
    """Load the description the spec's ``description:`` names (into the context). ``mount``:
    what writes the combined description of it and the spec's parts (robospec.resolve.parts),
    given the ref of the prepared description, its kind and shown name; it returns the ref of
    the combined text (and sets ``context.composed``), or None when the parts cannot be
    mounted."""
    desc = context.spec.description
    assert desc is not None
    read = reader(context, ("description",))
    prepared = prepare(read, DescriptionEntry.of(desc, context.spec))
    if prepared is None:
        return None
    if isinstance(prepared, FileRef):  # not downloaded: names are assumed
        from robospec.description.assumed import assumed_description

        context.warn(
            ("description", desc.kind),
            NOT_DOWNLOADED,
            f"'{desc.path}' is not downloaded: joint and link names are not checked",
            "python -m mani_skill.utils.download_asset " + " ".join(desc.download),
        )
        context.assumed = True
        context.loaded_description = assumed_description(context.spec, read.shown(prepared))
        return prepared
    if mount is not None:
        mounted = mount(context, prepared.ref, prepared.kind, prepared.shown)
        if mounted is None:
            return None
        prepared = dataclasses.replace(prepared, ref=mounted)
    description, ref = parse(read, prepared, context.composed)
    context.loaded_description = description
    return ref if description is not None else None


Mount = Callable[[ResolveContext, FileRef, str, str], "FileRef | None"]


def load_part_description(
    context: ResolveContext, desc: Any, where: KeyPath
) -> tuple[FileRef, RobotDescription, str] | None:
    """A part's bare description (``parts.NAME.description``), expanded and mended as the
    spec's own: its file, its facts and how diagnostics name it."""
    read = reader(context, where)
    prepared = prepare(read, DescriptionEntry.of(desc))
    if isinstance(prepared, FileRef):  # not downloaded: nothing to mount yet
        context.err(
            (*where, desc.kind),
            NOT_DOWNLOADED,
            f"'{desc.path}' is not downloaded: the part cannot be mounted",
            "python -m mani_skill.utils.download_asset " + " ".join(desc.download),
        )
        return None
    if prepared is None:
        return None
    description, ref = parse(read, prepared)
    return (ref, description, prepared.shown) if description is not None else None


def load_inherited_description(
    context: ResolveContext, base: Any
) -> tuple[FileRef | None, Literal["urdf", "mjcf"]]:
    """The description an ``extends`` class names, for a spec that gives none: the class's own
    file, which the generated agent names as the class does (never a copy)."""
    text = getattr(base, "mjcf_path", None) or getattr(base, "urdf_path", None)
    kind: Literal["urdf", "mjcf"] = "mjcf" if getattr(base, "mjcf_path", None) else "urdf"
    if not isinstance(text, str):
        context.err(
            ("extends",),
            UNUSABLE_PYTHON_REFERENCE,
            "the extended class names no urdf_path or mjcf_path",
            "add a description to the spec",
        )
        return None, kind
    assets = maniskill_assets_dir()
    path = Path(text)
    if assets is not None and path.is_relative_to(assets):
        ref = FileRef("maniskill_assets", path.relative_to(assets).as_posix(), path)
    else:
        ref = FileRef("file", text, path)
    if not path.is_file():
        context.err(
            ("extends",),
            DESCRIPTION_NOT_FOUND,
            f"the extended class's description is missing: {text}",
        )
        return None, kind
    read = reader(context)
    description, _ = parse(read, Prepared(ref, kind, read.shown(ref)))
    context.loaded_description = description
    return (ref if description is not None else None), kind
