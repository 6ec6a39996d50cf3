"""The files a spec names — its robot description above all — found and loaded.

A path in a spec is relative to the spec file, or starts with ``{maniskill_assets}`` or
``{maniskill_data}`` (ManiSkill's folders). The description is parsed here, once (xacro
expanded first), and its diagnostics are shown under the path the user wrote, never this
machine's absolute path.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from robospec.description.facts import RobotDescription
from robospec.description.sanity import SANITY_CODES

if TYPE_CHECKING:
    from robospec.compose.model import Composed
    from robospec.derive import Derived
from robospec.diagnostics import Diagnostic, Location, without_codes
from robospec.load.source_map import KeyPath
from robospec.resolve.context import ResolveContext
from robospec.resolve.paths import (
    maniskill_assets_dir,
    maniskill_data_dir,
    split_assets,
    split_data,
)
from robospec.resolve.resolved import FileRef


def file_ref(
    context: ResolveContext, text: str, path: KeyPath, *, may_be_missing: bool = False
) -> FileRef | None:
    """The file ``text`` names; RS050 (and None) when it is not a readable file."""
    in_assets = split_assets(text)
    in_data = split_data(text)
    if in_data is not None:
        ref = FileRef("maniskill_data", in_data, maniskill_data_dir() / in_data)
    elif in_assets is not None:
        assets = maniskill_assets_dir()
        if assets is None:
            context.err(
                path,
                "RS050",
                f"'{text}' names ManiSkill's assets, but ManiSkill is not installed",
                "pip install 'robospec[maniskill]'",
            )
            return None
        ref = FileRef("maniskill_assets", in_assets, assets / in_assets)
    else:
        try:  # realpath, not Path.resolve: that raises RuntimeError on a loop of links (< 3.13)
            absolute = Path(os.path.realpath(context.spec_file.parent / text))
        except (OSError, ValueError) as exc:  # a NUL byte in the name
            context.err(path, "RS050", f"cannot use '{text}' as a file: {exc}")
            return None
        ref = FileRef("file", text, absolute)
    try:
        found = ref.absolute.is_file()
        exists = found or ref.absolute.exists()
    except (OSError, ValueError) as exc:  # a name too long for the file system, a NUL byte
        context.err(
            path, "RS050", f"cannot use '{text}' as a file: {getattr(exc, 'strerror', None) or exc}"
        )
        return None
    if exists and not found:  # a folder or a FIFO: there, but not a file to read
        what = "a folder" if ref.absolute.is_dir() else "not a regular file"
        context.err(path, "RS050", f"cannot use '{text}' as a file: it is {what}")
        return None
    if not found:
        if may_be_missing:
            return ref
        context.err(
            path,
            "RS050",
            f"file not found: '{text}'",
            f"looked for {ref.absolute}" if ref.kind == "file" else None,
        )
        return None
    return ref


def shown_path(context: ResolveContext, ref: FileRef) -> str:
    """How diagnostics name ``ref``: as the spec wrote it, relative to where robospec ran."""
    return ref.placeholder_text or str(Path(context.loaded.path).parent / ref.relative)


def load_spec_description(context: ResolveContext, mount: Mount | None = None) -> FileRef | None:
    """Load the description the spec's ``description:`` names (into the context). ``mount``:
    what writes the combined description of it and the spec's parts (robospec.resolve.parts),
    given the ref of the prepared description, its kind and shown name; it returns the ref of
    the combined text (and sets ``context.composed``), or None when the parts cannot be
    mounted."""
    desc = context.spec.description
    assert desc is not None
    prepared = _prepare(context, desc, ("description",))
    if prepared is None or isinstance(prepared, FileRef):
        return prepared  # could not be read, or not downloaded (names are assumed)
    ref, kind, shown, packages, derived = prepared
    if mount is not None:
        mounted = mount(context, ref, kind, shown)
        if mounted is None:
            return None
        ref = mounted
    description, ref = _load(context, ref, kind, shown, packages, derived, context.composed)
    context.loaded_description = description
    return ref if description is not None else None


Mount = Callable[[ResolveContext, FileRef, str, str], "FileRef | None"]


def load_part_description(
    context: ResolveContext, desc: Any, where: KeyPath
) -> tuple[FileRef, RobotDescription, str] | None:
    """A part's bare description (``parts.NAME.description``), expanded and mended as the
    spec's own: its file, its facts and how diagnostics name it."""
    prepared = _prepare(context, desc, where)
    if prepared is None or isinstance(prepared, FileRef):
        if isinstance(prepared, FileRef):  # not downloaded: nothing to mount yet
            context.err(
                (*where, desc.kind),
                "RS055",
                f"'{desc.path}' is not downloaded: the part cannot be mounted",
                "python -m mani_skill.utils.download_asset " + " ".join(desc.download),
            )
        return None
    ref, kind, shown, packages, derived = prepared
    description, ref = _load(context, ref, kind, shown, packages, derived, None)
    return (ref, description, shown) if description is not None else None


Prepared = tuple[FileRef, Literal["urdf", "mjcf"], str, dict[str, str], "Derived | None"]


def _prepare(context: ResolveContext, desc: Any, where: KeyPath) -> Prepared | FileRef | None:
    """The description entry at ``where`` found, expanded (xacro) and mended (derive): its
    ref (with the text robospec wrote, if any), kind, shown name, packages and derivation. A
    download ManiSkill has not fetched yet gives its bare ref (the context's description is
    then assumed from the spec's names)."""
    path: KeyPath = (*where, desc.kind)
    packages = package_folders(context, desc, where)
    ref = file_ref(context, desc.path, path, may_be_missing=bool(desc.download))
    if ref is None:
        return None
    shown = shown_path(context, ref)
    if not ref.absolute.is_file():  # a download ManiSkill has not fetched yet
        if where != ("description",):
            return ref
        from robospec.description.assumed import assumed_description

        context.warn(
            path,
            "RS055",
            f"'{desc.path}' is not downloaded: joint and link names are not checked",
            "python -m mani_skill.utils.download_asset " + " ".join(desc.download),
        )
        context.assumed = True
        context.loaded_description = assumed_description(context.spec, shown)
        return ref
    mends = desc.mend.model_dump(exclude_none=True) if desc.mend is not None else {}
    if desc.kind == "xacro":
        from robospec.description.xacro import expand_xacro

        args = {k: _xacro_arg(v) for k, v in desc.args.items()}
        text, diags = expand_xacro(str(ref.absolute), args, packages=packages)
        context.diagnostics.extend(_relocate(diags, str(ref.absolute), shown))
        if text is None:
            return None
        shown += " (expanded)"
        ref = dataclasses.replace(ref, generated_text=text, has_srdf_beside=False)
    kind: Literal["urdf", "mjcf"] = "mjcf" if desc.kind == "mjcf" else "urdf"
    derived = None
    if mends:
        found = _derive(context, ref, kind, shown, packages, mends, where, path)
        if found is None:
            return None
        ref, derived = found
    return ref, kind, shown, packages, derived


def _load(
    context: ResolveContext,
    ref: FileRef,
    kind: Literal["urdf", "mjcf"],
    shown: str,
    packages: dict[str, str],
    derived: Derived | None,
    composed: Composed | None,
) -> tuple[RobotDescription | None, FileRef]:
    """Parse the description ``ref`` holds (its text, when robospec wrote one); its problems
    go to the context under the file the user wrote (each element's own, when composed)."""
    from robospec.description import load_description

    description, diags = load_description(
        str(ref.absolute),
        kind,
        text=ref.generated_text,
        packages=packages,
        beside_file=ref.has_srdf_beside,
    )
    if derived is not None:
        diags = derived.located(diags, str(ref.absolute)) if composed is None else diags
    diags = _unless_shipped(diags, ref)
    if composed is not None:
        from robospec.compose.model import relocate

        # each element at its file and line in the combined text's sources; the robot's own
        # at the line of its derived text, which the derivation then maps to the user's file
        diags = relocate(diags, str(ref.absolute), composed)
        if derived is not None:
            diags = derived.located(diags, shown)
        context.diagnostics.extend(diags)
    else:
        context.diagnostics.extend(_relocate(diags, str(ref.absolute), shown))
    # an expansion or a derived copy is written elsewhere: every path it names moves with it
    always = ref.generated_text is not None
    ref = dataclasses.replace(ref, mesh_paths=_carried_mesh_paths(description, always=always))
    return description, ref


def _derive(
    context: ResolveContext,
    ref: FileRef,
    kind: Literal["urdf", "mjcf"],
    shown: str,
    packages: dict[str, str],
    mends: dict[str, Any],
    where: KeyPath = ("description",),
    file_path: KeyPath = ("description",),
) -> tuple[FileRef, Derived] | None:
    """The spec's mends applied to a copy of the description (robospec.derive): the notes of
    what changed, in the description; what the spec asked that does not fit, at its entry."""
    from robospec.derive import NOT_FOR_KIND, STALE, Source, derive, mend_class
    from robospec.diagnostics.suggest import did_you_mean

    if ref.generated_text is not None:
        data = ref.generated_text.encode("utf-8")
    else:
        from robospec.description.urdf import read_file_bytes

        try:
            data = read_file_bytes(str(ref.absolute))
        except OSError as exc:
            context.err(
                file_path,
                "RS050",
                f"cannot read robot description '{shown}': {exc.strerror or exc}",
            )
            return None
    derived = derive(Source(str(ref.absolute), shown, kind, data, packages), mends)
    context.diagnostics.extend(derived.notes)
    context.diagnostics.extend(derived.refusals)
    for outcome in derived.outcomes:
        at: KeyPath = (*where, "mend", outcome.name)
        policy = _policy_text(mends[outcome.name])
        if outcome.status == "stale":
            context.warn(
                at,
                STALE,
                f"mend '{outcome.name}: {policy}' changes nothing in '{shown}'",
                "remove it (robospec new writes only the mends a robot needs)",
            )
        elif outcome.status == "not_for_kind":
            mend = mend_class(outcome.name)
            kinds = " and ".join(sorted(mend.KINDS)).upper() if mend is not None else "other"
            from robospec.derive import MENDS

            fitting = [m.NAME for m in MENDS if kind in m.KINDS]
            context.err(
                at,
                NOT_FOR_KIND,
                f"mend '{outcome.name}' is for {kinds} descriptions, and '{shown}' is "
                f"{kind.upper()}",
                did_you_mean(outcome.name, fitting)
                or f"{kind.upper()} mends: {', '.join(fitting)}",
            )
    return dataclasses.replace(ref, generated_text=derived.text, derived=True), derived


def _policy_text(policy: Any) -> str:
    if isinstance(policy, list):
        return "[" + ", ".join(f"{p:g}" if isinstance(p, float) else str(p) for p in policy) + "]"
    return str(policy)


def package_folders(
    context: ResolveContext, desc: Any = None, entry: KeyPath = ("description",)
) -> dict[str, str]:
    """The ``packages`` of the description entry at ``entry`` (the spec's own by default), each
    an absolute folder; a folder that is not there is RS058 at its value (and left out)."""
    desc = desc if desc is not None else context.spec.description
    assert desc is not None
    folders: dict[str, str] = {}
    for name, text in desc.packages.items():
        where: KeyPath = (*entry, "packages", name)
        in_assets, in_data = split_assets(text), split_data(text)
        if in_data is not None:
            folder = maniskill_data_dir() / in_data
        elif in_assets is not None:
            assets = maniskill_assets_dir()
            if assets is None:
                context.err(
                    where,
                    "RS050",
                    f"'{text}' names ManiSkill's assets, but ManiSkill is not installed",
                    "pip install 'robospec[maniskill]'",
                )
                continue
            folder = assets / in_assets
        else:
            try:  # realpath, as file_ref: a NUL byte or a loop of links is not a folder
                folder = Path(os.path.realpath(context.spec_file.parent / text))
            except (OSError, ValueError) as exc:
                context.err(where, "RS058", f"package '{name}': cannot use '{text}': {exc}")
                continue
        try:
            is_folder = folder.is_dir()
        except OSError:  # a name too long for the file system
            is_folder = False
        if not is_folder:
            context.err(
                where,
                "RS058",
                f"package '{name}': no folder '{text}'",
                f"looked for {folder}" if in_assets is None and in_data is None else None,
            )
            continue
        folders[name] = str(folder)
    return folders


def _carried_mesh_paths(
    description: RobotDescription | None, *, always: bool
) -> tuple[tuple[str, str], ...]:
    """``uri -> file`` for every mesh robospec found, when the generated package must carry
    the URDF: ``always``, or when SAPIEN's loader would open another file (or none) for one of
    them. Empty otherwise: ManiSkill loads the description where it is."""
    if description is None:
        return ()
    found = {m.uri: m.path for m in description.mesh_files if m.path is not None}
    moved = any(
        m.path is not None
        and (m.loader_path is None or os.path.normpath(m.loader_path) != os.path.normpath(m.path))
        for m in description.mesh_files
    )
    return tuple(found.items()) if always or moved else ()


def load_inherited_description(
    context: ResolveContext, base: Any
) -> tuple[FileRef | None, Literal["urdf", "mjcf"]]:
    """The description an ``extends`` class names, for a spec that gives none."""
    from robospec.description import load_description

    text = getattr(base, "mjcf_path", None) or getattr(base, "urdf_path", None)
    kind: Literal["urdf", "mjcf"] = "mjcf" if getattr(base, "mjcf_path", None) else "urdf"
    if not isinstance(text, str):
        context.err(
            ("extends",),
            "RS220",
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
        context.err(("extends",), "RS050", f"the extended class's description is missing: {text}")
        return None, kind
    description, diags = load_description(str(path), kind)
    diags = _unless_shipped(diags, ref)
    context.diagnostics.extend(_relocate(diags, str(path), shown_path(context, ref)))
    context.loaded_description = description
    return (ref if description is not None else None), kind


# Warnings about a description's physics that only editing the file can answer (an inertial
# SAPIEN ignores, an impossible inertia): not said of the descriptions ManiSkill ships, which a
# spec cannot change and ManiSkill's own agents load as they are (Fetch's fingers, the Allegro
# hand). Errors are said of every description.
_WARNINGS_NOT_FOR_SHIPPED = frozenset({"RS061", "RS062"}) | SANITY_CODES


def _unless_shipped(diagnostics: list[Diagnostic], ref: FileRef) -> list[Diagnostic]:
    if ref.kind == "file":
        return diagnostics
    return without_codes(diagnostics, _WARNINGS_NOT_FOR_SHIPPED)


def _xacro_arg(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _relocate(diagnostics: list[Diagnostic], absolute: str, shown: str) -> list[Diagnostic]:
    """Show description diagnostics under the path the user wrote, not this machine's path."""
    out = []
    for d in diagnostics:
        if d.location.file == absolute:
            d = Diagnostic(
                Location(shown, d.location.line, d.location.column),
                d.code,
                d.severity,
                d.message,
                d.hint,
            )
        out.append(d)
    return out
