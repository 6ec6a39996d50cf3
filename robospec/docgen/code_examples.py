"""The examples behind the per-code pages: data kept next to the docs, run through the compiler.

Each diagnostic code has a folder ``docs/examples/codes/RSxxx/`` holding

- ``fail.<ext>``: a spec that makes robospec report exactly that code,
- ``pass.<ext>``: the same spec fixed, which robospec accepts without that code,
- optionally more failing specs, ``fail_<what>.<ext>``: other ways to get the code (another
  field, another form of the same mistake), shown after the pair,
- any files the two need (a robot description, a xacro file), shown on the page too,
- optionally ``about.md``: prose for the page (why the rule exists, how to fix it).

Codes that no spec triggers through ``robospec validate`` are *documented*: their folder holds
only ``about.md`` with an example (or a check module's docstring documents them), and the page
says the example is not run when the docs are generated. They are RS4xx (``robospec import``
of Python classes), RS5xx (``robospec check``'s physics), RS6xx (``inspect``/``new``/``doc`` on
files named on the command line), RS9xx (internal) and :data:`RESERVED_CODES` (listed, but
not reported by this version).

Where robospec reports each failing example's diagnostics (code, line, column, words of the
message) is written down in ``docs/examples/codes/expected.toml`` (:data:`EXPECTED_FILE`), and
``tests/test_spec_examples.py`` holds every failing example to it: the catalogue is also the
test suite's collection of specs that must fail, and where.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location
from robospec.diagnostics.codes import (
    BAD_ATTACH,
    CONTROLLER_FIELD_MISSING,
    OPTIMIZE_WITH_PARTS,
    PART_INSIDE_ROBOT,
    UNKNOWN_GROUP,
)
from robospec.pipeline import compile_spec
from robospec.reporting import render

EXAMPLES_FOLDER = Path("examples") / "codes"
ABOUT_FILE = "about.md"
FAILING = "fail"
MORE_FAILING = "fail_"  # the prefix of further failing examples' names
PASSING = "pass"
EXPECTED_FILE = "expected.toml"  # in the examples' root: where each failing example reports

# ManiSkill's download folder is $MS_ASSET_DIR/data (robospec.resolve.paths.maniskill_data_dir)
ASSET_DIR_VARIABLE = "MS_ASSET_DIR"
NO_DOWNLOADS = ".no-maniskill-downloads"

# ranges whose examples are documented rather than run at docs-generation time
DOCUMENTED_PREFIXES = ("RS4", "RS5", "RS6", "RS9")
# codes outside those ranges that only a command reports on files named on its command line:
# `robospec check` (a part inside the robot), `robospec new --attach`, `robospec optimize`
COMMAND_CODES = frozenset({PART_INSIDE_ROBOT, BAD_ATTACH, OPTIMIZE_WITH_PARTS})
# in the code table, but no code path of this version reports them (a test keeps that true)
RESERVED_CODES = frozenset({UNKNOWN_GROUP, CONTROLLER_FIELD_MISSING})


def is_documented_only(code: str) -> bool:
    return code.startswith(DOCUMENTED_PREFIXES) or code in RESERVED_CODES | COMMAND_CODES


@dataclass(frozen=True)
class RunExample:
    """One example spec and what robospec reports for it: the diagnostics, and the text
    ``robospec validate`` prints for them in the example's folder."""

    path: Path
    diagnostics: tuple[Diagnostic, ...]
    report: str

    @property
    def text(self) -> str:
        # an RS001 example is deliberately not UTF-8: show its bytes as the replacement char
        return self.path.read_bytes().decode("utf-8", errors="replace")

    @property
    def codes(self) -> set[str]:
        return {d.code for d in self.diagnostics}

    @property
    def error_codes(self) -> set[str]:
        return {d.code for d in self.diagnostics if d.is_error}


@dataclass(frozen=True)
class CodeExamples:
    code: str
    folder: Path
    about: str | None
    failing: RunExample | None
    passing: RunExample | None
    more_failing: tuple[RunExample, ...]  # fail_*.<ext>, in name order
    support_files: tuple[Path, ...]  # files the examples need (descriptions), in name order


def examples_root(docs_dir: Path) -> Path:
    return docs_dir / EXAMPLES_FOLDER


def load_code_examples(docs_dir: Path, code: str) -> CodeExamples:
    """Read the folder of ``code`` and run its examples (a missing folder gives no examples)."""
    folder = examples_root(docs_dir) / code
    files = sorted(p for p in folder.iterdir() if p.is_file()) if folder.is_dir() else []
    about_path = folder / ABOUT_FILE
    about = about_path.read_text(encoding="utf-8") if about_path.is_file() else None
    failing = _spec_named(files, FAILING)
    passing = _spec_named(files, PASSING)
    more = [p for p in files if p.stem.startswith(MORE_FAILING)]
    support = tuple(p for p in files if p not in (failing, passing, about_path, *more))
    return CodeExamples(
        code=code,
        folder=folder,
        about=about,
        failing=run_example(failing) if failing else None,
        passing=run_example(passing) if passing else None,
        more_failing=tuple(run_example(p) for p in more),
        support_files=support,
    )


def failing_example_paths(docs_dir: Path) -> list[Path]:
    """Every failing example of the catalogue (``RSxxx/fail.<ext>``, ``RSxxx/fail_*.<ext>``),
    in code and name order."""
    return sorted(
        path
        for path in examples_root(docs_dir).glob("RS*/*")
        if path.is_file() and (path.stem == FAILING or path.stem.startswith(MORE_FAILING))
    )


def _spec_named(files: list[Path], stem: str) -> Path | None:
    matches = [p for p in files if p.stem == stem]
    return matches[0] if matches else None


def run_example(path: Path) -> RunExample:
    """Compile ``path`` as ``robospec validate`` does and render its text report, naming files
    relative to the example's folder (as if run there), so pages read the same wherever they
    are generated.

    ManiSkill's download folder is pointed at a folder that does not exist meanwhile, so an
    example of a robot that is not downloaded reads the same on a machine that has it.
    """
    saved = os.environ.get(ASSET_DIR_VARIABLE)
    os.environ[ASSET_DIR_VARIABLE] = str(path.parent / NO_DOWNLOADS)
    try:
        # the full path, so the report can quote the source lines it points at
        result = compile_spec(path, display=str(path))
    finally:
        if saved is None:
            del os.environ[ASSET_DIR_VARIABLE]
        else:
            os.environ[ASSET_DIR_VARIABLE] = saved
    folders = (str(path.parent.resolve()) + os.sep, str(path.parent) + os.sep)
    report = _strip(render(result.diagnostics, 1, "text"), folders)
    diagnostics = tuple(_relative(d, folders) for d in result.diagnostics)
    return RunExample(path, diagnostics, report)


def _strip(text: str, folders: tuple[str, ...]) -> str:
    for folder in folders:
        text = text.replace(folder, "")
    return text


def _relative(diagnostic: Diagnostic, folders: tuple[str, ...]) -> Diagnostic:
    """Files named by their absolute path (or from the working folder) are named relative to
    the example's folder."""

    def strip(text: str) -> str:
        return _strip(text, folders)

    location = diagnostic.location
    return Diagnostic(
        location=Location(strip(location.file), location.line, location.column),
        code=diagnostic.code,
        severity=diagnostic.severity,
        message=strip(diagnostic.message),
        hint=strip(diagnostic.hint) if diagnostic.hint else None,
    )
