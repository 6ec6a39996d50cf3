"""`robospec build`: a package of generated agent modules, written all at once or not at all.

Output is deterministic (specs in sorted order, no timestamps). A file robospec did not generate
is never overwritten: every file we write is listed in ``MANIFEST``, and only files listed there
by an earlier build may be replaced or removed. Anything in the folder that is not a regular file
(a symbolic link, a folder) is never ours: a link is never followed, replaced or removed.

How a build is written, so that nothing is lost:

- **One build at a time.** The whole compare-and-write step holds an advisory ``fcntl.flock`` on
  the output folder's parent directory (no lock file is left behind). A second concurrent
  ``robospec build`` of the same folder waits, then compares against the first one's result.
- **The manifest says what is ours.** It starts with :data:`MANIFEST_HEADER`; a file of that
  name without it (the user's, or a manifest robospec never wrote) is not trusted and not
  overwritten. (A manifest from before the header is trusted when the folder's ``__init__.py``
  is one robospec generated.)
- **Staged, then renamed.** The new files are written to a staging folder beside the output
  (``.<name>.robospec-*``), then put in place by renames, never by writing into the output:
  - no output folder yet: one ``rename(staging, out)``;
  - the folder holds only our files: the two folders are swapped in one atomic
    ``renameat2(RENAME_EXCHANGE)`` (Linux); elsewhere by two renames, the old folder first
    moved aside to ``.<name>.robospec-*.old``;
  - the folder also holds the user's files: ours are replaced one rename at a time. The
    manifest is written first listing the old files and the new, and again at the end listing
    the new: a kill midway leaves each file whole, old or new, and every one of them listed as
    ours, so the next build finishes the job.
- **Recovery.** Before comparing, a build (under the lock) puts back an old folder left aside by
  a killed two-rename swap when the output is missing, and removes leftover staging folders.
  So a build killed at any point leaves the previous output, or the new one, complete.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import CANNOT_WRITE, INVALID_IDENTIFIER, WOULD_OVERWRITE
from robospec.emit.package import GENERATED_MARKER, HEADLESS_MODULE, headless_module_source
from robospec.output.atomic import exchange
from robospec.output.modules import checked_robot_files, module_name_for, package_init
from robospec.pipeline import CompiledSpec

MANIFEST = "_robospec_manifest.txt"
MANIFEST_HEADER = "# robospec build: the files it wrote here, which it may replace or remove\n"


@dataclass
class BuildResult:
    diagnostics: list[Diagnostic] = field(default_factory=list)
    files: dict[str, str | bytes] = field(default_factory=dict)
    changed: list[str] = field(default_factory=list)


def plan_package(compiled: list[CompiledSpec], out_dir: Path) -> dict[str, str | bytes]:
    """The package's files ``{name: text}`` (specs that cannot be emitted are left out)."""
    return _plan(compiled, out_dir)[0]


def _plan(
    compiled: list[CompiledSpec], out_dir: Path
) -> tuple[dict[str, str | bytes], list[Diagnostic]]:
    """The package's files, and an RS105 diagnostic for each spec that cannot be emitted."""
    out_dir = out_dir.resolve()
    taken: set[str] = set()
    files: dict[str, str | bytes] = {}
    problems: list[Diagnostic] = []
    modules: list[tuple[str, str, str]] = []
    for item in sorted(compiled, key=lambda c: c.display):
        assert item.robot is not None
        module = module_name_for(item.robot.uid, taken)
        robot_files = checked_robot_files(
            item.robot, module, out_dir, item.display, self_contained=True
        )
        if isinstance(robot_files, Diagnostic):
            problems.append(robot_files)
            continue
        clash = sorted(set(robot_files) & set(files))
        if clash:  # a copied mesh named like another robot's module: never one over another
            problems.append(
                error(
                    Location(item.display),
                    INVALID_IDENTIFIER,
                    f"'{clash[0]}' would be written twice into the package",
                    "build this spec into another package",
                )
            )
            continue
        files.update(robot_files)
        modules.append((module, item.robot.uid, item.robot.class_name))
    files["__init__.py"] = package_init(modules)
    files[f"{HEADLESS_MODULE}.py"] = headless_module_source()
    files[MANIFEST] = manifest_text(files)
    return files, problems


def manifest_text(names: Iterable[str]) -> str:
    return MANIFEST_HEADER + "".join(f"{name}\n" for name in sorted(set(names) - {MANIFEST}))


def _previous_manifest(out_dir: Path) -> set[str]:
    """The files an earlier build wrote here, by its manifest; none if robospec did not write
    the manifest."""
    try:
        text = (out_dir / MANIFEST).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return set()
    if not text.startswith(MANIFEST_HEADER) and not _generated_init(out_dir):
        return set()
    names = text.removeprefix(MANIFEST_HEADER).splitlines()
    return {n for n in names if n and "/" not in n and n != ".." and not n.startswith("#")}


def _generated_init(out_dir: Path) -> bool:
    """Whether the folder's ``__init__.py`` is one robospec generated (a manifest of the
    robospec before the manifest's header lives beside one)."""
    init = out_dir / "__init__.py"
    try:
        head = init.read_text(encoding="utf-8")[:200] if not init.is_symlink() else ""
    except (OSError, UnicodeDecodeError):
        return False
    return head.startswith('"""ManiSkill agents ' + GENERATED_MARKER)


def _is_ours(path: Path, previous: set[str]) -> bool:
    """A file an earlier build wrote: listed in its manifest, and still a plain file."""
    return path.name in previous and path.is_file() and not path.is_symlink()


def build_package(compiled: list[CompiledSpec], out_dir: Path, *, check: bool) -> BuildResult:
    result = BuildResult()
    if not out_dir.name.isidentifier():
        result.diagnostics.append(
            error(
                Location(str(out_dir)),
                INVALID_IDENTIFIER,
                f"'{out_dir.name}' is not a valid Python package name",
            )
        )
        return result
    files, problems = _plan(compiled, out_dir)
    if problems:
        result.diagnostics.extend(problems)
        return result
    result.files = files
    # a link to the output folder is kept: we build into the folder it names
    target = Path(os.path.realpath(out_dir))
    if check:
        _compare(target, files, result)
        return result
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        with _locked(target.parent):
            _recover(target)
            stale = _compare(target, files, result)
            if not result.diagnostics and result.changed:
                _write_atomically(target, files, stale)
    except OSError as exc:  # a file in the way, no permission, a full disk: nothing is lost
        reason = exc.strerror or str(exc)
        result.diagnostics.append(
            error(Location(str(out_dir)), CANNOT_WRITE, f"cannot write {out_dir}: {reason}")
        )
    return result


def _compare(out_dir: Path, files: dict[str, str | bytes], result: BuildResult) -> list[str]:
    """Fill ``result`` with refusals and changed names; return our stale files to remove."""
    previous = _previous_manifest(out_dir)
    existing = {p.name: p for p in out_dir.iterdir()} if out_dir.is_dir() else {}
    for name in sorted(files):
        current = out_dir / name
        # the manifest is ours when robospec wrote it (previous is then not empty)
        ours = _is_ours(current, previous) or (name == MANIFEST and bool(previous))
        if name in existing and not ours:
            result.diagnostics.append(
                error(
                    Location(str(current)),
                    WOULD_OVERWRITE,
                    "refusing to overwrite a file robospec did not generate",
                    "move it away or pick another -o folder",
                )
            )
        elif not _same_bytes(current, files[name]):
            result.changed.append(name)
    stale = sorted(n for n in existing if n not in files and _is_ours(existing[n], previous))
    result.changed.extend(stale)
    return stale


def _same_bytes(path: Path, content: str | bytes) -> bool:
    try:
        return path.is_file() and path.read_bytes() == _bytes(content)
    except OSError:
        return False


@contextlib.contextmanager
def _locked(folder: Path) -> Iterator[None]:
    """Hold an exclusive advisory lock on ``folder`` (a directory can be flock'ed directly)."""
    try:
        import fcntl
    except ImportError:  # not POSIX: builds are atomic per rename, but not serialized
        yield
        return
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # closing releases the lock


def _staging_prefix(out_dir: Path) -> str:
    return f".{out_dir.name}.robospec-"


def _recover(out_dir: Path) -> None:
    """Undo what a killed build left beside ``out_dir`` (we hold the lock: nobody is writing)."""
    prefix = _staging_prefix(out_dir)
    leftovers = sorted(out_dir.parent.glob(prefix + "*"))
    if not out_dir.exists() and not out_dir.is_symlink():
        aside = [p for p in leftovers if p.name.endswith(".old") and p.is_dir()]
        if aside:
            os.replace(aside[-1], out_dir)  # killed between the two renames: put it back
            leftovers.remove(aside[-1])
    for path in leftovers:
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)


def _write_atomically(out_dir: Path, files: dict[str, str | bytes], stale: list[str]) -> None:
    staging = Path(tempfile.mkdtemp(prefix=_staging_prefix(out_dir), dir=out_dir.parent))
    try:
        for name in sorted(files):
            _write_synced(staging / name, files[name])
        if not out_dir.exists():
            os.replace(staging, out_dir)  # one rename: all the files appear at once
            return
        ours = set(files) | set(stale) | {MANIFEST, "__pycache__"}
        if {p.name for p in out_dir.iterdir()} <= ours:
            _swap(staging, out_dir)  # only our files are there: a reader sees old or new
            return
        # the folder holds the user's files too: replace ours one by one, with a manifest that
        # lists the old and the new first (a kill midway leaves nothing unlisted), then the new
        both = staging / (MANIFEST + ".both")
        _write_synced(both, manifest_text([*files, *stale]))
        os.replace(both, out_dir / MANIFEST)
        for name in sorted(files, key=lambda n: n == MANIFEST):
            os.replace(staging / name, out_dir / name)
        for name in stale:
            (out_dir / name).unlink(missing_ok=True)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _bytes(content: str | bytes) -> bytes:
    """A file's bytes: text as UTF-8 (robospec writes \\n line ends), copies as they are."""
    return content if isinstance(content, bytes) else content.encode("utf-8")


def _write_synced(path: Path, content: str | bytes) -> None:
    with open(path, "wb") as handle:
        handle.write(_bytes(content))
        handle.flush()
        os.fsync(handle.fileno())  # the rename must not publish empty files on a crash


def _swap(staging: Path, out_dir: Path) -> None:
    """Put ``staging`` at ``out_dir``; the old folder ends at ``staging``'s path, then goes."""
    if not exchange(staging, out_dir):
        aside = staging.with_name(staging.name + ".old")
        os.replace(out_dir, aside)  # a kill here is undone by _recover
        os.replace(staging, out_dir)
        staging = aside
    shutil.rmtree(staging, ignore_errors=True)
