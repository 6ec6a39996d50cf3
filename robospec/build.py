"""`robospec build`: a package of generated agent modules, written all at once or not at all.

Output is deterministic (specs in sorted order, no timestamps). A file robospec did not
generate is never overwritten: every file we write is listed in ``MANIFEST``, and only
files listed there by an earlier build may be replaced or removed.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from robospec.compile import CompiledSpec
from robospec.diagnostics import Diagnostic, Location, error
from robospec.output import checked_robot_files, module_name_for, package_init

MANIFEST = "_robospec_manifest.txt"


@dataclass
class BuildResult:
    diagnostics: list[Diagnostic] = field(default_factory=list)
    files: dict[str, str] = field(default_factory=dict)
    changed: list[str] = field(default_factory=list)


def plan_package(compiled: list[CompiledSpec], out_dir: Path) -> dict[str, str]:
    """The package's files ``{name: text}`` (specs that cannot be emitted are left out)."""
    return _plan(compiled, out_dir)[0]


def _plan(compiled: list[CompiledSpec], out_dir: Path) -> tuple[dict[str, str], list[Diagnostic]]:
    """The package's files, and an RS105 diagnostic for each spec that cannot be emitted."""
    out_dir = out_dir.resolve()
    taken: set[str] = set()
    files: dict[str, str] = {}
    problems: list[Diagnostic] = []
    modules: list[tuple[str, str, str]] = []
    for item in sorted(compiled, key=lambda c: c.display):
        assert item.robot is not None
        module = module_name_for(item.robot.uid, taken)
        robot_files, problem = checked_robot_files(item.robot, module, out_dir, item.display)
        if problem is not None or robot_files is None:
            problems.extend([problem] if problem is not None else [])
            continue
        files.update(robot_files)
        modules.append((module, item.robot.uid, item.robot.class_name))
    files["__init__.py"] = package_init(modules)
    files[MANIFEST] = "".join(f"{name}\n" for name in sorted(files))
    return files, problems


def _previous_manifest(out_dir: Path) -> set[str]:
    try:
        text = (out_dir / MANIFEST).read_text(encoding="utf-8")
    except OSError:
        return set()
    return {line for line in text.splitlines() if line and "/" not in line and line != ".."}


def build_package(compiled: list[CompiledSpec], out_dir: Path, *, check: bool) -> BuildResult:
    result = BuildResult()
    if not out_dir.name.isidentifier():
        result.diagnostics.append(
            error(
                Location(str(out_dir)),
                "RS105",
                f"'{out_dir.name}' is not a valid Python package name",
            )
        )
        return result
    files, problems = _plan(compiled, out_dir)
    if problems:
        result.diagnostics.extend(problems)
        return result
    result.files = files
    previous = _previous_manifest(out_dir)
    existing = {p.name for p in out_dir.iterdir()} if out_dir.is_dir() else set()
    for name in sorted(files):
        current = out_dir / name
        if name in existing and name not in previous and name != MANIFEST:
            result.diagnostics.append(
                error(
                    Location(str(current)),
                    "RS001",
                    "refusing to overwrite a file robospec did not generate",
                    "move it away or pick another -o folder",
                )
            )
        elif not current.is_file() or current.read_text(encoding="utf-8") != files[name]:
            result.changed.append(name)
    stale = sorted((previous & existing) - set(files))
    result.changed.extend(stale)
    if result.diagnostics or check or not result.changed:
        return result
    _write_atomically(out_dir, files, stale, existing)
    return result


def _write_atomically(
    out_dir: Path, files: dict[str, str], stale: list[str], existing: set[str]
) -> None:
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
    try:
        for name, text in files.items():
            (staging / name).write_text(text, encoding="utf-8", newline="\n")
        ours = set(files) | set(stale) | {MANIFEST, "__pycache__"}
        if not out_dir.exists():
            os.replace(staging, out_dir)  # one rename: all the files appear at once
            return
        if existing <= ours:
            # only our files are there: swap the folders, so a reader sees old or new
            backup = staging.with_name(staging.name + ".old")
            os.replace(out_dir, backup)
            os.replace(staging, out_dir)
            shutil.rmtree(backup, ignore_errors=True)
            return
        # the folder holds the user's files too: replace ours one by one, manifest last
        for name in sorted(files, key=lambda n: n == MANIFEST):
            os.replace(staging / name, out_dir / name)
        for name in stale:
            (out_dir / name).unlink(missing_ok=True)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
