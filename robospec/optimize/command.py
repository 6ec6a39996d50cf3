"""``robospec optimize SPEC -o OUT.yaml``: compile the spec, condense its URDF, simplify its
collision shapes, declare the link pairs that never touch, and write OUT.yaml with the optimized
description beside it; one :class:`~robospec.optimize.report.OptimizeResult` back.

The stages, each in its module: the options and their problems
(:mod:`robospec.optimize.options`), the links kept and the URDF condensed
(:mod:`robospec.optimize.links`, :mod:`robospec.optimize.condense`), the collision shapes
(:mod:`robospec.optimize.shapes`), the never_collide entries
(:mod:`robospec.optimize.never_collide`), the spec rewritten
(:mod:`robospec.optimize.spec_rewrite`), the fast profile (:mod:`robospec.optimize.fast`), the
files written and what may be overwritten (:mod:`robospec.optimize.outputs`: ``OUT.yaml``,
``<stem>.urdf``, ``<stem>.srdf`` and ``<stem>_collision/``, staged and renamed into place at the
end, so a failure leaves the old output or none, never a part) and the report
(:mod:`robospec.optimize.report`).

``--profile fast`` changes how the robot collides, for speed (see :mod:`robospec.optimize.fast`):
collision meshes become boxes, capsules or spheres where one lies within ``--max-error`` of
the mesh, the robot's own shapes get a contact offset small enough that pairs that never touch
make no contacts, and the spec recommends solver iterations for the robot's category; all of
it is written into the spec's ``simulation`` section, and the report gives each change with
what it measured.
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.diagnostics import Diagnostic, Location, error, has_errors, warning
from robospec.diagnostics.codes import (
    CANNOT_OPTIMIZE,
    CANNOT_WRITE,
    INTERNAL_ERROR,
    NO_PRIMITIVE_FITS,
    OPTIMIZE_WITH_PARTS,
    PYTHON_NAMED_LINK_MERGED,
)
from robospec.optimize.options import COMMAND_LINE, OptimizeOptions, ShapeMethod, option_problems
from robospec.optimize.outputs import (
    FINAL_URDF,
    MARK,
    Targets,
    drop_if_empty,
    make_collision_folder,
    move_into_place,
    not_ours,
    write_srdf,
    write_urdf,
)
from robospec.optimize.report import OptimizeReport, OptimizeResult, shape_json

if TYPE_CHECKING:
    from lxml import etree

    from robospec.pipeline import CompiledSpec
    from robospec.resolve.resolved import ResolvedRobot


def run_optimize(spec: Path, out: Path, options: OptimizeOptions | None = None) -> OptimizeResult:
    """Optimize ``spec`` into ``out``: the report, or None and the diagnostics that stopped it."""
    try:
        return _run_optimize(spec, out, options or OptimizeOptions())
    except Exception as exc:  # a bug of ours must still be a located diagnostic, and no output
        return OptimizeResult(
            None,
            [
                error(
                    Location(str(spec)),
                    INTERNAL_ERROR,
                    f"internal error: {type(exc).__name__}: {exc}",
                    "please report this with the spec that caused it",
                )
            ],
        )


def _run_optimize(spec: Path, out: Path, options: OptimizeOptions) -> OptimizeResult:
    from robospec.pipeline import compile_spec

    problems = option_problems(options)
    if problems:
        return OptimizeResult(None, problems)
    compiled = compile_spec(spec)
    refused = _refused(spec, compiled)
    if refused:
        return OptimizeResult(None, refused)
    targets = Targets.beside(out)
    owned = not_ours(targets)
    if owned:
        return OptimizeResult(None, owned)
    assert compiled.robot is not None  # refused above otherwise
    report = OptimizeReport(
        str(spec), str(out), targets.urdf.name, options.uid or f"{compiled.robot.uid}_optimized"
    )
    report.diagnostics.extend(d for d in compiled.diagnostics if not d.is_error)
    report.diagnostics.extend(_named_by_python(spec, compiled.robot))
    try:  # -o into a folder that does not exist yet makes it, as build -o does
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return OptimizeResult(
            None, [error(COMMAND_LINE, CANNOT_WRITE, f"cannot make {out.parent}: {exc.strerror}")]
        )
    # absolute: the meshes written there are named from it, and -o may be a relative path
    with tempfile.TemporaryDirectory(
        prefix=".robospec-optimize-", dir=out.parent.resolve()
    ) as staging:
        written = _optimize_into(Path(staging), compiled, targets, options, report)
        if has_errors(written):
            return OptimizeResult(None, written)
        # the output spec must compile: a mistake of ours must not reach the user's folder
        check = compile_spec(Path(staging) / targets.spec.name)
        if not check.ok:
            return OptimizeResult(None, list(check.diagnostics))
        move_into_place(Path(staging), targets)
    return OptimizeResult(report, report.diagnostics)


def _refused(spec: Path, compiled: CompiledSpec) -> list[Diagnostic]:
    """Why this spec cannot be optimized: it does not compile, it is composed of parts, or its
    description is not URDF; nothing when it can."""
    if not compiled.ok or compiled.robot is None or compiled.context is None:
        return list(compiled.diagnostics) or [
            error(Location(str(spec)), CANNOT_OPTIMIZE, "the spec does not compile")
        ]
    robot = compiled.robot
    if robot.parts:
        # the condensed description would hold the parts' links, which the optimized spec's
        # parts: would then mount a second time; split back, fold_frames' frames are gone
        return [
            error(
                compiled.loaded.source.key(("parts",)) if compiled.loaded else Location(str(spec)),
                OPTIMIZE_WITH_PARTS,
                "robospec optimize condenses one description, and this robot is composed of "
                f"{len(robot.parts) + 1} (parts: " + ", ".join(p.name for p in robot.parts) + ")",
                "optimize the robot's description and each part's spec on their own, and mount "
                "the optimized parts",
            )
        ]
    if robot.description_kind != "urdf" or compiled.description is None:
        return [
            error(
                Location(str(spec)),
                CANNOT_OPTIMIZE,
                "robospec optimize condenses URDF and xacro descriptions; this robot's is "
                f"{robot.description_kind.upper()}",
                'MuJoCo\'s compiler fuses static bodies itself (<compiler fusestatic="true"/>)',
            )
        ]
    return []


def _named_by_python(spec: Path, robot: ResolvedRobot) -> list[Diagnostic]:
    """RS608 when Python code (extends, hooks) may name links optimize cannot see."""
    hooks = robot.hooks
    if robot.base is None and not hooks.after_init and not hooks.after_loading_articulation:
        return []
    return [
        warning(
            Location(str(spec)),
            PYTHON_NAMED_LINK_MERGED,
            "links named by Python code (extends, hooks) are not known to robospec optimize",
            "pin each with --keep LINK",
        )
    ]


def _optimize_into(
    staging: Path,
    compiled: CompiledSpec,
    targets: Targets,
    options: OptimizeOptions,
    report: OptimizeReport,
) -> list[Diagnostic]:
    """Write every output under ``staging`` (same names as ``targets``); errors, if any."""
    condensed, problems = _condensed(compiled, options, report)
    if problems:
        return problems
    folder = staging / targets.collision.name
    shaped, problems = _shaped(condensed, folder, compiled, options, report)
    if problems:
        return problems
    assert shaped is not None  # (None only with the problems)
    # two renders: one that works from the staging folder, checked there, and the one that
    # works from OUT's folder, which replaces the first when everything is moved into place
    robot = compiled.robot
    assert robot is not None  # compiled
    urdf_file = staging / targets.urdf.name
    source = robot.description.relative
    write_urdf(shaped, urdf_file, staging, staging, source)
    final_dir = targets.urdf.parent
    write_urdf(shaped, staging / FINAL_URDF, final_dir, staging, source, final_dir=final_dir)
    from robospec.optimize.links import srdf_of

    srdf = srdf_of(robot.description)
    if srdf is not None:
        write_srdf(srdf, staging / targets.srdf.name)
    _write_spec(staging / targets.spec.name, urdf_file, shaped, compiled, targets, options, report)
    return []


def _condensed(
    compiled: CompiledSpec, options: OptimizeOptions, report: OptimizeReport
) -> tuple[Any, list[Diagnostic]]:
    """The spec's URDF with fixed joints merged (every link the spec names kept), what was
    merged and kept in the report; or the errors that stop it."""
    assert compiled.robot is not None and compiled.description is not None  # compiled
    from robospec.optimize import links
    from robospec.optimize.condense import condense

    urdf = links.absolute_meshes(compiled.robot.description.read_text(), compiled.description)
    keep = links.links_to_keep(compiled, options.keep)
    unknown = links.unknown_keep(compiled.description, options.keep)
    if unknown:
        return None, unknown
    condensed = condense(urdf, keep)
    merged_away = links.named_links_merged_away(compiled, condensed.robot)
    if merged_away:
        return None, merged_away
    report.profile = options.profile
    report.links_before = len(urdf.findall("link"))
    report.links_after = len(condensed.robot.findall("link"))
    report.merged = [(m.link, m.into, m.joint) for m in condensed.merged]
    report.kept = links.kept_on_fixed_joints(urdf, keep)
    report.unmerged = links.unmerged(condensed.robot, keep)
    return condensed.robot, []


def _shaped(
    robot: etree._Element,
    folder: Path,
    compiled: CompiledSpec,
    options: OptimizeOptions,
    report: OptimizeReport,
) -> tuple[etree._Element | None, list[Diagnostic]]:
    """``robot`` with its collision meshes made by the shapes method (new meshes written under
    ``folder``), the changes in the report; or the errors that stop it."""
    assert compiled.robot is not None  # compiled
    method = options.shape_method
    if method == ShapeMethod.keep:
        return robot, []
    from robospec.optimize.shapes import MissingDependency, optimize_collisions

    make_collision_folder(folder)
    try:
        robot, changes = optimize_collisions(
            robot,
            folder,
            method=method.value,
            max_vertices=options.max_vertices,
            # what SAPIEN builds from a mesh depends on it: one hull, or one per part
            multiple_collisions=compiled.robot.load_multiple_collisions,
            max_error=options.bound,
        )
    except MissingDependency as exc:
        return None, [error(COMMAND_LINE, CANNOT_OPTIMIZE, str(exc), exc.hint)]
    report.shapes = [shape_json(c) for c in changes]
    if method == ShapeMethod.primitives:
        report.diagnostics.extend(_unfitted(compiled, changes, options.bound))
    drop_if_empty(folder)
    return robot, []


def _unfitted(compiled: CompiledSpec, changes: Sequence[Any], bound: float) -> list[Diagnostic]:
    """RS674 when some collision meshes fit no primitive within the bound: which, and the
    nearest miss."""
    missed = [c for c in changes if c.reason == "no primitive within the bound"]
    if not missed:
        return []
    nearest = min(missed, key=lambda c: c.fit_error)
    fitted = sum(c.primitives for c in changes)
    found = warning(
        Location(str(compiled.path)),
        NO_PRIMITIVE_FITS,
        f"{len(missed)} collision mesh(es) fit no primitive within {bound * 1000:g} mm and keep "
        f"the shapes SAPIEN makes of them ({fitted} became primitives); the nearest miss: "
        f"{nearest.link}'s {nearest.fit}, {nearest.fit_error * 1000:.1f} mm off",
        "a larger --max-error turns more into primitives, and changes the robot more",
    )
    return [found]


def _write_spec(
    staged_spec: Path,
    urdf_file: Path,
    urdf: etree._Element,
    compiled: CompiledSpec,
    targets: Targets,
    options: OptimizeOptions,
    report: OptimizeReport,
) -> None:
    """The optimized spec, with the never_collide entries the bits allow and, for the fast
    profile, its simulation section."""
    matrix = None
    if options.samples:
        from robospec.optimize.never_collide import sampled_entries

        report.samples = options.samples
        report.never_collide, matrix = sampled_entries(
            urdf_file, urdf, compiled, options.samples, options.seed
        )
    while True:
        staged_spec.write_text(_optimized_spec(compiled, targets, report), encoding="utf-8")
        if not report.never_collide or not _packing_problems(staged_spec):
            break
        # the packer could not honour every entry beside the spec's own without disabling
        # pairs that touch: the entry covering the fewest pairs goes
        report.never_collide.pop()
    if options.profile == "fast":
        from robospec.optimize.fast import fast_simulation

        report.simulation, report.contacts = fast_simulation(
            urdf_file, staged_spec, compiled, matrix, options
        )
        staged_spec.write_text(_optimized_spec(compiled, targets, report), encoding="utf-8")


def _packing_problems(spec: Path) -> bool:
    """Whether the spec's never_collide needs more bits than are free: pairs it does not list
    disabled too, or listed pairs left colliding."""
    from robospec.pipeline import compile_spec

    packed = compile_spec(spec).robot
    record = packed.never_collide if packed is not None else None
    return record is not None and bool(record.side_effects or record.uncovered)


def _optimized_spec(compiled: CompiledSpec, targets: Targets, report: OptimizeReport) -> str:
    """The spec as written, with its uid, description and never_collide changed: a YAML spec
    through ruamel's round trip (comments and order kept), a TOML one as YAML."""
    from robospec.optimize.spec_rewrite import rewrite_spec

    simulation = dict(report.simulation or {})
    robot, description = compiled.robot, compiled.description
    if robot is not None and description is not None and description.armature:
        # an MJCF's armature is a fact of its compiled model, which the URDF written from it
        # cannot carry: the optimized spec says it
        simulation["armature"] = dict(robot.armature)
    return rewrite_spec(
        compiled.path,
        targets.spec,
        uid=report.uid,
        urdf=targets.urdf.name,
        never_collide=report.never_collide,
        header=f"# {MARK} from {compiled.path.name}: robospec optimize rewrites this file",
        simulation=simulation,
    )
