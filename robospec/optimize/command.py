"""``robospec optimize SPEC -o OUT.yaml``: compile the spec, condense its URDF, simplify its
collision shapes, declare the link pairs that never touch, and write OUT.yaml with the optimized
description beside it.

What is written, all beside OUT: ``OUT.yaml`` (the spec, pointing at the new description),
``<stem>.urdf`` (the optimized description: meshes named relative to it), ``<stem>.srdf`` (the
SRDF SAPIEN reads beside the original URDF, when there is one) and ``<stem>_collision/`` (the
collision meshes it made). Each carries robospec's mark, and a file without it is never
overwritten (RS604). Everything is written to temporary names first and renamed in place at the
end, so a failure leaves the old output or none, never a part.

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

# the first line of every file robospec optimize writes: what it may overwrite
MARK = "written by robospec optimize"
SHAPE_METHODS = ("keep", "convert", "hull", "coacd", "primitives")
FINAL_URDF = ".final.urdf"  # in the staging folder: the URDF as it is named from OUT's folder


@dataclass(frozen=True)
class OptimizeOptions:
    keep: tuple[str, ...] = ()  # links to keep although the spec does not name them
    uid: str | None = None  # the optimized spec's uid; default: the spec's, plus "_optimized"
    shapes: str = "convert"  # what becomes of collision meshes: SHAPE_METHODS
    max_vertices: int | None = None  # a cap on each convex shape's vertices (hull)
    samples: int = 10_000  # configurations for the collision matrix (MoveIt's default); 0: none
    seed: int = 0


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
                f"shape(s), {s['vertices_before']} -> {s['vertices_after']} vertices"
                for s in self.shapes
                if s["method"] != "kept"
            ]
        if self.samples:
            lines.append(
                f"  never_collide: {len(self.never_collide)} entr(ies) from {self.samples} "
                "sampled configurations and the keyframes"
            )
            lines += [f"    [{', '.join(entry)}]" for entry in self.never_collide]
        return "\n".join(lines)


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
    if options.shapes not in SHAPE_METHODS:
        return [
            error(
                at,
                "RS607",
                f"--shapes {options.shapes!r} is not one of {', '.join(SHAPE_METHODS)}",
            )
        ]
    return []


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
    urdf = _absolute_meshes(_description_text(robot.description), description)
    keep = _links_to_keep(compiled, urdf, options)
    unknown = [name for name in options.keep if description.link(name) is None]
    if unknown:
        return [
            error(Location("<command line>"), "RS202", f"--keep: unknown link '{name}'")
            for name in unknown
        ]
    condensed = condense(urdf, keep)
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
    if options.shapes != "keep":
        from robospec.optimize.shapes import MissingDependency, optimize_collisions

        collision_dir.mkdir()
        (collision_dir / ".robospec-optimize").write_text(MARK + "\n")
        try:
            optimized, changes = optimize_collisions(
                optimized,
                collision_dir,
                method=options.shapes,
                max_vertices=options.max_vertices,
                # what SAPIEN builds from a mesh depends on it: one hull, or one per part
                multiple_collisions=robot.load_multiple_collisions,
            )
        except MissingDependency as exc:
            return [error(Location("<command line>"), "RS607", str(exc), exc.hint)]
        report.shapes = [_shape_json(c) for c in changes]
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
    if options.samples:
        report.samples = options.samples
        report.never_collide = _never_collide(urdf_file, optimized, compiled, options)
    staged_spec = staging / targets["spec"].name
    while True:
        staged_spec.write_text(_optimized_spec(compiled, targets, report), encoding="utf-8")
        if not report.never_collide or not _packing_problems(staged_spec):
            return []
        # the packer could not honour every entry beside the spec's own without disabling
        # pairs that touch: the entry covering the fewest pairs goes
        report.never_collide.pop()


def _packing_problems(spec: Path) -> bool:
    """Whether the spec's never_collide needs more bits than are free: pairs it does not list
    disabled too, or listed pairs left colliding."""
    from robospec.pipeline import compile_spec

    packed = compile_spec(spec).robot
    record = packed.never_collide if packed is not None else None
    return record is not None and bool(record.side_effects or record.uncovered)


def _description_text(ref: Any) -> str:
    return ref.generated_text if ref.generated_text is not None else ref.absolute.read_text()


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
    }


def _never_collide(
    urdf_file: Path, urdf: Any, compiled: Any, options: OptimizeOptions
) -> list[list[str]]:
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
    return never_collide_entries(
        matrix.never | matrix.always, matrix.adjacent, free_bits(taken), parents
    )


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
