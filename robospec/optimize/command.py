"""``robospec optimize SPEC -o OUT.yaml``: compile the spec, condense its URDF, simplify its
collision shapes, declare the link pairs that never touch, and write OUT.yaml with the optimized
description beside it.

What is written, all beside OUT: ``OUT.yaml`` (the spec, pointing at the new description),
``<stem>.urdf`` (the optimized description: meshes named relative to it), ``<stem>.srdf`` (the
SRDF SAPIEN reads beside the original URDF, when there is one) and ``<stem>_collision/`` (the
collision meshes it made). Each carries robospec's mark, and a file without it is never
overwritten (RS604). Everything is written to temporary names first and renamed in place at the
end, so a failure leaves the old output or none, never a part.

``--profile fast`` changes how the robot collides, for speed (see :mod:`robospec.optimize.fast`):
collision meshes become boxes, capsules or spheres where one lies within ``--max-error`` of
the mesh, the robot's own shapes get a contact offset small enough that pairs that never touch
make no contacts, and the spec recommends solver iterations for the robot's category; all of
it is written into the spec's ``simulation`` section, and the report gives each change with
what it measured.

The links kept are every link the spec names — wherever: groups' links, camera mounts, tcp,
ee_link and root_link_name, named links, link and collision rules, never_collide, grasping and
the other members' links, drives (``Bindings.link_names`` of the resolve stage) — the links of
the SRDF's pairs, the root, and those ``--keep`` pins.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robospec.diagnostics import Diagnostic, Location, error, has_errors, warning
from robospec.maniskill.scenes import CONTACT_OFFSET

# the first line of every file robospec optimize writes: what it may overwrite
MARK = "written by robospec optimize"
SHAPE_METHODS = ("keep", "convert", "hull", "coacd", "primitives")
PROFILES = ("default", "fast")
CATEGORIES = ("manipulation", "locomotion")
# --max-error: a primitive standing off the mesh by more than 5 cm is another robot
MAX_ERROR_RANGE = (0.0, 0.05)  # exclusive, inclusive; m
DEFAULT_MAX_ERROR = 0.005
# --contact-offset: above ManiSkill's own 2 cm it is no profile for speed; below 0.1 mm PhysX
# sees contacts only once shapes touch
CONTACT_OFFSET_RANGE = (0.0001, CONTACT_OFFSET)  # inclusive; m
FINAL_URDF = ".final.urdf"  # in the staging folder: the URDF as it is named from OUT's folder


@dataclass(frozen=True)
class OptimizeOptions:
    keep: tuple[str, ...] = ()  # links to keep although the spec does not name them
    uid: str | None = None  # the optimized spec's uid; default: the spec's, plus "_optimized"
    shapes: str = ""  # what becomes of collision meshes: SHAPE_METHODS ("": the profile's)
    max_vertices: int | None = None  # a cap on each convex shape's vertices (hull)
    samples: int = 10_000  # configurations for the collision matrix (MoveIt's default); 0: none
    seed: int = 0
    profile: str = "default"  # PROFILES: "fast" changes how the robot collides, for speed
    max_error: float | None = None  # primitives: how far one may stand off the mesh (m)
    contact_offset: float | None = None  # fast: the robot's shapes' offset (default: measured)
    category: str | None = None  # fast: manipulation or locomotion (default: by the body)
    # the command line as given (after the program name): where each option's value stands,
    # for the diagnostics about it
    arguments: tuple[str, ...] = ()

    @property
    def shape_method(self) -> str:
        """The shapes method asked for, or the profile's: primitives for fast."""
        if self.shapes != "":
            return self.shapes
        return "primitives" if self.profile == "fast" else "convert"


@dataclass
class OptimizeReport:
    spec: str
    out: str
    description: str  # the optimized description, relative to OUT's folder
    uid: str
    links_before: int = 0
    links_after: int = 0
    merged: list[tuple[str, str, str]] = field(default_factory=list)  # (link, into, joint)
    kept: list[str] = field(default_factory=list)  # links on fixed joints kept: named by the spec
    # links on fixed joints kept because SAPIEN takes their mass (or their parent's) from
    # collision shapes, or a <mimic> names their joint
    unmerged: list[str] = field(default_factory=list)
    shapes: list[dict[str, Any]] = field(default_factory=list)
    never_collide: list[list[str]] = field(default_factory=list)  # entries added
    samples: int = 0
    profile: str = "default"
    # the fast profile: the spec's simulation section as written, and what it measured
    simulation: dict[str, Any] = field(default_factory=dict)
    contacts: list[dict[str, Any]] = field(default_factory=list)  # before, after
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def to_json(self) -> dict[str, Any]:
        return {
            "spec": self.spec,
            "out": self.out,
            "description": self.description,
            "uid": self.uid,
            "links": {"before": self.links_before, "after": self.links_after},
            "merged": [{"link": a, "into": b, "joint": j} for a, b, j in self.merged],
            "kept": self.kept,
            "unmerged": self.unmerged,
            "collision_shapes": self.shapes,
            "never_collide": {"samples": self.samples, "entries": self.never_collide},
            "profile": self.profile,
            "simulation": self.simulation,
            "contacts": self.contacts,
            "diagnostics": [d.to_json() for d in self.diagnostics],
        }

    def to_text(self) -> str:
        lines = [
            f"{self.spec} -> {self.out} (uid {self.uid}, description {self.description})",
            f"  links: {self.links_before} -> {self.links_after} ({len(self.merged)} merged)",
        ]
        lines += [
            f"    {link} -> {into} (fixed joint {joint})" for link, into, joint in self.merged
        ]
        if self.kept:
            lines.append("  kept on fixed joints, named by the spec: " + ", ".join(self.kept))
        if self.unmerged:
            lines.append(
                "  kept on fixed joints, their mass (or their parent's) SAPIEN takes from their "
                "collision shapes, or a <mimic> names the joint: " + ", ".join(self.unmerged)
            )
        if self.shapes:
            before = sum(s["shapes_before"] for s in self.shapes)
            after = sum(s["shapes_after"] for s in self.shapes)
            v_before = sum(s["vertices_before"] for s in self.shapes)
            v_after = sum(s["vertices_after"] for s in self.shapes)
            lines.append(
                f"  collision shapes: {before} -> {after}, vertices {v_before} -> {v_after}"
            )
            lines += [
                f"    {s['link']}: {s['method']} {s['shapes_before']} -> {s['shapes_after']} "
                f"shape(s), {s['vertices_before']} -> {s['vertices_after']} vertices" + _fit_text(s)
                for s in self.shapes
                if s["method"] != "kept" or s.get("reason")
            ]
        if self.samples:
            lines.append(
                f"  never_collide: {len(self.never_collide)} entr(ies) from {self.samples} "
                "sampled configurations and the keyframes"
            )
            lines += [f"    [{', '.join(entry)}]" for entry in self.never_collide]
        if self.profile != "default":
            lines += _profile_text(self.profile, self.simulation, self.contacts)
        return "\n".join(lines)


def _fit_text(shape: dict[str, Any]) -> str:
    if shape.get("fit_error") is None and not shape.get("reason"):
        return ""
    text = ""
    if shape.get("fit_error") is not None:
        text += f", {shape['fit']} within {shape['fit_error'] * 1000:.2f} mm"
    if shape.get("reason"):
        text += f" (kept: {shape['reason']})"
    return text


def _profile_text(
    profile: str, simulation: dict[str, Any], contacts: list[dict[str, Any]]
) -> list[str]:
    lines = [f"  profile {profile}: the robot collides differently, for speed"]
    if "contact_offset" in simulation:
        lines.append(
            f"    contact offset of the robot's shapes: {simulation['contact_offset']} m "
            "(ManiSkill's scenes: 0.02 m)"
        )
    if len(contacts) == 2:
        before, after = contacts
        lines.append(
            f"      pairs of its links making contacts, per sampled configuration: "
            f"{before['pairs_per_configuration']:.1f} -> {after['pairs_per_configuration']:.1f} "
            f"({before['configurations']} configurations); pairs that never touch making "
            f"contacts: {before['never_touching_pairs']} -> {after['never_touching_pairs']}"
        )
    if "solver_position_iterations" in simulation:
        lines.append(
            f"    recommended sim config ({simulation.get('category')}): solver iterations "
            f"{simulation['solver_position_iterations']} position, "
            f"{simulation['solver_velocity_iterations']} velocity "
            "(sim_config_for(uid); ManiSkill's default 15 and 1)"
        )
    return lines


def run_optimize(
    spec: Path, out: Path, options: OptimizeOptions = OptimizeOptions()
) -> tuple[OptimizeReport | None, list[Diagnostic]]:
    """Optimize ``spec`` into ``out``; the report, or None and the diagnostics that stopped it."""
    try:
        return _run_optimize(spec, out, options)
    except Exception as exc:  # a bug of ours must still be a located diagnostic, and no output
        return None, [
            error(
                Location(str(spec)),
                "RS900",
                f"internal error: {type(exc).__name__}: {exc}",
                "please report this with the spec that caused it",
            )
        ]


def _run_optimize(
    spec: Path, out: Path, options: OptimizeOptions
) -> tuple[OptimizeReport | None, list[Diagnostic]]:
    from robospec.pipeline import compile_spec

    command_line = Location("<command line>")
    problems = _option_problems(options, command_line)
    if problems:
        return None, problems
    compiled = compile_spec(spec)
    if not compiled.ok or compiled.robot is None or compiled.context is None:
        return None, list(compiled.diagnostics) or [
            error(Location(str(spec)), "RS607", "the spec does not compile")
        ]
    robot = compiled.robot
    if robot.parts:
        # the condensed description would hold the parts' links, which the optimized spec's
        # parts: would then mount a second time; split back, fold_frames' frames are gone
        return None, [
            error(
                compiled.loaded.source.key(("parts",)) if compiled.loaded else Location(str(spec)),
                "RS743",
                "robospec optimize condenses one description, and this robot is composed of "
                f"{len(robot.parts) + 1} (parts: " + ", ".join(p.name for p in robot.parts) + ")",
                "optimize the robot's description and each part's spec on their own, and mount "
                "the optimized parts",
            )
        ]
    if robot.description_kind != "urdf" or compiled.description is None:
        return None, [
            error(
                Location(str(spec)),
                "RS607",
                "robospec optimize condenses URDF and xacro descriptions; this robot's is "
                f"{robot.description_kind.upper()}",
                'MuJoCo\'s compiler fuses static bodies itself (<compiler fusestatic="true"/>)',
            )
        ]
    targets = _targets(out)
    owned = [_not_ours(path, out) for path in targets.values()]
    if any(owned):
        return None, [d for d in owned if d is not None]
    report = OptimizeReport(str(spec), str(out), targets["urdf"].name, _uid(robot.uid, options))
    report.diagnostics.extend(d for d in compiled.diagnostics if not d.is_error)
    if robot.base is not None or robot.hooks.after_init or robot.hooks.after_loading_articulation:
        report.diagnostics.append(
            warning(
                Location(str(spec)),
                "RS608",
                "links named by Python code (extends, hooks) are not known to robospec optimize",
                "pin each with --keep LINK",
            )
        )
    try:  # -o into a folder that does not exist yet makes it, as build -o does
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return None, [error(command_line, "RS603", f"cannot make {out.parent}: {exc.strerror}")]
    # absolute: the meshes written there are named from it, and -o may be a relative path
    with tempfile.TemporaryDirectory(
        prefix=".robospec-optimize-", dir=out.parent.resolve()
    ) as staging:
        written = _optimize_into(Path(staging), compiled, targets, options, report)
        if has_errors(written):
            return None, written
        # the output spec must compile: a mistake of ours must not reach the user's folder
        check = compile_spec(Path(staging) / targets["spec"].name)
        if not check.ok:
            return None, list(check.diagnostics)
        _move_into_place(Path(staging), targets)
    return report, report.diagnostics


def _option_problems(options: OptimizeOptions, at: Location) -> list[Diagnostic]:
    """Every option problem, each located at its value on the command line."""
    import math

    from robospec.diagnostics.command_line import argument_location
    from robospec.diagnostics.suggest import did_you_mean

    def where(option: str, value: object) -> Location:
        if not options.arguments:
            return at
        return argument_location(option, str(value), options.arguments)

    problems: list[Diagnostic] = []
    if options.shapes not in ("", *SHAPE_METHODS):
        problems.append(
            error(
                where("--shapes", options.shapes),
                "RS607",
                f"--shapes {options.shapes!r} is not one of {', '.join(SHAPE_METHODS)}",
            )
        )
    if options.profile not in PROFILES:
        problems.append(
            error(
                where("--profile", options.profile),
                "RS670",
                f"unknown profile {options.profile!r}",
                did_you_mean(options.profile, PROFILES) or "profiles: " + ", ".join(PROFILES),
            )
        )
    if options.category is not None and options.category not in CATEGORIES:
        problems.append(
            error(
                where("--category", options.category),
                "RS675",
                f"unknown category {options.category!r}",
                did_you_mean(options.category, CATEGORIES)
                or "categories: " + ", ".join(CATEGORIES),
            )
        )
    low, high = MAX_ERROR_RANGE
    if options.max_error is not None and not (
        math.isfinite(options.max_error) and low < options.max_error <= high
    ):
        problems.append(
            error(
                where("--max-error", _argument_text(options.max_error, options.arguments)),
                "RS671",
                f"--max-error {options.max_error:g} is out of range: a primitive may stand "
                f"off the mesh by more than 0 and at most {high:g} m",
                f"the fast profile's default is {DEFAULT_MAX_ERROR:g} m (5 mm)",
            )
        )
    low, high = CONTACT_OFFSET_RANGE
    if options.contact_offset is not None and not (
        math.isfinite(options.contact_offset) and low <= options.contact_offset <= high
    ):
        problems.append(
            error(
                where(
                    "--contact-offset", _argument_text(options.contact_offset, options.arguments)
                ),
                "RS672",
                f"--contact-offset {options.contact_offset:g} is out of range: from {low:g} "
                f"to {high:g} m (ManiSkill's own offset)",
                "leave it out and the fast profile measures one",
            )
        )
    if problems or options.profile not in PROFILES:
        return sorted(problems, key=lambda d: d.location)
    fast_only = [
        (name, value)
        for name, value in (
            ("--contact-offset", options.contact_offset),
            ("--category", options.category),
        )
        if value is not None and options.profile != "fast"
    ]
    if options.max_error is not None and options.shape_method != "primitives":
        fast_only.append(("--max-error", options.max_error))
    return [
        error(
            where(name, _argument_text(value, options.arguments)),
            "RS676",
            f"{name} applies only to "
            + (
                "primitive collision shapes (--shapes primitives, or --profile fast)"
                if name == "--max-error"
                else "--profile fast"
            ),
            "add --profile fast" if options.shape_method != "primitives" else None,
        )
        for name, value in fast_only
    ]


def _argument_text(value: object, arguments: Sequence[str]) -> str:
    """A number option's value as the command line wrote it (``5e-3`` for 0.005), to locate
    it there; as Python writes it when the command line is not known."""
    if isinstance(value, float):
        for argument in arguments:
            text = argument.partition("=")[2] or argument
            try:
                if float(text) == value:
                    return text
            except ValueError:
                continue
    return str(value)


def _uid(uid: str, options: OptimizeOptions) -> str:
    return options.uid if options.uid else f"{uid}_optimized"


def _targets(out: Path) -> dict[str, Path]:
    stem = out.name.split(".")[0]
    return {
        "spec": out,
        "urdf": out.with_name(f"{stem}.urdf"),
        "srdf": out.with_name(f"{stem}.srdf"),
        "collision": out.with_name(f"{stem}_collision"),
    }


def _not_ours(path: Path, out: Path) -> Diagnostic | None:
    """RS607 when ``path`` exists and robospec optimize did not write it."""
    if not path.exists() and not path.is_symlink():
        return None
    marked = path / ".robospec-optimize" if path.is_dir() else path
    try:
        with open(marked, encoding="utf-8", errors="replace") as stream:
            head = stream.read(200)
    except OSError:
        head = ""
    if MARK in head:
        return None
    return error(
        Location(str(path)),
        "RS604",
        f"{path} exists and robospec optimize did not write it; it is not overwritten",
        f"move it away, or write the optimized spec elsewhere than {out}",
    )


def _optimize_into(
    staging: Path,
    compiled: Any,
    targets: dict[str, Path],
    options: OptimizeOptions,
    report: OptimizeReport,
) -> list[Diagnostic]:
    """Write every output under ``staging`` (same names as ``targets``); errors, if any."""
    from robospec.optimize.condense import condense

    robot = compiled.robot
    description = compiled.description
    urdf = _absolute_meshes(robot.description.read_text(), description)
    keep = _links_to_keep(compiled, urdf, options)
    unknown = [name for name in options.keep if description.link(name) is None]
    if unknown:
        return [
            error(Location("<command line>"), "RS202", f"--keep: unknown link '{name}'")
            for name in unknown
        ]
    condensed = condense(urdf, keep)
    merged_away = _named_links_merged_away(compiled, condensed.robot)
    if merged_away:
        return merged_away
    report.profile = options.profile
    report.links_before = len(urdf.findall("link"))
    report.links_after = len(condensed.robot.findall("link"))
    report.merged = [(m.link, m.into, m.joint) for m in condensed.merged]
    report.kept = sorted(
        name
        for name in keep
        if any(j.get("type") == "fixed" and _child(j) == name for j in urdf.findall("joint"))
    )
    report.unmerged = sorted(
        name
        for joint in condensed.robot.findall("joint")
        if joint.get("type") == "fixed" and (name := _child(joint)) is not None
        if name not in keep
    )
    optimized = condensed.robot
    collision_dir = staging / targets["collision"].name
    method = options.shape_method
    if method != "keep":
        from robospec.optimize.shapes import MissingDependency, optimize_collisions

        collision_dir.mkdir()
        (collision_dir / ".robospec-optimize").write_text(MARK + "\n")
        try:
            optimized, changes = optimize_collisions(
                optimized,
                collision_dir,
                method=method,
                max_vertices=options.max_vertices,
                # what SAPIEN builds from a mesh depends on it: one hull, or one per part
                multiple_collisions=robot.load_multiple_collisions,
                max_error=_max_error(options),
            )
        except MissingDependency as exc:
            return [error(Location("<command line>"), "RS607", str(exc), exc.hint)]
        report.shapes = [_shape_json(c) for c in changes]
        unfitted = (
            _unfitted(compiled, changes, _max_error(options)) if method == "primitives" else None
        )
        if unfitted is not None:
            report.diagnostics.append(unfitted)
        if all(p.name == ".robospec-optimize" for p in collision_dir.iterdir()):
            shutil.rmtree(collision_dir)  # nothing was made: no folder
    # two renders: one that works from the staging folder, checked there, and the one that
    # works from OUT's folder, which replaces the first when everything is moved into place
    urdf_file = staging / targets["urdf"].name
    source = robot.description.relative
    _write_urdf(optimized, urdf_file, staging, staging, source)
    final_dir = targets["urdf"].parent
    _write_urdf(optimized, staging / FINAL_URDF, final_dir, staging, source, final_dir=final_dir)
    srdf = _srdf_of(robot.description)
    if srdf is not None:
        (staging / targets["srdf"].name).write_text(
            srdf.replace("?>", f"?>\n<!-- {MARK} -->", 1)
            if srdf.startswith("<?xml")
            else f"<!-- {MARK} -->\n{srdf}"
        )
    matrix = None
    if options.samples:
        report.samples = options.samples
        report.never_collide, matrix = _never_collide(urdf_file, optimized, compiled, options)
    staged_spec = staging / targets["spec"].name
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
    return []


def _max_error(options: OptimizeOptions) -> float:
    return options.max_error if options.max_error is not None else DEFAULT_MAX_ERROR


def _unfitted(compiled: Any, changes: Sequence[Any], bound: float) -> Diagnostic | None:
    """RS674 when some collision meshes fit no primitive within the bound: which, and the
    nearest miss."""
    missed = [c for c in changes if c.reason == "no primitive within the bound"]
    if not missed:
        return None
    nearest = min(missed, key=lambda c: c.fit_error)
    fitted = sum(c.primitives for c in changes)
    return warning(
        Location(str(compiled.path)),
        "RS674",
        f"{len(missed)} collision mesh(es) fit no primitive within {bound * 1000:g} mm and keep "
        f"the shapes SAPIEN makes of them ({fitted} became primitives); the nearest miss: "
        f"{nearest.link}'s {nearest.fit}, {nearest.fit_error * 1000:.1f} mm off",
        "a larger --max-error turns more into primitives, and changes the robot more",
    )


def _named_links_merged_away(compiled: Any, condensed: Any) -> list[Diagnostic]:
    """RS673 for each link the spec names that the condensed description lacks, where the
    spec names it: optimize keeps every link the spec names, so this is a link named where
    the keep list did not look, and the optimized spec would not compile."""
    present = {link.get("name") for link in condensed.findall("link")}
    problems = []
    seen: set[str] = set()
    for path, name in compiled.context.bindings.link_names:
        if name in present or name in seen:
            continue
        seen.add(name)
        problems.append(
            error(
                compiled.context.value(path),
                "RS673",
                f"link '{name}' would be merged away by robospec optimize, and the spec names it",
                f"keep it with --keep {name}",
            )
        )
    return problems


def _packing_problems(spec: Path) -> bool:
    """Whether the spec's never_collide needs more bits than are free: pairs it does not list
    disabled too, or listed pairs left colliding."""
    from robospec.pipeline import compile_spec

    packed = compile_spec(spec).robot
    record = packed.never_collide if packed is not None else None
    return record is not None and bool(record.side_effects or record.uncovered)


def _absolute_meshes(text: str, description: Any) -> Any:
    """The URDF's <robot> with every mesh and texture robospec found named by absolute path."""
    from lxml import etree

    root = etree.fromstring(text.encode())
    found = {m.uri: m.path for m in description.mesh_files if m.path is not None}
    for element in root.iter("mesh", "texture"):
        filename = element.get("filename")
        if filename in found:
            element.set("filename", str(Path(found[filename]).resolve()))
    return root


def _child(joint: Any) -> str | None:
    child = joint.find("child")
    return child.get("link") if child is not None else None


def _links_to_keep(compiled: Any, urdf: Any, options: OptimizeOptions) -> set[str]:
    keep = {name for _, name in compiled.context.bindings.link_names}
    keep.update(options.keep)
    srdf = _srdf_of(compiled.robot.description)
    if srdf is not None:
        from lxml import etree

        for pair in etree.fromstring(srdf.encode()).iter("disable_collisions"):
            keep.update(filter(None, (pair.get("link1"), pair.get("link2"))))
    return keep


def _srdf_of(ref: Any) -> str | None:
    """The SRDF SAPIEN reads beside the spec's URDF (never beside a xacro expansion)."""
    if not ref.has_srdf_beside:
        return None
    from robospec.description.srdf import srdf_path

    srdf = Path(srdf_path(str(ref.absolute)))
    return srdf.read_text() if srdf.is_file() else None


def _write_urdf(
    robot: Any,
    path: Path,
    relative_to: Path,
    staging: Path,
    source: str,
    final_dir: Path | None = None,
) -> None:
    """The optimized URDF, its meshes named relative to ``relative_to``; meshes written under
    ``staging`` are named where they will be under ``final_dir`` (when given)."""
    from lxml import etree

    robot = etree.fromstring(etree.tostring(robot))
    for element in robot.iter("mesh", "texture"):
        filename = element.get("filename") or ""
        if os.path.isabs(filename):
            target = Path(filename)
            if final_dir is not None and staging in target.parents:
                target = final_dir / target.relative_to(staging)
            element.set("filename", Path(os.path.relpath(target, relative_to)).as_posix())
    robot.addprevious(etree.Comment(f" {MARK} from {source}: do not edit "))
    text = etree.tostring(robot.getroottree(), encoding="unicode", pretty_print=True)
    path.write_text(text if text.endswith("\n") else text + "\n", encoding="utf-8")


def _shape_json(change: Any) -> dict[str, Any]:
    return {
        "link": change.link,
        "source": Path(change.source).name,
        "method": change.method,
        "shapes_before": change.shapes_before,
        "shapes_after": change.shapes_after,
        "vertices_before": change.vertices_before,
        "vertices_after": change.vertices_after,
        "fit": change.fit or None,
        "fit_error": change.fit_error,
        "reason": change.reason or None,
        "primitives": change.primitives,
    }


def _never_collide(
    urdf_file: Path, urdf: Any, compiled: Any, options: OptimizeOptions
) -> tuple[list[list[str]], Any]:
    """never_collide entries for the pairs that touched in no sampled configuration (or in
    every one), within the group-2 bits the spec leaves free."""
    from robospec.optimize.collision_matrix import sample_collision_matrix
    from robospec.optimize.never_collide import free_bits, never_collide_entries

    robot = compiled.robot
    keyframes = [
        dict(zip(robot.active_joints, keyframe.qpos, strict=False))
        for keyframe in robot.keyframes
        if keyframe.qpos is not None
    ]
    matrix = sample_collision_matrix(
        str(urdf_file),
        samples=options.samples,
        seed=options.seed,
        keyframes=keyframes,
        fix_root_link=robot.fix_root_link,
    )
    taken = {rule.bit for rule in robot.collision_rules if rule.group == 2}
    taken |= set(compiled.context.spec.scene_collision_bits)
    taken |= {bit for bit, _ in compiled.description.loader_collision_bits}
    parents = {
        child: parent.get("link")
        for joint in urdf.iter("joint")
        if (child := _child(joint)) is not None and (parent := joint.find("parent")) is not None
    }
    entries = never_collide_entries(
        matrix.never | matrix.always, matrix.adjacent, free_bits(taken), parents
    )
    return entries, matrix


def _optimized_spec(compiled: Any, targets: dict[str, Path], report: OptimizeReport) -> str:
    """The spec as written, with its uid, description and never_collide changed: a YAML spec
    through ruamel's round trip (comments and order kept), a TOML one as YAML."""
    from robospec.optimize.spec_rewrite import rewrite_spec

    return rewrite_spec(
        compiled.path,
        targets["spec"],
        uid=report.uid,
        urdf=targets["urdf"].name,
        never_collide=report.never_collide,
        header=f"# {MARK} from {compiled.path.name}: robospec optimize rewrites this file",
        simulation=report.simulation,
    )


def _move_into_place(staging: Path, targets: dict[str, Path]) -> None:
    """Rename each staged output over its target; the spec last, so that it never names a
    description that is not there yet."""
    os.replace(staging / FINAL_URDF, staging / targets["urdf"].name)
    for key in ("collision", "urdf", "srdf", "spec"):
        staged = staging / targets[key].name
        final = targets[key]
        if key == "collision" and final.is_dir():
            shutil.rmtree(final)
        elif not staged.exists() and final.exists() and key in ("srdf", "collision"):
            # an output of an earlier run that this one does not make
            shutil.rmtree(final) if final.is_dir() else final.unlink()
        if staged.exists():
            os.replace(staged, final)


def render(report: OptimizeReport | None, diagnostics: Sequence[Diagnostic], fmt: str) -> str:
    import json

    if fmt == "json":
        data = report.to_json() if report is not None else {"diagnostics": []}
        if report is None:
            data["diagnostics"] = [d.to_json() for d in diagnostics]
        return json.dumps(data, indent=2)
    parts = [report.to_text()] if report is not None else []
    parts += [d.format_text() for d in diagnostics]
    return "\n".join(parts)
