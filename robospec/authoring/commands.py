"""What ``robospec inspect``, ``new`` and ``doc`` do apart from argument parsing: each returns
its output text and diagnostics, and writes files only when it has no errors (atomically)."""

from __future__ import annotations

import os
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error, has_errors


def run_inspect(path: Path, format: str) -> tuple[str | None, list[Diagnostic]]:
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.inspect import inspect_report, render_json, render_text

    source, diagnostics = read_description_file(path)
    if source is None:
        return None, diagnostics
    report = inspect_report(source)
    return (render_json(report) if format == "json" else render_text(report)), diagnostics


def run_new(
    description: Path, out: Path, uid: str | None, force: bool
) -> tuple[list[Path] | None, list[Diagnostic]]:
    """The files written (the spec at ``out``, and the schema its modeline names when there was
    none to name) and the diagnostics; None when nothing was written."""
    if uid is not None:
        from robospec.cli.uid_option import invalid_uid
        from robospec.maniskill.builtin_uids import MANISKILL_UIDS

        problem = invalid_uid(uid)
        if problem is not None:
            return None, [problem]
        if uid in MANISKILL_UIDS:
            return None, [
                error(
                    Location("<uid>"),
                    "RS306",
                    f"uid '{uid}' is already registered by ManiSkill",
                    f"use a new uid such as 'rs_{uid}'",
                )
            ]
    if out.exists() and not force:
        return None, [
            error(
                Location(str(out)),
                "RS601",
                f"{out} already exists; robospec new does not overwrite it",
                "pass --force to replace it",
            )
        ]
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.scaffold import SCHEMA_BESIDE, scaffold, schema_reference
    from robospec.importer.yamlout import to_yaml

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
    written = [out]
    reference = schema_reference(out.parent)
    if reference is None:
        # no schema to point at: put one beside the spec, so that editors check and complete
        # it offline from the first keystroke (the next spec in this folder will find it)
        from robospec.schema import schema_text

        reference = SCHEMA_BESIDE
        written.append(out.parent / SCHEMA_BESIDE)
        diagnostics.extend(write_text(written[-1], schema_text()))
    diagnostics.extend(write_text(out, to_yaml(scaffold(source, out, uid), reference)))
    return (None if has_errors(diagnostics) else written), diagnostics


def run_doc(spec: Path, out: Path) -> list[Diagnostic]:
    from robospec.authoring.card import robot_card
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    diagnostics = list(compiled.diagnostics)
    if has_errors(diagnostics) or compiled.robot is None or compiled.description is None:
        return diagnostics
    # the spec as seen from the card, so the card links to it wherever both are
    spec_link = Path(os.path.relpath(spec.resolve(), out.resolve().parent)).as_posix()
    text = robot_card(compiled.robot, compiled.description, spec_link)
    return diagnostics + write_text(out, text)


def write_text(path: Path, text: str) -> list[Diagnostic]:
    from robospec.files import write_atomically

    try:
        write_atomically(path, text)
    except OSError as exc:
        return [
            error(
                Location(str(path)),
                "RS603",
                f"cannot write {path}: {exc.strerror or type(exc).__name__}",
            )
        ]
    return []
