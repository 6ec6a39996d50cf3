"""The examples behind the per-code pages: data kept next to the docs, run through the compiler.

Each diagnostic code has a folder ``docs/examples/codes/RSxxx/`` holding

- ``fail.<ext>``: a spec that makes robospec report exactly that code,
- ``pass.<ext>``: the same spec fixed, which robospec accepts without that code,
- any files the two need (a robot description, a xacro file), shown on the page too,
- optionally ``about.md``: prose for the page (why the rule exists, how to fix it).

Codes that user input cannot trigger through ``robospec validate`` (RS4xx come from
``robospec import`` of Python classes, RS5xx from ``robospec check``'s physics, RS9xx are
internal) are *documented*: their folder holds only ``about.md`` (or a check module's docstring
documents them), and the page says the example is not run when the docs are generated.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from robospec.compile import compile_spec
from robospec.diagnostics import Diagnostic

EXAMPLES_FOLDER = Path("examples") / "codes"
ABOUT_FILE = "about.md"
FAILING = "fail"
PASSING = "pass"

# ranges whose examples are documented rather than run at docs-generation time
DOCUMENTED_PREFIXES = ("RS4", "RS5", "RS9")


def is_documented_only(code: str) -> bool:
    return code.startswith(DOCUMENTED_PREFIXES)


@dataclass(frozen=True)
class RunExample:
    """One example spec and what robospec reports for it."""

    path: Path
    diagnostics: tuple[Diagnostic, ...]

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
    support = tuple(p for p in files if p not in (failing, passing, about_path))
    return CodeExamples(
        code=code,
        folder=folder,
        about=about,
        failing=run_example(failing) if failing else None,
        passing=run_example(passing) if passing else None,
        support_files=support,
    )


def _spec_named(files: list[Path], stem: str) -> Path | None:
    matches = [p for p in files if p.stem == stem]
    return matches[0] if matches else None


def run_example(path: Path) -> RunExample:
    """Compile ``path`` as ``robospec validate`` does, naming files relative to its folder."""
    result = compile_spec(path, display=path.name)
    folder = str(path.parent.resolve()) + os.sep
    return RunExample(path, tuple(_relative(d, folder) for d in result.diagnostics))


def _relative(diagnostic: Diagnostic, folder: str) -> Diagnostic:
    """Messages that name a file with its absolute path name it relative to the example's
    folder, so the pages are the same on every machine."""
    return Diagnostic(
        location=diagnostic.location,
        code=diagnostic.code,
        severity=diagnostic.severity,
        message=diagnostic.message.replace(folder, ""),
        hint=diagnostic.hint.replace(folder, "") if diagnostic.hint else None,
    )
