"""`robospec.register(paths)`: compile specs and register their agents at import time.

A warm start must cost little next to ``import mani_skill.envs``: each spec's compiled module
is cached under a key made of the spec's bytes, and is trusted only while every file it was
compiled from still has the same hash. The warm path reads bytes and hashes them; it imports
neither pydantic nor ruamel nor lxml.
"""

from __future__ import annotations

import atexit
import hashlib
import importlib.util
import json
import os
import shutil
import sys
import tempfile
import warnings
from collections.abc import Iterable
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic, Location, SpecError, error
from robospec.diagnostics.codes import DUPLICATE_UID, INTERNAL_ERROR
from robospec.files import cache_root
from robospec.maniskill.builtin_uids import Overrides, override_allowed
from robospec.output.load_errors import guard

if TYPE_CHECKING:
    from robospec.pipeline import CompiledSpec

CACHE_FORMAT = "1"


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _file_hash(path: str) -> str | None:
    try:
        return _sha256(Path(path).read_bytes())
    except OSError:
        return None


def cache_salt() -> str:
    """What else a cache entry depends on: the cache layout, robospec's version, and which
    ManiSkill is installed (its distribution, version and files: the nightly's
    ``__version__`` says 3.0.1 too)."""
    from importlib.metadata import PackageNotFoundError, version

    from robospec.maniskill.installed import installed

    try:
        robospec_version = version("robospec")
    except PackageNotFoundError:
        robospec_version = "unknown"
    maniskill = installed()
    return "/".join((CACHE_FORMAT, robospec_version, maniskill.identity if maniskill else "none"))


def register(
    paths: str | os.PathLike[str] | Iterable[str | os.PathLike[str]],
    *,
    cache_dir: str | os.PathLike[str] | None = None,
    override: bool | Iterable[str] = False,
) -> dict[str, type]:
    """Compile the specs (files or folders) and register their agents with ManiSkill.

    Returns ``{uid: agent class}``. Raises :class:`robospec.SpecError` carrying every
    diagnostic when any spec has errors; then nothing is registered.

    A uid that is already registered (by ManiSkill or anyone else) is an error, unless the
    spec says ``override: true`` or ``override`` here is True or names that uid: then the
    spec's agent replaces the registered one, e.g. so ManiSkill's tasks, which choose start
    poses by uid, run with a spec-built ``panda``.
    """
    overrides: Overrides = override if isinstance(override, bool) else frozenset(override)
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    root = Path(cache_dir) if cache_dir is not None else cache_root()
    from robospec.load.discovery import discover

    files, problems = discover([Path(p) for p in paths])
    if problems:  # a missing path, a folder without specs: never "registered nothing" quietly
        raise SpecError(problems)
    salt = cache_salt()
    entries: list[tuple[Path, Path]] = []
    cold: list[tuple[Path, Path]] = []
    for file in files:
        entry = _entry_for(file, root, salt)
        entries.append((file, entry))
        if not _entry_is_fresh(entry):
            cold.append((file, entry))
    if cold:
        placed = _compile_entries(cold, [f for f, _ in entries], overrides)
        entries = [(file, placed.get(file, entry)) for file, entry in entries]
    return _load_entries(entries, overrides)


def _entry_for(file: Path, root: Path, salt: str) -> Path:
    """The cache entry of a spec: named by a hash of robospec's version, the spec's path and
    its bytes, never by anything the spec says (its uid cannot steer where files go)."""
    from robospec.load.reader import read_spec_file_bytes

    # as validate reads it: a FIFO is refused (reading it would block), a huge file by its size
    data, problem = read_spec_file_bytes(file, str(file))
    if data is None:
        raise SpecError([problem] if problem else [])
    key = _sha256(salt.encode() + b"\0" + str(file.resolve()).encode() + b"\0" + data)
    return root / key[:40]


def _entry_is_fresh(entry: Path) -> bool:
    try:
        manifest = json.loads((entry / "manifest.json").read_text(encoding="utf-8"))
        deps = manifest["deps"]
        module_file = _module_file(entry, manifest)
        if module_file is None or _file_hash(str(module_file)) != manifest["module_sha256"]:
            return False  # a corrupted or edited entry is rebuilt, never trusted
        return all(_file_hash(path) == digest for path, digest in deps)
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return False


def _module_file(entry: Path, manifest: dict[str, object]) -> Path | None:
    """The entry's module, named by the manifest: a plain file name inside the entry only."""
    name = manifest.get("module_file")
    if not isinstance(name, str) or not name.endswith(".py") or name != os.path.basename(name):
        return None
    if name.startswith(".") or os.sep in name or (os.altsep and os.altsep in name):
        return None
    path = entry / name
    return path if path.is_file() and not path.is_symlink() else None


def _compile_entries(
    cold: list[tuple[Path, Path]], all_files: list[Path], overrides: Overrides
) -> dict[Path, Path]:
    """Compile the cold specs into their cache entries; returns ``{spec: entry}`` for each,
    which is a temporary folder instead when the cache cannot be written."""
    from robospec.diagnostics import has_errors
    from robospec.pipeline import compile_all

    compiled, diagnostics = compile_all(all_files, overrides=overrides)
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    if has_errors(diagnostics):
        raise SpecError([d for d in diagnostics if d.is_error])
    by_path = {item.path: item for item in compiled}
    placed: dict[Path, Path] = {}
    for file, entry in cold:
        item = by_path[file]
        try:
            _store(item, file, entry)
            placed[file] = entry
        except OSError as exc:
            fallback = _fallback_root() / entry.name
            warnings.warn(
                f"robospec: cannot write the cache entry {entry} ({exc}); "
                f"compiled into {fallback} for this process instead",
                RuntimeWarning,
                stacklevel=3,
            )
            _store(item, file, fallback)
            placed[file] = fallback
    return placed


def _store(item: CompiledSpec, file: Path, entry: Path) -> None:
    """Write the entry in a staging folder beside it, then rename it into place."""
    from robospec.output.modules import checked_robot_files, module_name_for

    assert item.robot is not None
    module = module_name_for(item.robot.uid, set())
    # files name each other relative to the folder they live in: emit for this entry's folder
    files = checked_robot_files(item.robot, module, entry, item.display)
    if isinstance(files, Diagnostic):
        raise SpecError([files])
    entry.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".tmp-", dir=entry.parent))
    try:
        for name, content in files.items():
            if isinstance(content, bytes):
                (staging / name).write_bytes(content)
            else:
                (staging / name).write_text(content, encoding="utf-8")
        deps = [str(file.resolve()), *_dependencies(item.robot)]
        manifest = {
            "uid": item.robot.uid,
            "class_name": item.robot.class_name,
            "override": item.robot.override,
            "module_file": f"{module}.py",
            "module_sha256": _sha256(str(files[f"{module}.py"]).encode()),
            "deps": [[path, _file_hash(path)] for path in deps],
        }
        (staging / "manifest.json").write_text(json.dumps(manifest, indent=1))
        _install(staging, entry)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _install(staging: Path, entry: Path) -> None:
    """Rename ``staging`` to ``entry``, replacing a stale or broken entry (a folder, a file or a
    link); an entry another process has just written for the same key is kept."""
    try:
        os.replace(staging, entry)  # atomic while the entry is absent (or an empty folder)
        return
    except OSError:
        if _entry_is_fresh(entry):
            return  # a concurrent register() wrote the same key: same content
    from robospec.output.atomic import exchange

    if exchange(staging, entry):  # one step: a reader sees the old entry or the new one
        _remove(staging)  # now the old entry
        return
    # elsewhere: move the old entry aside in one rename, then put the new one in its place
    aside = Path(tempfile.mkdtemp(prefix=".old-", dir=entry.parent)) / "entry"
    try:
        os.replace(entry, aside)
    except FileNotFoundError:
        pass
    try:
        os.replace(staging, entry)
    finally:
        shutil.rmtree(aside.parent, ignore_errors=True)


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


_FALLBACK: list[Path] = []


def _fallback_root() -> Path:
    """A private temporary cache for this process, removed at exit: generated modules name
    their files relative to themselves, so the folder must outlive registration."""
    if not _FALLBACK:
        root = Path(tempfile.mkdtemp(prefix="robospec-cache-"))
        atexit.register(shutil.rmtree, root, ignore_errors=True)
        _FALLBACK.append(root)
    return _FALLBACK[0]


def _dependencies(robot: object) -> list[str]:
    from robospec.resolve.resolved import FileRef, ResolvedRobot

    assert isinstance(robot, ResolvedRobot)
    refs = [robot.description] + [
        value for c in robot.controllers for _, value in c.kwargs if isinstance(value, FileRef)
    ]
    deps: list[str] = []
    for source in robot.description.sources:  # a composed robot's parts: specs, descriptions
        deps.append(source)
        if source.endswith(".xacro"):  # and what a part's xacro may include
            deps.extend(_xacro_neighbours(Path(source).parent))
    for ref in refs:
        deps.append(str(ref.absolute))
        if ref.derived:
            # files robospec wrote for the derived copy (mirrored meshes) live in the cache:
            # one gone makes the entry stale, and compiling again writes it back
            derived = cache_root() / "derived"
            deps.extend(p for _uri, p in ref.mesh_paths if Path(p).is_relative_to(derived))
        if ref.derived and ref.absolute.suffix.lower() == ".xml":
            # a derived MJCF holds its includes written in place: a change there recompiles
            deps.extend(str(p) for p in sorted(ref.absolute.parent.glob("*.xml")) if p.is_file())
        if ref.generated_text is not None and not ref.has_srdf_beside:
            # a xacro file may include its neighbours: any change there recompiles
            deps.extend(_xacro_neighbours(ref.absolute.parent))
    if robot.description_kind == "urdf" and robot.description.has_srdf_beside:
        from robospec.description.srdf import srdf_path

        srdf = srdf_path(str(robot.description.absolute))
        if os.path.isfile(srdf):  # SAPIEN's collision bits, which never_collide packs around
            deps.append(srdf)
    return sorted(set(deps), key=deps.index)


def _xacro_neighbours(folder: Path) -> list[str]:
    return [
        str(p) for p in sorted(folder.rglob("*")) if p.is_file() and p.suffix in (".xacro", ".urdf")
    ]


def _load_entries(entries: list[tuple[Path, Path]], overrides: Overrides) -> dict[str, type]:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    from robospec.maniskill import render_fallback

    # gym.make(..., render_backend="none") must load these robots, and the task's scene, on a
    # machine without a rendering device too: there, visuals are left out (nothing changes
    # where SAPIEN finds a device). A built package's __init__ does the same.
    render_fallback.install()

    loaded: dict[str, type] = {}
    for file, entry in entries:
        manifest = json.loads((entry / "manifest.json").read_text(encoding="utf-8"))
        uid = manifest["uid"]
        module_name = f"robospec_agents.{entry.name}"
        existing = REGISTERED_AGENTS.get(uid)
        if existing is not None:
            if getattr(existing.agent_cls, "__module__", None) == module_name:
                loaded[uid] = existing.agent_cls  # the same spec, registered before
                continue
            if _REGISTERED_FROM.get(uid) == file.resolve():
                # this very file, edited since register() loaded it in this process (a
                # notebook, a reload): its new agent replaces its old one
                del REGISTERED_AGENTS[uid]
            elif override_allowed(uid, bool(manifest.get("override")), overrides):
                del REGISTERED_AGENTS[uid]  # replaced on purpose: the module registers ours
            else:
                raise SpecError(
                    [
                        error(
                            Location(str(file)),
                            DUPLICATE_UID,
                            f"uid '{uid}' is already registered by "
                            f"{existing.agent_cls.__module__}."
                            f"{existing.agent_cls.__name__}",
                            "set `override: true` in the spec (or register(..., override=...)) "
                            "to replace it on purpose",
                        )
                    ]
                )
        module_file = _module_file(entry, manifest)
        if module_file is None:  # checked fresh a moment ago: someone broke it since
            raise SpecError(
                [
                    error(
                        Location(str(entry)),
                        INTERNAL_ERROR,
                        "the cache entry changed while loading",
                    )
                ]
            )
        module = _exec_module(module_name, module_file)
        loaded[uid] = getattr(module, manifest["class_name"])
        # what ManiSkill's loaders raise when an environment loads it: a located SpecError
        guard(loaded[uid], file)
        _REGISTERED_FROM[uid] = file.resolve()
    return loaded


# uid -> the spec file register() registered it from, in this process
_REGISTERED_FROM: dict[str, Path] = {}


def _exec_module(name: str, path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


def sim_config_for(uid: str) -> dict[str, object]:
    """The sim config the spec of registered robot ``uid`` recommends (its ``simulation``
    section), for ``gym.make(..., sim_config=...)``: ManiSkill merges it over the task's own.
    Empty for a robot whose spec recommends none, or a robot robospec did not compile."""
    import copy

    from mani_skill.agents.registration import REGISTERED_AGENTS

    if uid not in REGISTERED_AGENTS:
        raise KeyError(f"no agent is registered under uid {uid!r}")
    agent = REGISTERED_AGENTS[uid].agent_cls
    return copy.deepcopy(getattr(agent, "recommended_sim_config", {}))
