"""Parts: the robots a spec mounts (``parts:``), composed into its description.

Each part's spec is compiled on its own first (by :mod:`robospec.pipeline`: it is a robot of
its own, checked where it is written) and handed here as a :class:`PartInput`; a part given as
a bare description is loaded here, mended as the spec's own would be. :func:`compose_parts`
writes the combined description (:mod:`robospec.compose`); the robot's spec is then resolved
against it, so it may name any link or joint of its parts. What the parts' specs declare comes
along as each part's robot renamed into the robot's names (:mod:`robospec.resolve.part_renaming`:
a clashing name gets the part's prefix, as clashing link and joint names do), concatenated with
the robot's own (:mod:`robospec.resolve.carried`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from robospec.diagnostics import error, note, warning
from robospec.diagnostics.codes import PART_HAS_ERRORS, PARTS_WITHOUT_DESCRIPTION
from robospec.load.source_map import KeyPath
from robospec.resolve.context import ResolveContext
from robospec.resolve.part_types import PartInput
from robospec.resolve.resolved import FileRef

if TYPE_CHECKING:
    from robospec.compose import PartSource, Problem

# the codes of this module (robospec/diagnostics/codes.py)


# -- composing -------------------------------------------------------------------------------


def compose_parts(context: ResolveContext, ref: FileRef, kind: str, shown: str) -> FileRef | None:
    """The robot's description (``ref``) with every part mounted, as the ref of the combined
    text (and ``context.composed``); None (and the reasons, located) when a part cannot be
    mounted."""
    from robospec.compose import BaseSource, compose

    sources = []
    ready = True
    for name, part in context.spec.parts.items():
        source = _part_source(context, name, part, kind)
        if source is None:
            ready = False
        else:
            sources.append(source)
    data = _text(ref)
    if not ready or data is None:
        return None
    composed = compose(BaseSource(kind, data, str(ref.absolute), shown), sources)  # type: ignore[arg-type]
    for problem in composed.problems:
        _report(context, problem)
    if composed.text is None:
        return None
    # written beside the generated module (robospec.output): it names its meshes from there
    combined = dataclasses.replace(
        ref,
        generated_text=composed.text,
        derived=True,
        has_srdf_beside=False,
        parts=tuple(f"part '{m.name}'" for m in composed.parts),
        sources=tuple(dict.fromkeys(_sources(context))),
    )
    context.composed = composed
    return combined


def _sources(context: ResolveContext) -> Iterator[str]:
    """The files the combined description is written from, besides the robot's own: what
    ``register`` must see unchanged to trust its cache."""
    for given in context.parts.values():
        if given.spec_path is not None:
            yield given.spec_path
        ref = given.robot.description if given.robot is not None else given.ref
        if ref is not None:
            yield str(ref.absolute)
            yield from ref.sources


def _report(context: ResolveContext, problem: Problem) -> None:
    where = problem.path
    located = context.at_key(where) if len(where) == 2 else context.at_value(where)
    make = {"note": note, "warning": warning}.get(problem.severity, error)
    context.diagnostics.append(make(located, problem.code, problem.message, problem.hint))


def _text(ref: FileRef) -> bytes | None:
    try:
        return ref.read_bytes()
    except OSError:
        return None  # the description's own load says why


def _part_source(
    context: ResolveContext, name: str, part: Any, base_kind: str
) -> PartSource | None:
    """Part ``name`` as composing takes it: its description's text and where it is mounted;
    None (and why, located) when it cannot be mounted."""
    from robospec.compose import PartSource
    from robospec.resolve.poses import position_and_quaternion

    if part.spec is not None:
        given = _spec_part(context, name, base_kind)
        key = "spec"
    else:
        given = _description_part(context, name, part, base_kind)
        key = "description"
    if given is None or given.description is None:
        return None
    ref = given.robot.description if given.robot is not None else given.ref
    data = _text(ref) if ref is not None else None
    if ref is None or data is None:
        return None
    description = given.description
    p, q = position_and_quaternion(part.pose)
    rpy = tuple(part.pose.rpy) if part.pose.q is None and part.pose.rpy is not None else None
    entry = context.at_key(("parts", name))
    return PartSource(
        name=name,
        kind=given.robot.description_kind if given.robot is not None else description.kind,
        text=data,
        path=str(ref.absolute),
        shown=given.shown,
        at=part.at,
        position=p,
        quaternion=q,
        rpy=rpy,
        joint=part.joint_name(name),
        prefix=part.name_prefix(name),
        files={m.uri: m.path for m in description.mesh_files if m.path is not None},
        entry=(entry.file, entry.line),
        entry_path=str(context.spec_file.resolve()),
        key=key,  # type: ignore[arg-type]
        joint_given=part.joint is not None,
        fold_frames=part.fold_frames,
    )


def _spec_part(context: ResolveContext, name: str, base_kind: str) -> PartInput | None:
    """A part given as a spec, as its own compilation left it: None (and why) when it has
    errors, is of the other kind or moves freely."""
    from robospec.compose import mixed_formats
    from robospec.diagnostics.codes import PART_NOT_A_FIXED_TREE

    where: KeyPath = ("parts", name, "spec")
    given = context.parts.get(name)
    if given is None or given.cycle:
        return None  # the pipeline reported the ring of specs
    if given.failed or given.robot is None or given.description is None:
        first = given.errors[0] if given.errors else "it did not compile"
        more = f" (and {len(given.errors) - 1} more)" if len(given.errors) > 1 else ""
        context.err(
            where,
            PART_HAS_ERRORS,
            f"part '{name}' cannot be mounted: its spec has errors: {first}{more}",
            f"robospec validate {given.spec_shown}",
        )
        return None
    kind = given.robot.description_kind
    if kind != base_kind:
        _report(context, mixed_formats(base_kind, name, kind, "spec"))  # type: ignore[arg-type]
        return None
    if not given.fix_root_link or given.description.floating_root:
        context.err(
            where,
            PART_NOT_A_FIXED_TREE,
            f"part '{name}' moves freely (its spec sets loader.fix_root_link: false, or "
            "its root has a free joint): only a robot fixed at its root can be mounted",
            "mount a description of the part without its free root",
        )
        return None
    return given


def _description_part(
    context: ResolveContext, name: str, part: Any, base_kind: str
) -> PartInput | None:
    """A part given as a bare description, loaded (and kept in ``context.parts``): None (and
    why) when it is of the other kind, cannot be read or has a free root."""
    from robospec.compose import mixed_formats
    from robospec.diagnostics.codes import PART_NOT_A_FIXED_TREE
    from robospec.resolve.description_files import load_part_description

    where: KeyPath = ("parts", name, "description")
    kind = part.description.loaded_kind  # an MJCF MuJoCo compiles is a URDF
    if kind != base_kind:  # said before the part is read: its problems would not matter
        _report(context, mixed_formats(base_kind, name, kind, "description"))  # type: ignore[arg-type]
        return None
    loaded = load_part_description(context, part.description, where)
    if loaded is None:
        return None
    ref, description, shown = loaded
    if description.floating_root:
        context.err(
            where,
            PART_NOT_A_FIXED_TREE,
            f"part '{name}' has a free root joint: only a robot fixed at its root can be mounted",
        )
        return None
    given = PartInput(name, None, description, shown, ref=ref)
    context.parts[name] = given
    return given


def warn_unsupported(context: ResolveContext) -> None:
    """A robot whose description comes from an extended class cannot mount parts."""
    if context.spec.parts and context.spec.description is None:
        context.diagnostics.append(
            error(
                context.at_key(("parts",)),
                PARTS_WITHOUT_DESCRIPTION,
                "parts are mounted on the spec's own description, and this spec takes its "
                "robot from the extended class",
                "give `description:` (the class's URDF or MJCF)",
            )
        )


__all__ = ["PartInput", "compose_parts", "warn_unsupported"]
