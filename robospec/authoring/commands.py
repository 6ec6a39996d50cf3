"""What ``robospec inspect``, ``new`` and ``doc`` do apart from argument parsing: each returns
its output text and diagnostics, and writes files only when it has no errors (atomically)."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic, Location, error, has_errors, warning

if TYPE_CHECKING:
    from robospec.authoring.analysis import RobotAnalysis
    from robospec.authoring.card import CardPicture
    from robospec.authoring.rest_pose import RestPose
    from robospec.pipeline import CompiledSpec

REST_TOUCHES = "RS605"
NOT_LOADED = "RS606"
# why a rest pose went unchecked that the user should hear about as a warning (ManiSkill is
# installed but failed); "not installed" and --no-sim are only said in the scaffold's header
CANNOT_LOAD_PREFIXES = ("ManiSkill could not load", "the simulator crashed", "loading it in")


def run_inspect(path: Path, format: str) -> tuple[str | None, list[Diagnostic]]:
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.inspect import inspect_report, render_json, render_text

    # a robot ManiSkill would load wrongly is still shown, beside the errors that say so
    source, diagnostics = read_description_file(path, keep_errors=True)
    if source is None:
        return None, diagnostics
    report = inspect_report(source)
    return (render_json(report) if format == "json" else render_text(report)), diagnostics


def run_new(
    description: Path,
    out: Path,
    uid: str | None,
    force: bool,
    simulate: bool = True,
    uid_location: Location | None = None,
) -> tuple[list[Path] | None, list[Diagnostic]]:
    """The files written (the spec at ``out``, and the schema its modeline names when there was
    none to name) and the diagnostics; None when nothing was written.

    With ``simulate`` (and ManiSkill installed) the rest keyframe is searched free of
    self-contact and a floating robot's standing height measured, in a child process
    (:mod:`robospec.authoring.rest_pose`). ``uid_location`` is where ``uid`` was given (the
    command line's ``--uid``), for the diagnostics about it."""
    if uid is not None:
        from robospec.diagnostics.command_line import COMMAND_LINE

        problem = _uid_problem(uid, uid_location or Location(COMMAND_LINE))
        if problem is not None:
            return None, [problem]
    if out.exists() and not force:
        return None, [
            error(
                Location(str(out)),
                "RS601",
                f"{out} already exists; robospec new does not overwrite it",
                "pass --force to replace it",
            )
        ]
    from robospec.authoring.analysis import analyse
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.scaffold import SCHEMA_BESIDE, schema_reference

    source, diagnostics = read_description_file(description)
    if source is None:
        return None, diagnostics
    if not source.description.active_joints:
        return None, [
            *diagnostics,
            error(
                Location(str(description)),
                "RS602",
                f"'{description.name}' has no active joints: there is nothing to control",
                "robospec agents need at least one revolute, continuous or prismatic joint",
            ),
        ]
    analysis = analyse(source)
    written = [out]
    reference = schema_reference(out.parent)
    if reference is None:
        # no schema to point at: put one beside the spec, so that editors check and complete
        # it offline from the first keystroke (the next spec in this folder will find it)
        from robospec.schema import schema_text

        reference = SCHEMA_BESIDE
        written.append(out.parent / SCHEMA_BESIDE)
        diagnostics.extend(write_text(written[-1], schema_text()))
    text, more = scaffold_text(analysis, out, uid, reference, simulate)
    diagnostics.extend(more)
    refused = _validate_errors(text, out)
    if refused:  # never write a spec robospec validate would reject: say what it would say
        return None, [*diagnostics, *refused]
    diagnostics.extend(write_text(out, text))
    return (None if has_errors(diagnostics) else written), diagnostics


def scaffold_text(
    analysis: RobotAnalysis, out: Path, uid: str | None, schema: str, simulate: bool
) -> tuple[str, list[Diagnostic]]:
    """The spec's text, and warnings about its rest pose and its gains.

    With ``simulate``: the rest pose is searched in ManiSkill (:mod:`.rest_pose`), then the
    gains computed there are measured and changed where they miss (:mod:`.refine`), each in a
    child process; without, both stay as computed from the description."""
    from robospec.authoring.joint_gains import joint_gains, rating_warnings, with_refined
    from robospec.authoring.rest_pose import PROBE_UID, Refinement, RestPose, probe_rest_pose
    from robospec.authoring.scaffold import scaffold
    from robospec.authoring.scaffold_controllers import unbalanced
    from robospec.importer.yamlout import to_yaml

    start = analysis.start_qpos()
    found = None
    if simulate:
        draft = scaffold(analysis, out, RestPose(start), PROBE_UID, absolute_paths=True)
        refinement = Refinement(str(analysis.source.path.resolve()), str(out), schema)
        rest, found = probe_rest_pose(
            to_yaml(draft, schema),
            analysis.description,
            start,
            analysis.groups.mimic,
            analysis.body.floating,
            refinement,
            analysis.upright(start),
        )
    else:
        rest = RestPose(start, unchecked_because="robospec new --no-sim")
    gains = joint_gains(analysis, rest.qpos, unbalanced(analysis))
    refined = False
    problems: list[Diagnostic] = []
    if isinstance(found, str):
        problems.append(
            warning(
                Location(str(analysis.source.path)),
                NOT_LOADED,
                f"the gains were not measured in ManiSkill: {found}",
                "they are written as computed from the description; robospec check measures them",
            )
        )
    elif found is not None:
        gains = with_refined(gains, found.gains, found.over_rating)
        refined = bool(found.changed)

    def written(rest: RestPose) -> str:
        return to_yaml(scaffold(analysis, out, rest, uid, gains=gains, refined=refined), schema)

    text = written(rest)
    depth = {(a, b): d for a, b, d in rest.touching}
    while rest.never_collide and _never_collide_rejected(text, out):
        # validate would refuse the pairs (no collision-group bit left for them all): adjacent
        # pairs go first (the last found), then the shallowest overlapping pair (it was the last
        # one found: the Shadow hand lost its 24 mm thumb overlap for a 1 mm one), and the rest
        # warnings name it as touching
        if rest.adjacent:
            rest = dataclasses.replace(rest, adjacent=rest.adjacent[:-1])
        else:
            shallowest = min(rest.overlapping, key=lambda pair: depth.get(pair, 0.0))
            kept = tuple(pair for pair in rest.overlapping if pair != shallowest)
            rest = dataclasses.replace(rest, overlapping=kept)
        text = written(rest)
    return text, [
        *rating_warnings(analysis, gains),
        *problems,
        *_rest_warnings(analysis, rest, text, out),
    ]


def _validate_errors(text: str, out: Path) -> list[Diagnostic]:
    from robospec.pipeline import compile_spec

    return [d for d in compile_spec(out, text=text.encode("utf-8")).diagnostics if d.is_error]


def _never_collide_rejected(text: str, out: Path) -> bool:
    """Whether ``robospec validate`` would refuse the scaffold's never_collide: pairs left
    colliding for want of a free collision-group bit, or pairs it does not list disabled."""
    from robospec.pipeline import compile_spec

    robot = compile_spec(out, text=text.encode("utf-8")).robot
    record = robot.never_collide if robot is not None else None
    return record is not None and bool(record.uncovered or record.side_effects)


def _rest_warnings(
    analysis: RobotAnalysis, rest: RestPose, text: str, out: Path
) -> list[Diagnostic]:
    from robospec.load.reader import parse_spec_bytes

    loaded, _ = parse_spec_bytes(text.encode("utf-8"), str(out), "yaml")
    if loaded is None:
        return []
    at = loaded.source.key(("keyframes", "rest"))
    left = [t for t in rest.touching if (t[0], t[1]) not in rest.never_collide]
    if left:
        pairs = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for a, b, d in left)
        return [
            warning(
                at,
                REST_TOUCHES,
                f"no rest pose free of self-contact found in {rest.tried} tries: {pairs}",
                "move the keyframe apart, or declare the contact with never_collide if it is meant",
            )
        ]
    if rest.unchecked_because and rest.unchecked_because.startswith(CANNOT_LOAD_PREFIXES):
        return [
            warning(
                Location(str(analysis.source.path)),
                NOT_LOADED,
                f"the rest keyframe was not checked: {rest.unchecked_because}",
                "robospec check loads it the same way and will say more; the scaffold is "
                "written without the check",
            )
        ]
    return []


def _uid_problem(uid: str, at: Location) -> Diagnostic | None:
    from robospec.maniskill.installed import registered_uids
    from robospec.model.uid import invalid_uid

    problem = invalid_uid(uid, at)
    if problem is not None:
        return problem
    if uid in registered_uids():
        return error(
            at,
            "RS306",
            f"uid '{uid}' is already registered by ManiSkill",
            f"use a new uid such as 'rs_{uid}'",
        )
    return None


def run_doc(
    spec: Path,
    out: Path,
    plots: Path | None = None,
    images: bool = False,
    collisions: bool = False,
) -> list[Diagnostic]:
    """:func:`write_card`'s diagnostics."""
    return write_card(spec, out, plots, images, collisions)[1]


def write_card(
    spec: Path,
    out: Path,
    plots: Path | None = None,
    images: bool = False,
    collisions: bool = False,
) -> tuple[list[Path], list[Diagnostic]]:
    """Write the card ``out``; with ``images`` also its pictures, in ``<out's stem>_images/``
    beside it (with ``collisions``, the collision shapes too), and the cameras' findings. The
    files written (the card, then each picture), and the diagnostics."""
    from robospec.authoring.card import robot_card
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    diagnostics = list(compiled.diagnostics)
    if has_errors(diagnostics) or compiled.robot is None or compiled.description is None:
        return [], diagnostics
    pictures: list[CardPicture] = []
    if images:
        pictures, more = _pictures(compiled, out, collisions)
        diagnostics += more
        if has_errors(more):
            return [], diagnostics
    # the spec as seen from the card, so the card links to it wherever both are
    spec_link = Path(os.path.relpath(spec.resolve(), out.resolve().parent)).as_posix()
    links = []
    if plots is not None:  # check --plot / tune --plot wrote DIR/<uid>/<controller>.png
        for controller in compiled.robot.controllers:
            picture = plots / compiled.robot.uid / f"{controller.name}.png"
            if picture.is_file():
                relative = os.path.relpath(picture.resolve(), out.resolve().parent)
                links.append((controller.name, Path(relative).as_posix()))
    text = robot_card(compiled.robot, compiled.description, spec_link, links, pictures)
    diagnostics += write_text(out, text)
    if has_errors(diagnostics):
        return [], diagnostics
    return [out, *(out.parent / picture.link for picture in pictures)], diagnostics


def images_folder(out: Path) -> Path:
    """Where ``doc --images`` puts the pictures of the card ``out``."""
    return out.parent / f"{out.stem}_images"


def _pictures(
    compiled: CompiledSpec, out: Path, collisions: bool
) -> tuple[list[CardPicture], list[Diagnostic]]:
    """Draw and write the card's pictures; the diagnostics say what the cameras see, or why
    nothing could be drawn (then nothing is written)."""
    from robospec.authoring.card import CardPicture
    from robospec.diagnostics.command_line import COMMAND_LINE
    from robospec.pictures.album import AlbumOptions, CameraSettings, make_album
    from robospec.pictures.camera_checks import Limits
    from robospec.pictures.gl import RenderUnavailable

    robot, description, context = compiled.robot, compiled.description, compiled.context
    assert robot is not None and description is not None and context is not None
    settings = context.spec.checks.camera_views
    cameras = CameraSettings(
        Limits(
            settings.max_mount_fraction,
            settings.max_robot_fraction,
            settings.min_seen_fraction,
            settings.tcp_in_view,
        ),
        settings.table_height,
        {camera.uid: context.key(("cameras", camera.uid)) for camera in robot.cameras},
    )
    folder = images_folder(out)
    try:
        album = make_album(
            robot, description, cameras, folder.as_posix(), AlbumOptions(collisions=collisions)
        )
    except RenderUnavailable as exc:
        return [], [error(Location(COMMAND_LINE), exc.code, exc.message, exc.hint)]
    diagnostics = list(album.diagnostics)
    for picture in album.pictures:
        diagnostics += write_bytes(folder / picture.path, picture.png)
    relative = Path(os.path.relpath(folder.resolve(), out.resolve().parent)).as_posix()
    pictures = [
        CardPicture(p.kind, p.keyframe, p.name, f"{relative}/{p.path}") for p in album.pictures
    ]
    return pictures, diagnostics


def write_bytes(path: Path, data: bytes) -> list[Diagnostic]:
    return write_text(path, data, mode=0o644)


def write_text(path: Path, text: str | bytes, mode: int | None = None) -> list[Diagnostic]:
    from robospec.files import write_atomically

    try:
        write_atomically(path, text, mode)
    except OSError as exc:
        return [
            error(
                Location(str(path)),
                "RS603",
                f"cannot write {path}: {exc.strerror or type(exc).__name__}",
            )
        ]
    return []
