"""Description loading: one service for every reader of a robot description named by a path.

    path as written ──placeholders──▶ the file (a FileRef) ──xacro──▶ URDF text
        ──mends (robospec.derive)──▶ the derived copy ──parse (robospec.description)──▶ facts

Its readers: the resolve stage, for a spec's description and its parts'
(:mod:`robospec.resolve.description_files`); ``robospec new`` and ``inspect``, for a file named
on the command line (:mod:`robospec.authoring.description_file`); the language server, for a
half-written spec's. Each gives a :class:`Reader`: where its relative paths start and where the
entry it reads was written. Every problem becomes a diagnostic in the reader's list, in the
order found: a problem of the entry itself (a file that is not there, a package folder, a mend
that does not fit) where the reader says the entry wrote it; a problem of the description at
its element, in the file the user wrote (never this machine's absolute path; a derived copy's
lines mapped back to the user's, an expansion's named ``FILE (expanded)``).

It sits in resolve, the lowest floor that reads a description by its path: compose, below,
takes texts; the files it finds are resolve's :class:`~robospec.resolve.resolved.FileRef`.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from robospec.description.facts import RobotDescription
from robospec.description.sanity import SANITY_CODES
from robospec.diagnostics import Diagnostic, Location, error, warning, without_codes
from robospec.diagnostics.codes import (
    DESCRIPTION_NOT_FOUND,
    IGNORED_INERTIAL,
    NO_RATE_LIMIT,
    PACKAGE_NOT_FOUND,
    TRIANGLE_INEQUALITY,
)
from robospec.load.source_map import KeyPath
from robospec.resolve.paths import in_maniskill
from robospec.resolve.resolved import FileRef

if TYPE_CHECKING:
    from robospec.compose.model import Composed
    from robospec.derive import Derived

ParsedKind = Literal["urdf", "mjcf"]
EXPANDED = " (expanded)"  # how diagnostics name a xacro's expansion: its lines are not the file's


@dataclass(frozen=True)
class DescriptionEntry:
    """A robot description as a spec's ``description:`` (or a part's) or a command line names
    it."""

    path: str  # as written: relative to the reader's folder, or in a ManiSkill folder
    kind: Literal["urdf", "xacro", "mjcf"]
    args: Mapping[str, Any] = field(default_factory=dict)  # a xacro's arguments
    packages: Mapping[str, str] = field(default_factory=dict)  # ROS package -> folder as written
    # mend class -> policy, as declared (robospec.derive); None: the mends it needs to load
    mends: Mapping[str, Any] | None = field(default_factory=dict)
    download: tuple[str, ...] = ()  # ManiSkill's download ids: the file may not be there yet
    # what the spec's other sections change in the derived copy (robospec.derive.SECTIONS):
    # section -> its settings
    sections: Mapping[str, Any] = field(default_factory=dict)
    # an MJCF's loader: "mujoco" compiles it into the URDF ManiSkill loads (robospec.derive.
    # mujoco_urdf); None or "maniskill": ManiSkill's own MJCF loader reads it
    loader: str | None = None
    # with loader "mujoco": the MJCF's sites written as links of their own (description.sites)
    sites: tuple[str, ...] = ()

    @classmethod
    def of(cls, desc: Any, spec: Any = None) -> DescriptionEntry:
        """The entry a spec's ``description`` (robospec.model.spec.Description) gives, with
        what ``spec``'s own sections change in its derived copy (a planar base)."""
        mends = desc.mend.model_dump(exclude_none=True) if desc.mend is not None else {}
        sections = derived_sections(spec) if spec is not None else {}
        return cls(
            desc.path,
            desc.kind,
            desc.args,
            desc.packages,
            mends,
            tuple(desc.download),
            sections,
            getattr(desc, "loader", None),
            tuple(getattr(desc, "sites", ())),
        )

    @property
    def compiled(self) -> bool:
        """Whether MuJoCo compiles the MJCF into the URDF ManiSkill loads."""
        return self.kind == "mjcf" and self.loader == "mujoco"

    @property
    def parsed_kind(self) -> ParsedKind:
        return "mjcf" if self.kind == "mjcf" and not self.compiled else "urdf"


def derived_sections(spec: Any) -> dict[str, Any]:
    """The spec's sections that change its description's derived copy, as settings."""
    base = getattr(spec, "mobile_base", None)
    if base is None:
        return {}
    return {"mobile_base": mobile_base_settings(base)}


def mobile_base_settings(base: Any) -> dict[str, Any]:
    """What a ``mobile_base`` section (robospec.model.mechanisms.MobileBase) changes in the
    derived copy, as the planar base's settings (robospec.derive.planar_base)."""
    wheels = base.wheels if isinstance(base.wheels, list) else [base.wheels]
    return {
        "link": base.link,
        "height": float(base.height),
        "joints": list(base.joints),
        "wheels": list(wheels),
        "wheel_joints": base.wheel_joints,
    }


@dataclass
class Reader:
    """Who reads a description: where its relative paths start, how its diagnostics name a
    file there, and where the entry wrote each of its keys (a key path below the entry)."""

    folder: Path  # relative paths are against this folder
    shown_folder: Path  # ... and named below this one (the folder as the user gave it)
    locate: Callable[[KeyPath], Location]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # the entry is the file itself (a command line), not a key naming it: a file that cannot
    # be read is told as reading it fails, at its first line, not as a key naming no file
    entry_is_file: bool = False

    def err(self, where: KeyPath, code: str, message: str, hint: str | None = None) -> None:
        self.diagnostics.append(error(self.locate(where), code, message, hint))

    def warn(self, where: KeyPath, code: str, message: str, hint: str | None = None) -> None:
        self.diagnostics.append(warning(self.locate(where), code, message, hint))

    def shown(self, ref: FileRef) -> str:
        """How diagnostics name ``ref``: as the user wrote it."""
        return ref.placeholder_text or str(self.shown_folder / ref.relative)


@dataclass(frozen=True)
class Prepared:
    """A description found, expanded and mended, not parsed yet."""

    ref: FileRef  # its generated_text: the expansion or the derived copy, when there is one
    kind: ParsedKind
    shown: str  # how diagnostics name it
    packages: dict[str, str] = field(default_factory=dict)  # ROS package -> absolute folder
    derived: Derived | None = None
    mends: dict[str, Any] = field(default_factory=dict)  # the mends applied to it
    expanded: bool = False  # read as xacro: named so, or a URDF whose content is xacro
    compiled: bool = False  # an MJCF MuJoCo compiled, written as a URDF (loader: mujoco)
    # what the description carries that its text does not say (a compiled MJCF's keyframes,
    # actuators and floating root): RobotDescription's fields
    facts: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Loaded:
    """A description parsed: its facts, its file (with the mesh files a copy must carry) and
    what it was read from."""

    description: RobotDescription
    ref: FileRef
    prepared: Prepared


def load(reader: Reader, entry: DescriptionEntry) -> Loaded | FileRef | None:
    """The description ``entry`` names, parsed; its bare ref when ManiSkill has not downloaded
    it yet; None when it could not be read (the reader has the reasons)."""
    prepared = prepare(reader, entry)
    if prepared is None or isinstance(prepared, FileRef):
        return prepared
    description, ref = parse(reader, prepared)
    return Loaded(description, ref, prepared) if description is not None else None


def find_file(
    reader: Reader, text: str, where: KeyPath, *, may_be_missing: bool = False
) -> FileRef | None:
    """The file ``text`` names; RS050 at ``where`` (and None) when it is not a readable file."""
    found = in_maniskill(text)
    if found is not None:
        kind, relative, absolute = found
        if absolute is None:
            reader.err(
                where,
                DESCRIPTION_NOT_FOUND,
                f"'{text}' names ManiSkill's assets, but ManiSkill is not installed",
                "pip install 'robospec[maniskill]'",
            )
            return None
        ref = FileRef(kind, relative, absolute)
    else:
        try:  # realpath, not Path.resolve: that raises RuntimeError on a loop of links (< 3.13)
            ref = FileRef("file", text, Path(os.path.realpath(reader.folder / text)))
        except (OSError, ValueError) as exc:  # a NUL byte in the name
            reader.err(where, DESCRIPTION_NOT_FOUND, f"cannot use '{text}' as a file: {exc}")
            return None
    problem = None if reader.entry_is_file else _not_a_file(ref, text, may_be_missing)
    if problem is not None:
        reader.err(where, DESCRIPTION_NOT_FOUND, *problem)
        return None
    return ref


def _not_a_file(ref: FileRef, text: str, may_be_missing: bool) -> tuple[str, str | None] | None:
    """Why ``ref`` is not a file to read (message, hint); None when it is one (or may be
    missing, and is)."""
    try:
        found = ref.absolute.is_file()
        exists = found or ref.absolute.exists()
    except (OSError, ValueError) as exc:  # a name too long for the file system, a NUL byte
        return f"cannot use '{text}' as a file: {getattr(exc, 'strerror', None) or exc}", None
    if exists and not found:  # a folder or a FIFO: there, but not a file to read
        what = "a folder" if ref.absolute.is_dir() else "not a regular file"
        return f"cannot use '{text}' as a file: it is {what}", None
    if found or may_be_missing:
        return None
    return f"file not found: '{text}'", f"looked for {ref.absolute}" if ref.kind == "file" else None


def package_folders(reader: Reader, packages: Mapping[str, str]) -> dict[str, str]:
    """The ``packages`` of an entry, each an absolute folder; a folder that is not there is
    RS058 at its value (and left out)."""
    folders: dict[str, str] = {}
    for name, text in packages.items():
        where: KeyPath = ("packages", name)
        found = in_maniskill(text)
        if found is not None and found[2] is None:
            reader.err(
                where,
                DESCRIPTION_NOT_FOUND,
                f"'{text}' names ManiSkill's assets, but ManiSkill is not installed",
                "pip install 'robospec[maniskill]'",
            )
            continue
        if found is not None:
            folder = found[2]
        else:
            try:  # realpath, as find_file: a NUL byte or a loop of links is not a folder
                folder = Path(os.path.realpath(reader.folder / text))
            except (OSError, ValueError) as exc:
                reader.err(
                    where, PACKAGE_NOT_FOUND, f"package '{name}': cannot use '{text}': {exc}"
                )
                continue
        try:
            is_folder = folder is not None and folder.is_dir()
        except OSError:  # a name too long for the file system
            is_folder = False
        if not is_folder:
            reader.err(
                where,
                PACKAGE_NOT_FOUND,
                f"package '{name}': no folder '{text}'",
                f"looked for {folder}" if found is None else None,
            )
            continue
        folders[name] = str(folder)
    return folders


def prepare(reader: Reader, entry: DescriptionEntry) -> Prepared | FileRef | None:
    """The description ``entry`` names found, expanded (xacro) and mended (derive); its bare
    ref when ManiSkill has not downloaded it yet; None when it cannot be read."""
    packages = package_folders(reader, entry.packages)
    ref = find_file(reader, entry.path, (entry.kind,), may_be_missing=bool(entry.download))
    if ref is None:
        return None
    if entry.download and not ref.absolute.is_file():  # ManiSkill has not fetched it yet
        return ref
    shown = reader.shown(ref)
    expand = entry.kind == "xacro" or (entry.kind == "urdf" and _xacro_content(reader, ref, shown))
    if expand:
        from robospec.description.xacro import expand_xacro

        args = {k: _xacro_arg(v) for k, v in entry.args.items()}
        text, diags = expand_xacro(str(ref.absolute), args, packages=packages)
        reader.diagnostics.extend(_relocate(diags, str(ref.absolute), shown))
        if text is None:
            return None
        shown += EXPANDED
        # (a URDF file's SRDF is its robot's still, expanded or not)
        beside = entry.kind != "xacro" and ref.has_srdf_beside
        ref = dataclasses.replace(ref, generated_text=text, has_srdf_beside=beside)
    kind: ParsedKind = "mjcf" if entry.kind == "mjcf" else "urdf"
    prepared = Prepared(ref, kind, shown, packages, expanded=expand)
    if entry.mends is None or entry.mends or entry.sections:
        mended = _mended(reader, prepared, entry.mends, (entry.kind,), entry.sections)
        if mended is None or not entry.compiled:
            return mended
        prepared = mended
    return _compiled(reader, prepared, (entry.kind,), entry.sites) if entry.compiled else prepared


def _compiled(
    reader: Reader, prepared: Prepared, where: KeyPath, sites: tuple[str, ...] = ()
) -> Prepared | None:
    """``prepared`` (an MJCF, mended or not) compiled by MuJoCo and written as the URDF
    ManiSkill's URDF loader reads (robospec.derive.mujoco_urdf): a derived copy, whose
    diagnostics point at the MJCF's bodies and joints."""
    from robospec.derive import Derived, Source
    from robospec.derive.mujoco_urdf import compile_urdf

    ref, shown = prepared.ref, prepared.shown
    try:
        data = ref.read_bytes()
    except OSError as exc:
        reader.err(
            where,
            DESCRIPTION_NOT_FOUND,
            f"cannot read robot description '{shown}': {exc.strerror or exc}",
        )
        return None
    source = Source(str(ref.absolute), shown, "mjcf", data, prepared.packages)
    named = tuple((site, reader.locate(("sites", i))) for i, site in enumerate(sites))
    compiled = compile_urdf(source, reader.locate(where), named)
    reader.diagnostics.extend(compiled.diagnostics)
    if compiled.text is None or any(d.is_error for d in compiled.diagnostics):
        return None
    derived = Derived(
        compiled.text,
        "urdf",
        line_map=compiled.line_map,
        explained=frozenset(),
    )
    ref = dataclasses.replace(
        ref,
        generated_text=compiled.text,
        derived=True,
        has_srdf_beside=False,
        sources=tuple(dict.fromkeys((*ref.sources, *compiled.files))),
    )
    return dataclasses.replace(
        prepared, ref=ref, kind="urdf", derived=derived, compiled=True, facts=compiled.facts
    )


def _xacro_content(reader: Reader, ref: FileRef, shown: str) -> bool:
    """Whether a file named as a URDF is xacro (RS092, a warning the reader gets: it is then
    expanded as one, whatever its name)."""
    from robospec.description.xacro_content import xacro_content

    try:
        data = ref.read_bytes()
    except OSError:  # the parse after says so
        return False
    found = xacro_content(str(ref.absolute), data)
    if found is not None:
        reader.diagnostics.extend(_relocate([found], str(ref.absolute), shown))
    return found is not None


def _mended(
    reader: Reader,
    prepared: Prepared,
    declared: Mapping[str, Any] | None,
    where: KeyPath,
    sections: Mapping[str, Any] | None = None,
) -> Prepared | None:
    """``prepared`` with the ``declared`` mends applied to a copy (robospec.derive), or with
    those it needs when ``declared`` is None: the notes of what changed, in the description;
    a declared mend that does not fit, at its entry (a file that cannot be read, at
    ``where``)."""
    from robospec.derive import Source, derive, suggest_mends

    ref, shown = prepared.ref, prepared.shown
    try:
        data = ref.read_bytes()
    except OSError as exc:
        reader.err(
            where,
            DESCRIPTION_NOT_FOUND,
            f"cannot read robot description '{shown}': {exc.strerror or exc}",
        )
        return None
    source = Source(str(ref.absolute), shown, prepared.kind, data, prepared.packages)
    if declared is None:
        mends, derived = suggest_mends(source)
        if sections:  # what a section changes, after the mends the file needs to load
            derived = derive(source, mends, sections)
        elif not mends:
            return prepared
    else:
        mends, derived = dict(declared), derive(source, declared, sections)
    reader.diagnostics.extend(derived.notes)
    reader.diagnostics.extend(derived.refusals)
    if declared is not None:
        _report_outcomes(reader, derived, mends, prepared)
    ref = dataclasses.replace(ref, generated_text=derived.text, derived=True)
    return dataclasses.replace(prepared, ref=ref, derived=derived, mends=dict(mends))


def _report_outcomes(
    reader: Reader, derived: Derived, mends: Mapping[str, Any], prepared: Prepared
) -> None:
    """A declared mend that changes nothing (a warning), or is for the other kind of
    description (an error), at its entry."""
    from robospec.derive import MENDS, mend_class
    from robospec.diagnostics.codes import MEND_FOR_OTHER_KIND, STALE_MEND
    from robospec.diagnostics.suggest import did_you_mean

    kind, shown = prepared.kind, prepared.shown
    for outcome in derived.outcomes:
        at: KeyPath = ("mend", outcome.name)
        if outcome.status == "stale":
            reader.warn(
                at,
                STALE_MEND,
                f"mend '{outcome.name}: {_policy_text(mends[outcome.name])}' changes nothing "
                f"in '{shown}'",
                "remove it (robospec new writes only the mends a robot needs)",
            )
        elif outcome.status == "not_for_kind":
            mend = mend_class(outcome.name)
            kinds = " and ".join(sorted(mend.KINDS)).upper() if mend is not None else "other"
            fitting = [m.NAME for m in MENDS if kind in m.KINDS]
            reader.err(
                at,
                MEND_FOR_OTHER_KIND,
                f"mend '{outcome.name}' is for {kinds} descriptions, and '{shown}' is "
                f"{kind.upper()}",
                did_you_mean(outcome.name, fitting)
                or f"{kind.upper()} mends: {', '.join(fitting)}",
            )


def _policy_text(policy: Any) -> str:
    if isinstance(policy, list):
        return "[" + ", ".join(f"{p:g}" if isinstance(p, float) else str(p) for p in policy) + "]"
    return str(policy)


def parse(
    reader: Reader, prepared: Prepared, composed: Composed | None = None
) -> tuple[RobotDescription | None, FileRef]:
    """Parse the description ``prepared`` holds (its text, when robospec wrote one): its facts
    and its ref, with the mesh files a copy of it must carry. ``composed``: the text is the
    combined description of a robot and its parts (robospec.compose), and each element's
    problem goes to the file and line it was written on."""
    from robospec.description import load_description

    ref, derived, absolute = prepared.ref, prepared.derived, str(prepared.ref.absolute)
    description, diags = load_description(
        absolute,
        prepared.kind,
        text=ref.generated_text,
        packages=prepared.packages,
        beside_file=ref.has_srdf_beside,
    )
    if prepared.compiled:  # an MJCF has no rate limits to write: no warning says so
        diags = without_codes(diags, _NOT_FOR_COMPILED)
        if description is not None:
            lines = derived.line_map if derived is not None else ()
            description = _with_facts(description, prepared.facts, lines, prepared.shown)
    if derived is not None and composed is None:
        diags = derived.located(diags, absolute)
    diags = _unless_shipped(diags, ref)
    if composed is not None:
        from robospec.compose.model import relocate

        # each element at its file and line in the combined text's sources; the robot's own
        # at the line of its derived text, which the derivation then maps to the user's file
        diags = relocate(diags, absolute, composed)
        if derived is not None:
            diags = derived.located(diags, prepared.shown)
        reader.diagnostics.extend(diags)
    else:
        reader.diagnostics.extend(_relocate(diags, absolute, prepared.shown))
    # an expansion or a derived copy is written elsewhere: every path it names moves with it
    always = ref.generated_text is not None
    ref = dataclasses.replace(ref, mesh_paths=_carried_mesh_paths(description, always=always))
    return description, ref


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


# Warnings about a description's physics that only editing the file can answer (an inertial
# SAPIEN ignores, an impossible inertia): not said of the descriptions ManiSkill ships, which a
# spec cannot change and ManiSkill's own agents load as they are (Fetch's fingers, the Allegro
# hand). Errors are said of every description.
_WARNINGS_NOT_FOR_SHIPPED = frozenset({IGNORED_INERTIAL, TRIANGLE_INEQUALITY}) | SANITY_CODES


def _with_facts(
    description: RobotDescription,
    facts: Mapping[str, Any],
    line_map: tuple[tuple[int, tuple[str, int]], ...],
    shown: str,
) -> RobotDescription:
    """``description`` with what a compiled MJCF's model says besides the URDF (its <key>
    keyframes, each in the description's qpos order; its actuators; a floating root), each
    link and joint at the line of the MJCF body or joint it was written from (``line_map``;
    line 1 for one written in a file the MJCF includes)."""
    lines = dict(line_map)

    def line(urdf_line: int) -> int:
        file, there = lines.get(urdf_line, (shown, 1))
        return there if file == shown else 1

    links = tuple(dataclasses.replace(link, line=line(link.line)) for link in description.links)
    joints = tuple(dataclasses.replace(j, line=line(j.line)) for j in description.joints)
    order = {name: i for i, name in enumerate(description.active_joint_names)}
    keyframes = tuple(
        dataclasses.replace(
            key, qpos=tuple(sorted(key.qpos, key=lambda p: order.get(p[0], len(order))))
        )
        for key in facts.get("keyframes", ())
    )
    return dataclasses.replace(
        description,
        **{**facts, "keyframes": keyframes},
        links=links,
        joints=joints,
        _links_by_name={},
        _joints_by_name={},
    )


# Warnings about a compiled MJCF's URDF that say what the MJCF cannot say (rate limits)
_NOT_FOR_COMPILED = frozenset({NO_RATE_LIMIT})


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
