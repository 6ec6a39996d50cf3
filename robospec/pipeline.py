"""The pipeline, file by file: read → model → resolve → check. No stage raises on bad input."""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from robospec.diagnostics import (
    Diagnostic,
    Location,
    error,
    has_errors,
    sort_key,
    without_codes,
)
from robospec.diagnostics.codes import (
    DESCRIPTION_NOT_FOUND,
    DUPLICATE_UID,
    INTERNAL_ERROR,
    PART_CYCLE,
    UNKNOWN_SILENCED_CODE,
)
from robospec.load.discovery import discover
from robospec.load.reader import SPEC_SUFFIXES, parse_spec_bytes, read_spec
from robospec.load.source_map import KeyPath, LoadedSpec
from robospec.maniskill.builtin_uids import Overrides, override_allowed
from robospec.maniskill.installed import registered_uids
from robospec.model.frozen import Spec
from robospec.model.validate import SpecModelResult, build_spec

if TYPE_CHECKING:
    # resolve and checks (with the description and lxml they load) are imported where a spec
    # reaches them: a spec whose first error is in its text or its model needs neither
    from robospec.checks import CheckContext
    from robospec.compose.model import Composed
    from robospec.description.facts import RobotDescription
    from robospec.resolve.part_types import Locator, PartInput
    from robospec.resolve.resolved import ResolvedRobot


@dataclass
class CompiledSpec:
    path: Path
    display: str
    loaded: LoadedSpec | None = None
    robot: ResolvedRobot | None = None
    description: RobotDescription | None = None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # the resolved robot with its spec and locators, as the checks saw it (physics checks too)
    context: CheckContext | None = None
    # with parts: the combined description (where its lines came from), and what came along
    # from the parts' specs: key path here -> where the part's spec wrote it
    composed: Composed | None = None
    part_origins: dict[KeyPath, tuple[Locator, KeyPath]] = field(default_factory=dict)

    def part_location(self, path: KeyPath) -> Location | None:
        """Where a part's spec wrote what ``path`` names here (its key), if it came from one."""
        found = self.part_origins.get(path)
        return found[0](found[1], True) if found is not None else None

    @property
    def ok(self) -> bool:
        return self.robot is not None and not has_errors(self.diagnostics)


def compile_spec(
    path: Path,
    display: str | None = None,
    *,
    overrides: Overrides = False,
    text: bytes | None = None,
    silence: frozenset[str] = frozenset(),
    mounting: tuple[Path, ...] = (),
) -> CompiledSpec:
    """``overrides``: uids this compilation may take over from ManiSkill (True: any), as
    ``register(..., override=...)`` allows, on top of a spec's own ``override: true``.
    ``text``: the spec's contents as an editor holds them, unsaved (the file's are read when
    None); relative paths in it are still relative to ``path``. ``silence``: warning codes
    not to report (the command line's ``--silence``), with those the spec lists.
    ``mounting``: the specs being compiled that mount this one as a part (outermost first), to
    find a ring of parts."""
    result = CompiledSpec(path, display or str(path))
    try:
        _compile_into(result, overrides, text, mounting)
    except Exception as exc:  # a bug of ours must still be a located diagnostic
        result.robot = None
        result.diagnostics.append(
            error(
                Location(result.display),
                INTERNAL_ERROR,
                f"internal error: {type(exc).__name__}: {exc}",
                "please report this with the spec that caused it",
            )
        )
    _silence(result, silence)
    # a controller's mistake is met again in every controller that extends it, at the one place
    # it was written: the same diagnostic, said once
    result.diagnostics = sorted(dict.fromkeys(result.diagnostics), key=sort_key)
    return result


def silenced_codes(result: CompiledSpec, silence: frozenset[str]) -> frozenset[str]:
    """The warning codes not to report for ``result``: the command line's ``silence`` and the
    codes robospec has that the spec's own ``silence`` list names."""
    from robospec.diagnostics.codes import CODES

    listed = result.loaded.data.get("silence") if result.loaded is not None else None
    named = listed if isinstance(listed, list) else []
    return silence | {code for code in named if isinstance(code, str) and code in CODES}


def _silence(result: CompiledSpec, silence: frozenset[str]) -> None:
    """Drop the warnings whose codes the spec's ``silence`` list or the command line's
    ``--silence`` name; errors stay, whatever the list says. A listed code robospec does not
    have is an error (RS107)."""
    listed = result.loaded.data.get("silence") if result.loaded is not None else None
    if not silence and not isinstance(listed, list):
        return  # nothing to silence, as in most specs: the catalogue of codes is not read
    from robospec.diagnostics.codes import CODES

    codes = set(silenced_codes(result, silence))
    problems: list[Diagnostic] = []
    if isinstance(listed, list) and result.loaded is not None:
        for index, code in enumerate(listed):
            if not isinstance(code, str):
                continue  # the schema reports it
            if code not in CODES and code.startswith("RS"):
                problems.append(
                    error(
                        result.loaded.source.value(("silence", index)),
                        UNKNOWN_SILENCED_CODE,
                        f"{code} is not a robospec diagnostic code",
                        "docs/diagnostics.md lists them",
                    )
                )
    result.diagnostics = without_codes(result.diagnostics, codes) + problems
    if problems:
        result.robot = None


def _compile_into(
    result: CompiledSpec, overrides: Overrides, text: bytes | None, mounting: tuple[Path, ...]
) -> None:
    fmt = SPEC_SUFFIXES.get(result.path.suffix.lower())
    if text is not None and fmt is not None:
        loaded, diagnostics = parse_spec_bytes(text, result.display, fmt)
    else:
        loaded, diagnostics = read_spec(result.path, result.display)
    result.diagnostics.extend(diagnostics)
    if loaded is None:
        return
    result.loaded = loaded
    model = build_spec(loaded)
    result.diagnostics.extend(model.diagnostics)
    if model.spec is None or model.diagnostics:
        return
    spec = model.spec
    if spec.uid in registered_uids() and not override_allowed(spec.uid, spec.override, overrides):
        result.diagnostics.append(
            error(
                loaded.source.value(("uid",)),
                DUPLICATE_UID,
                f"uid '{spec.uid}' is already registered by ManiSkill; its register_agent would "
                "skip this robot with only a warning",
                f"use a new uid such as 'rs_{spec.uid}', or set `override: true` to replace "
                "ManiSkill's agent on purpose",
            )
        )
    from robospec.resolve import resolve
    from robospec.resolve.carried import filled_joints, passive_joints
    from robospec.resolve.description_files import shown_path

    parts = _compile_parts(result, spec, model, loaded, mounting)
    resolution = resolve(loaded, model, result.path, parts)
    result.diagnostics.extend(resolution.diagnostics)
    result.composed = resolution.composed
    result.part_origins = resolution.origins
    result.description = resolution.loaded_description
    robot = resolution.robot
    if robot is None or resolution.loaded_description is None:
        return
    # the checks, only for a robot to check: a first error in resolve needs none of them
    from robospec.checks import BINDING_CHECKS, ROBOT_CHECKS, CheckContext, run_checks

    context = CheckContext(
        spec=spec,
        robot=robot,
        description=resolution.loaded_description,
        description_file=shown_path(resolution, robot.description),
        bindings=resolution.bindings,
        locate_value=resolution.at_value,
        locate_key=resolution.at_key,
        description_origins=resolution.composed.origins if resolution.composed else None,
        filled_by_parts=filled_joints(resolution),
        part_passive_joints=passive_joints(resolution),
    )
    result.diagnostics.extend(run_checks(BINDING_CHECKS, context))
    if not has_errors(result.diagnostics):
        result.diagnostics.extend(run_checks(ROBOT_CHECKS, context))
        result.context = context
    if not has_errors(result.diagnostics):
        result.robot = robot


def _compile_parts(
    result: CompiledSpec,
    spec: Spec,
    model: SpecModelResult,
    loaded: LoadedSpec,
    mounting: tuple[Path, ...],
) -> dict[str, PartInput]:
    """Each part given as a spec, compiled on its own (its problems reported where they are
    written); a spec that mounts, directly or through its parts, the spec mounting it is
    RS733 at the entry that closes the ring."""
    if not spec.parts:
        return {}  # nothing of the parts' machinery is imported for a spec without parts
    from robospec.resolve.part_types import PartInput

    parts: dict[str, PartInput] = {}
    here = _identity(result.path)
    for name, part in spec.parts.items():
        if part.spec is None:
            continue
        where = loaded.source.value(model.origin(("parts", name, "spec")))
        path = result.path.parent / part.spec
        display = os.path.normpath(str(Path(result.display).parent / part.spec))
        chain = (*mounting, here)
        if _identity(path) in chain:
            ring = [p.name for p in chain[chain.index(_identity(path)) :]] + [path.name]
            result.diagnostics.append(
                error(
                    where,
                    PART_CYCLE,
                    f"part '{name}' mounts a spec that mounts this one: {' -> '.join(ring)}",
                    "a spec cannot be a part of itself",
                )
            )
            parts[name] = PartInput(name, None, None, display, display, cycle=True)
            continue
        if not path.is_file():
            result.diagnostics.append(
                error(where, DESCRIPTION_NOT_FOUND, f"file not found: '{part.spec}'")
            )
            parts[name] = PartInput(name, None, None, display, display, cycle=True)
            continue
        # its own problems are its file's: validating it reports them; here, RS737 names them
        parts[name] = part_input(name, compile_spec(path, display, mounting=chain))
    return parts


def part_input(name: str, compiled: CompiledSpec) -> PartInput:
    """What mounting and merging read of a part's own compilation."""
    from robospec.resolve.part_types import PartInput

    context = compiled.context
    if compiled.robot is None or context is None or compiled.description is None:
        errors = tuple(
            d.format_text().split("\n", 1)[0] for d in compiled.diagnostics if d.is_error
        )
        return PartInput(
            name, None, None, compiled.display, compiled.display, failed=True, errors=errors
        )
    spec = context.spec
    carried_not = [
        what
        for what, given in (
            ("hooks", bool(spec.hooks.after_init or spec.hooks.after_loading_articulation)),
            ("hooked methods", bool(spec.hooks.methods)),
            ("extended class (extends)", spec.extends is not None),
            (
                "is_static, is_standing and is_fallen",
                bool(spec.is_static or spec.is_standing or spec.is_fallen),
            ),
        )
        if given
    ]
    return PartInput(
        name=name,
        robot=compiled.robot,
        description=compiled.description,
        shown=context.description_file,
        spec_shown=compiled.display,
        spec_path=str(_identity(compiled.path)),
        locate=lambda path, key: context.key(path) if key else context.value(path),
        fix_root_link=compiled.robot.fix_root_link,
        passive_joints=context.passive_joints_bound,
        carried_not=tuple(carried_not),
    )


def _identity(path: Path) -> Path:
    try:
        return Path(os.path.realpath(path))
    except (OSError, ValueError):
        return path


def compile_all(
    paths: Sequence[Path], *, overrides: Overrides = False, silence: frozenset[str] = frozenset()
) -> tuple[list[CompiledSpec], list[Diagnostic]]:
    """Compile every spec found, then check uids across them."""
    files, diagnostics = discover(paths)
    compiled = [compile_spec(p, overrides=overrides, silence=silence) for p in files]
    diagnostics.extend(_duplicate_uids(compiled))
    return compiled, diagnostics


def _duplicate_uids(compiled: list[CompiledSpec]) -> Iterable[Diagnostic]:
    first: dict[str, CompiledSpec] = {}
    for item in compiled:
        if item.loaded is None or not isinstance(item.loaded.data.get("uid"), str):
            continue
        uid = item.loaded.data["uid"]
        if uid in first:
            other = first[uid]
            assert other.loaded is not None
            where = other.loaded.source.value(("uid",))
            item.robot = None
            yield error(
                item.loaded.source.value(("uid",)),
                DUPLICATE_UID,
                f"uid '{uid}' is also used by {where.file}:{where.line}",
            )
        else:
            first[uid] = item
