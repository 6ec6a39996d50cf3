"""What ``robospec inspect``, ``new`` and ``doc`` do apart from argument parsing: each returns a
:class:`CommandResult` — the report it prints, the files it writes, its diagnostics — that the
CLI renders and writes (:meth:`CommandResult.write`, atomically). A command lists files to
write only where it has no errors, but for what a failed one wrote before: ``new``'s schema
beside a spec validate refused, ``doc``'s pictures of a card whose cameras fail."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic, Location, error, has_errors
from robospec.diagnostics.codes import CANNOT_WRITE, DUPLICATE_UID, NOTHING_TO_CONTROL, SPEC_EXISTS

if TYPE_CHECKING:
    from robospec.authoring.card import CardPicture, SolvedTask
    from robospec.pipeline import CompiledSpec


@dataclass(frozen=True)
class Output:
    """A file a command writes: where, what, and its mode (None: as a new file's)."""

    path: Path
    content: str | bytes
    mode: int | None = None


@dataclass(frozen=True)
class CommandResult:
    """What an authoring command produced."""

    report: str | None = None  # what it prints on stdout (inspect's report), None: nothing
    outputs: tuple[Output, ...] = ()  # the files it writes, in order
    diagnostics: tuple[Diagnostic, ...] = ()
    written: tuple[Path, ...] = ()  # the files written so far (:meth:`write`)

    @property
    def failed(self) -> bool:
        return has_errors(self.diagnostics)

    def with_diagnostics(self, more: list[Diagnostic]) -> CommandResult:
        return dataclasses.replace(self, diagnostics=(*self.diagnostics, *more))

    def write(self) -> CommandResult:
        """This result with its outputs written, in order: a file that cannot be written is an
        error (RS603), and the files after it are not written (a card never without its
        pictures)."""
        from robospec.files import write_atomically

        written = list(self.written)
        problems = []
        for output in self.outputs:
            try:
                write_atomically(output.path, output.content, output.mode)
            except OSError as exc:
                why = exc.strerror or type(exc).__name__
                at = Location(str(output.path))
                problems.append(error(at, CANNOT_WRITE, f"cannot write {output.path}: {why}"))
                break
            written.append(output.path)
        result = dataclasses.replace(self, outputs=(), written=tuple(written))
        return result.with_diagnostics(problems)


def run_inspect(path: Path, as_json: bool = False, loader: str | None = None) -> CommandResult:
    """The report of the description at ``path`` (text, or JSON); none when it cannot be read.

    An MJCF is read as ``new``'s spec reads it (``loader`` None): compiled by MuJoCo where it
    compiles, else as ManiSkill's MJCF loader reads it; ``loader`` "mujoco" or "maniskill"
    asks for one reading (MuJoCo's refusal is then the diagnostics)."""
    from robospec.authoring.description_file import (
        file_kind,
        read_compiled_mjcf,
        read_description_file,
    )
    from robospec.authoring.inspect import inspect_report, render_json, render_text

    if loader == "mujoco" and file_kind(path) == "mjcf":
        source, diagnostics = read_compiled_mjcf(path)
    else:
        # a robot ManiSkill would load wrongly is still shown, beside the errors that say so
        source, diagnostics = read_description_file(
            path, keep_errors=True, compile_mjcf=loader is None
        )
    if source is None:
        return CommandResult(diagnostics=tuple(diagnostics))
    report = inspect_report(source)
    text = render_json(report) if as_json else render_text(report)
    return CommandResult(text, diagnostics=tuple(diagnostics))


def run_new(
    description: Path,
    out: Path,
    uid: str | None,
    force: bool,
    simulate: bool = True,
    uid_location: Location | None = None,
) -> CommandResult:
    """The spec scaffolded from ``description`` to write at ``out``, then the schema its
    modeline names when there was none to name (:mod:`robospec.authoring.new`).

    With ``simulate`` (and ManiSkill installed) the rest keyframe is searched free of
    self-contact and a floating robot's standing height measured, in a child process.
    ``uid_location`` is where ``uid`` was given (the command line's ``--uid``), for the
    diagnostics about it."""
    from robospec.authoring.new.analysis import analyse
    from robospec.authoring.new.mobile_base import read_for_new
    from robospec.authoring.new.scaffold import SCHEMA_BESIDE, schema_reference
    from robospec.authoring.new.spec_text import scaffold_text

    refused = _refused(description, out, uid, force, uid_location)
    if refused:
        return CommandResult(diagnostics=tuple(refused))
    # (a robot with no joint that moves, or on a planar or floating root joint, is read with
    # a planar base: something to drive)
    source, diagnostics = read_for_new(description)
    if source is None:
        return CommandResult(diagnostics=tuple(diagnostics))
    if not source.description.active_joints:
        return CommandResult(diagnostics=(*diagnostics, _nothing_to_control(description)))
    schema: tuple[Output, ...] = ()
    reference = schema_reference(out.parent)
    if reference is None:
        # no schema to point at: put one beside the spec, so that editors check and complete
        # it offline from the first keystroke (the next spec in this folder will find it)
        from robospec.schema import schema_text

        reference = SCHEMA_BESIDE
        schema = (Output(out.parent / SCHEMA_BESIDE, schema_text()),)
    text, more = scaffold_text(analyse(source), out, uid, reference, simulate)
    diagnostics.extend(more)
    invalid = _validate_errors(text, out)
    if invalid:  # never write a spec robospec validate would reject: say what it would say
        return CommandResult(outputs=schema, diagnostics=(*diagnostics, *invalid))
    return CommandResult(outputs=(Output(out, text), *schema), diagnostics=tuple(diagnostics))


def _refused(
    description: Path, out: Path, uid: str | None, force: bool, uid_location: Location | None
) -> list[Diagnostic]:
    """Why ``new`` writes nothing before it reads the description: a bad ``--uid``, or a spec
    already at ``out`` without ``force``."""
    if uid is not None:
        from robospec.diagnostics.command_line import COMMAND_LINE

        problem = _uid_problem(uid, uid_location or Location(COMMAND_LINE))
        if problem is not None:
            return [problem]
    if out.exists() and not force:
        return [
            error(
                Location(str(out)),
                SPEC_EXISTS,
                f"{out} already exists; robospec new does not overwrite it",
                "pass --force to replace it",
            )
        ]
    return []


def _nothing_to_control(description: Path) -> Diagnostic:
    return error(
        Location(str(description)),
        NOTHING_TO_CONTROL,
        f"'{description.name}' has no active joints: there is nothing to control",
        "robospec agents need at least one revolute, continuous or prismatic joint",
    )


def _validate_errors(text: str, out: Path) -> list[Diagnostic]:
    from robospec.pipeline import compile_spec

    return [d for d in compile_spec(out, text=text.encode("utf-8")).diagnostics if d.is_error]


def _uid_problem(uid: str, at: Location) -> Diagnostic | None:
    from robospec.maniskill.installed import registered_uids
    from robospec.model.uid import invalid_uid

    problem = invalid_uid(uid, at)
    if problem is not None:
        return problem
    if uid in registered_uids():
        return error(
            at,
            DUPLICATE_UID,
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
    demos: Path | None = None,
) -> CommandResult:
    """The card ``out``; with ``images`` also its pictures, in ``<out's stem>_images/`` beside
    it (with ``collisions``, the collision shapes too), written before it, and the cameras'
    findings; with ``demos``, the success of each task whose episodes ``robospec solve -o``
    recorded there for this robot."""
    from robospec.authoring.card import robot_card
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    diagnostics = list(compiled.diagnostics)
    if has_errors(diagnostics) or compiled.robot is None or compiled.description is None:
        return CommandResult(diagnostics=tuple(diagnostics))
    pictures: list[CardPicture] = []
    drawn: list[Output] = []
    if images:
        pictures, drawn, more = _pictures(compiled, out, collisions)
        diagnostics += more
        if has_errors(more):
            return CommandResult(outputs=tuple(drawn), diagnostics=tuple(diagnostics))
    # the spec as seen from the card, so the card links to it wherever both are
    spec_link = Path(os.path.relpath(spec.resolve(), out.resolve().parent)).as_posix()
    links = []
    if plots is not None:  # check --plot / tune --plot wrote DIR/<uid>/<controller>.png
        for controller in compiled.robot.controllers:
            picture = plots / compiled.robot.uid / f"{controller.name}.png"
            if picture.is_file():
                relative = os.path.relpath(picture.resolve(), out.resolve().parent)
                links.append((controller.name, Path(relative).as_posix()))
    solved = solved_tasks(demos, compiled.robot.uid, out) if demos is not None else []
    text = robot_card(compiled.robot, compiled.description, spec_link, links, pictures, solved)
    return CommandResult(outputs=(*drawn, Output(out, text)), diagnostics=tuple(diagnostics))


def solved_tasks(folder: Path, uid: str, out: Path) -> list[SolvedTask]:
    """The tasks ``robospec solve -o folder`` recorded for ``uid``: each ManiSkill trajectory
    record (``TASK.json``: ``env_info`` names the task and the robot, each episode says whether
    it succeeded), by task name; the record linked from the card ``out``."""
    import json

    from robospec.authoring.card import SolvedTask

    found = []
    for record in sorted(folder.glob("*.json")):
        try:
            data = json.loads(record.read_text(encoding="utf-8"))
            info = data["env_info"]
            episodes = data["episodes"]
            robots = info["env_kwargs"].get("robot_uids")
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            continue  # not a trajectory record
        if robots != uid or not isinstance(episodes, list):
            continue
        link = Path(os.path.relpath(record.resolve(), out.resolve().parent)).as_posix()
        successes = sum(bool(e.get("success")) for e in episodes if isinstance(e, dict))
        found.append(SolvedTask(str(info.get("env_id")), len(episodes), successes, link))
    return sorted(found, key=lambda task: task.task)


def images_folder(out: Path) -> Path:
    """Where ``doc --images`` puts the pictures of the card ``out``."""
    return out.parent / f"{out.stem}_images"


def _pictures(
    compiled: CompiledSpec, out: Path, collisions: bool
) -> tuple[list[CardPicture], list[Output], list[Diagnostic]]:
    """The card's pictures, drawn, as the card links them and as files to write; the
    diagnostics say what the cameras see, or why nothing could be drawn (then there is none)."""
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
        return [], [], [error(Location(COMMAND_LINE), exc.code, exc.message, exc.hint)]
    files = [Output(folder / picture.path, picture.png, mode=0o644) for picture in album.pictures]
    relative = Path(os.path.relpath(folder.resolve(), out.resolve().parent)).as_posix()
    pictures = [
        CardPicture(p.kind, p.keyframe, p.name, f"{relative}/{p.path}") for p in album.pictures
    ]
    return pictures, files, list(album.diagnostics)
