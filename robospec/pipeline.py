"""The pipeline, file by file: read → model → resolve → check. No stage raises on bad input."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from robospec.checks import BINDING_CHECKS, ROBOT_CHECKS, CheckContext, run_checks
from robospec.description.facts import RobotDescription
from robospec.diagnostics import Diagnostic, Location, Severity, error, has_errors, sort_key
from robospec.load.discovery import discover
from robospec.load.reader import SPEC_SUFFIXES, parse_spec_bytes, read_spec
from robospec.load.source_map import LoadedSpec
from robospec.maniskill.builtin_uids import Overrides, override_allowed
from robospec.maniskill.installed import registered_uids
from robospec.model.validate import build_spec
from robospec.resolve import resolve
from robospec.resolve.description_files import shown_path
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
) -> CompiledSpec:
    """``overrides``: uids this compilation may take over from ManiSkill (True: any), as
    ``register(..., override=...)`` allows, on top of a spec's own ``override: true``.
    ``text``: the spec's contents as an editor holds them, unsaved (the file's are read when
    None); relative paths in it are still relative to ``path``. ``silence``: warning codes
    not to report (the command line's ``--silence``), with those the spec lists."""
    result = CompiledSpec(path, display or str(path))
    try:
        _compile_into(result, overrides, text)
    except Exception as exc:  # a bug of ours must still be a located diagnostic
        result.robot = None
        result.diagnostics.append(
            error(
                Location(result.display),
                "RS900",
                f"internal error: {type(exc).__name__}: {exc}",
                "please report this with the spec that caused it",
            )
        )
    _silence(result, silence)
    # a controller's mistake is met again in every controller that extends it, at the one place
    # it was written: the same diagnostic, said once
    result.diagnostics = sorted(dict.fromkeys(result.diagnostics), key=sort_key)
    return result


def _silence(result: CompiledSpec, silence: frozenset[str]) -> None:
    """Drop the warnings whose codes the spec's ``silence`` list or the command line's
    ``--silence`` name; errors stay, whatever the list says. A listed code robospec does not
    have is an error (RS107)."""
    from robospec.diagnostics.codes import CODES

    codes = set(silence)
    listed = result.loaded.data.get("silence") if result.loaded is not None else None
    problems: list[Diagnostic] = []
    if isinstance(listed, list) and result.loaded is not None:
        for index, code in enumerate(listed):
            if not isinstance(code, str):
                continue  # the schema reports it
            if code in CODES:
                codes.add(code)
            elif code.startswith("RS"):
                problems.append(
                    error(
                        result.loaded.source.value(("silence", index)),
                        "RS107",
                        f"{code} is not a robospec diagnostic code",
                        "docs/diagnostics.md lists them",
                    )
                )
    result.diagnostics = [
        d for d in result.diagnostics if d.severity is Severity.ERROR or d.code not in codes
    ] + problems
    if problems:
        result.robot = None


def _compile_into(result: CompiledSpec, overrides: Overrides, text: bytes | None) -> None:
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
                "RS306",
                f"uid '{spec.uid}' is already registered by ManiSkill; its register_agent would "
                "skip this robot with only a warning",
                f"use a new uid such as 'rs_{spec.uid}', or set `override: true` to replace "
                "ManiSkill's agent on purpose",
            )
        )
    resolution = resolve(loaded, model, result.path)
    result.diagnostics.extend(resolution.diagnostics)
    result.description = resolution.loaded_description
    robot = resolution.robot
    if robot is None or resolution.loaded_description is None:
        return
    context = CheckContext(
        spec=spec,
        robot=robot,
        description=resolution.loaded_description,
        description_file=shown_path(resolution, robot.description),
        bindings=resolution.bindings,
        locate_value=resolution.at_value,
        locate_key=resolution.at_key,
    )
    result.diagnostics.extend(run_checks(BINDING_CHECKS, context))
    if not has_errors(result.diagnostics):
        result.diagnostics.extend(run_checks(ROBOT_CHECKS, context))
        result.context = context
    if not has_errors(result.diagnostics):
        result.robot = robot


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
                "RS306",
                f"uid '{uid}' is also used by {where.file}:{where.line}",
            )
        else:
            first[uid] = item
