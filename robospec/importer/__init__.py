"""`robospec import module:Class`: write a spec from an existing ManiSkill agent class.

Three stages, one module each, data flowing one way:

- :mod:`~robospec.importer.introspect` — the class → an :class:`AgentRecord` (plain, frozen
  records; the robot is never loaded into a scene),
- :mod:`~robospec.importer.specdata` — the record → spec data and comments (groups, controller
  names, ``extends``, keyframes by group; upstream mistakes as diagnostics, see
  :mod:`~robospec.importer.upstream`),
- :mod:`~robospec.importer.yamlout` — the data → YAML text.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import IMPORT_MODULE_UNIMPORTABLE, INTERNAL_ERROR

SCHEMA_FILE = Path(__file__).resolve().parent.parent.parent / "schemas" / "robospec.schema.json"


@dataclass
class ImportResult:
    text: str | None
    diagnostics: list[Diagnostic] = field(default_factory=list)


def schema_reference(out_dir: Path) -> str:
    """The schema path for the modeline: relative to the spec's folder."""
    try:
        return Path(os.path.relpath(SCHEMA_FILE, out_dir.resolve())).as_posix()
    except ValueError:
        return SCHEMA_FILE.as_posix()


def import_class(cls: type, uid: str | None = None, out_dir: Path | None = None) -> ImportResult:
    """The spec text for an agent class (``uid`` defaults to the class's own)."""
    from robospec.importer.introspect import load_installed_description, read_agent
    from robospec.importer.specdata import spec_data
    from robospec.importer.yamlout import to_yaml

    out_dir = out_dir or Path.cwd()
    file, description, diagnostics = load_installed_description(cls)
    if description is None:
        file = None
    record, found = read_agent(cls, description, file)
    diagnostics.extend(found)
    doc, found = spec_data(record, uid or record.uid, out_dir)
    diagnostics.extend(found)
    return ImportResult(to_yaml(doc, schema_reference(out_dir)), diagnostics)


def import_agent(target: str, uid: str | None = None, out_dir: Path | None = None) -> ImportResult:
    """``module:Class`` → spec text; every failure is a diagnostic, never an exception."""
    from robospec.importer.target import load_target

    try:
        cls, diagnostics = load_target(target)
        if cls is None:
            return ImportResult(None, diagnostics)
        return import_class(cls, uid, out_dir)
    except ImportError as exc:  # the maniskill extra is not installed
        return ImportResult(
            None,
            [
                error(
                    Location("<module:Class>"),
                    IMPORT_MODULE_UNIMPORTABLE,
                    f"cannot import ManiSkill: {exc}",
                    "pip install 'robospec[maniskill]'",
                )
            ],
        )
    except Exception as exc:  # a bug of ours must still be a diagnostic
        return ImportResult(
            None,
            [
                error(
                    Location("<module:Class>"),
                    INTERNAL_ERROR,
                    f"internal error: {type(exc).__name__}: {exc}",
                    "please report this with the class that caused it",
                )
            ],
        )
