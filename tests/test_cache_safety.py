"""The import-time cache is rebuilt, never trusted, when an entry is broken or stale; and when
the cache cannot be written at all, `robospec.register` still works (a warning, not a crash).

Each test fills the cache with the real compiler, breaks the entry the way a crash, a full disk
or a stray hand would (or changes a file the entry was compiled from), then registers in this
process for the first time: the code that runs is the freshly compiled module, never what was
planted in the cache, and the entry is whole and fresh again.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from conftest import ROOT
from hypothesis import given
from hypothesis import strategies as st

import robospec
from robospec.output.modules import module_name_for
from robospec.output.register import _compile_entries, _entry_for, _entry_is_fresh, cache_salt

CANARY_CODE = "import pathlib\npathlib.Path({path!r}).write_text('the cache was trusted')\n"


@pytest.fixture
def spec(tmp_path: Path) -> Path:
    """A small spec under a uid of its own, so each test registers a new agent."""
    path = tmp_path / "specs" / "arm.yaml"
    path.parent.mkdir()
    text = (ROOT / "tests/specs/positive/minimal.yaml").read_text()
    path.write_text(text.replace("uid: rs_test", f"uid: rs_cache_{uuid.uuid4().hex[:12]}"))
    return path


def fill(spec: Path, cache: Path) -> Path:
    """Compile ``spec`` into ``cache`` as a cold `register` would; return its entry."""
    entry = _entry_for(spec, cache, cache_salt())
    _compile_entries([(spec, entry)], [spec], False)
    assert _entry_is_fresh(entry)
    return entry


def register_fresh(spec: Path, cache: Path) -> type:
    pytest.importorskip("mani_skill")
    from mani_skill.agents.registration import REGISTERED_AGENTS

    ((uid, cls),) = robospec.register(spec, cache_dir=cache).items()
    assert REGISTERED_AGENTS[uid].agent_cls is cls
    assert cls.uid == uid and cls.__name__.startswith("RsCache")
    return cls


def loaded_from(cls: type) -> Path:
    """The module file the class was executed from."""
    return Path(sys.modules[cls.__module__].__file__ or "")


def module_of(entry: Path) -> Path:
    manifest = json.loads((entry / "manifest.json").read_text())
    return entry / manifest["module_file"]


def plant_canary(module: Path, canary: Path) -> None:
    module.write_text(CANARY_CODE.format(path=str(canary)))


@pytest.mark.maniskill
@pytest.mark.parametrize(
    "damage",
    ["truncated", "garbage bytes", "valid python, wrong content", "code appended", "empty"],
)
def test_a_damaged_module_in_the_cache_is_rebuilt_not_run(
    spec: Path, tmp_path: Path, damage: str
) -> None:
    cache, canary = tmp_path / "cache", tmp_path / "CANARY"
    entry = fill(spec, cache)
    module = module_of(entry)
    good = module.read_bytes()
    if damage == "truncated":
        module.write_bytes(good[: len(good) // 2])
    elif damage == "garbage bytes":
        module.write_bytes(bytes(range(256)) * 8)
    elif damage == "empty":
        module.write_bytes(b"")
    elif damage == "code appended":  # the generated agent, and then some: still not trusted
        module.write_bytes(good + CANARY_CODE.format(path=str(canary)).encode())
    else:
        plant_canary(module, canary)
    assert not _entry_is_fresh(entry)
    cls = register_fresh(spec, cache)
    assert not canary.exists()
    assert module.read_bytes() == good and _entry_is_fresh(entry)
    assert loaded_from(cls) == module  # the class comes from the rebuilt module


@pytest.mark.maniskill
@pytest.mark.parametrize(
    "manifest_text",
    ["", "{not json", "[]", '{"deps": 3}', "\x00\x01\x02", '{"module_file": null}'],
    ids=["empty", "truncated", "a list", "wrong types", "binary", "no module"],
)
def test_a_damaged_manifest_is_rebuilt(spec: Path, tmp_path: Path, manifest_text: str) -> None:
    cache = tmp_path / "cache"
    entry = fill(spec, cache)
    module = module_of(entry)
    good = module.read_bytes()
    (entry / "manifest.json").write_text(manifest_text)
    assert not _entry_is_fresh(entry)
    cls = register_fresh(spec, cache)
    assert _entry_is_fresh(entry) and module_of(entry) == module
    assert module.read_bytes() == good and loaded_from(cls) == module


@pytest.mark.maniskill
def test_a_manifest_naming_a_module_outside_its_entry_is_not_trusted(
    spec: Path, tmp_path: Path
) -> None:
    # the hash matches, but the file is not the entry's own: never load code from elsewhere
    cache, canary = tmp_path / "cache", tmp_path / "CANARY"
    entry = fill(spec, cache)
    outside = tmp_path / "planted.py"
    plant_canary(outside, canary)
    manifest = json.loads((entry / "manifest.json").read_text())
    digest = __import__("hashlib").sha256(outside.read_bytes()).hexdigest()
    for name in (os.path.relpath(outside, entry), str(outside)):
        manifest.update(module_file=name, module_sha256=digest)
        (entry / "manifest.json").write_text(json.dumps(manifest))
        assert not _entry_is_fresh(entry), name
    # a link inside the entry pointing at it is refused too
    link = entry / "linked.py"
    link.symlink_to(outside)
    manifest.update(module_file="linked.py")
    (entry / "manifest.json").write_text(json.dumps(manifest))
    assert not _entry_is_fresh(entry)
    cls = register_fresh(spec, cache)
    assert not canary.exists()
    assert _entry_is_fresh(entry) and loaded_from(cls) == module_of(entry)
    assert not os.path.lexists(link)  # the rebuilt entry holds its own module only


@pytest.mark.maniskill
@pytest.mark.parametrize(
    "replacement", ["entry is a file", "module is a folder", "manifest is a folder"]
)
def test_an_entry_replaced_by_something_else_is_rebuilt(
    spec: Path, tmp_path: Path, replacement: str
) -> None:
    import shutil

    cache = tmp_path / "cache"
    entry = fill(spec, cache)
    if replacement == "entry is a file":
        shutil.rmtree(entry)
        entry.write_text("not a folder\n")
    else:
        target = (
            module_of(entry) if replacement == "module is a folder" else entry / "manifest.json"
        )
        target.unlink()
        target.mkdir()
        (target / "inside").write_text("x\n")
    assert not _entry_is_fresh(entry)
    cls = register_fresh(spec, cache)
    assert entry.is_dir() and _entry_is_fresh(entry)
    assert loaded_from(cls) == module_of(entry)
    assert [p.name for p in cache.iterdir() if p.name != entry.name] == []  # nothing left over


@pytest.mark.maniskill
def test_changing_a_file_the_entry_was_compiled_from_rebuilds_it(tmp_path: Path) -> None:
    # twolink: a TOML spec whose xacro description is expanded into the entry
    robot = tmp_path / "robot"
    shutil.copytree(ROOT / "specs/robots/twolink", robot)
    spec = tmp_path / "twolink.toml"
    text = (ROOT / "specs/twolink.toml").read_text()
    spec.write_text(
        text.replace('"robots/twolink/', '"robot/')
        .replace('uid = "twolink"', f'uid = "rs_cache_{uuid.uuid4().hex[:12]}"')
        .replace('class_name = "TwoLink"', "")
    )
    cache = tmp_path / "cache"
    entry = fill(spec, cache)
    expanded = entry / (module_of(entry).stem + ".urdf")
    assert '<mass value="0.3"/>' in expanded.read_text()  # the hand's
    xacro = robot / "twolink.urdf.xacro"
    xacro.write_text(xacro.read_text().replace('hand" mass="0.3"', 'hand" mass="0.45"'))
    assert not _entry_is_fresh(entry)
    cls = register_fresh(spec, cache)
    assert _entry_is_fresh(entry) and loaded_from(cls) == module_of(entry)  # recompiled ...
    assert '<mass value="0.45"/>' in expanded.read_text()  # ... from the edited xacro
    assert '<mass value="0.3"/>' not in expanded.read_text()


@pytest.mark.maniskill
@pytest.mark.parametrize("blocker", ["cache is a file", "a parent of the cache is a file"])
def test_a_cache_that_cannot_be_written_warns_and_registers_anyway(
    spec: Path, tmp_path: Path, blocker: str
) -> None:
    blocking_file = tmp_path / "blocking"
    blocking_file.write_text("a file where a folder should be\n")
    cache = blocking_file if blocker == "cache is a file" else blocking_file / "cache"
    with pytest.warns(RuntimeWarning, match="cannot write the cache entry"):
        cls = register_fresh(spec, cache)
    assert blocking_file.read_text() == "a file where a folder should be\n"
    # the module was compiled into a temporary folder that lives as long as this process
    assert Path(sys.modules[cls.__module__].__file__ or "").is_file()


@pytest.mark.maniskill
@pytest.mark.skipif(
    not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root may write anywhere"
)
def test_a_read_only_cache_folder_warns_and_registers_anyway(spec: Path, tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    cache.mkdir()
    cache.chmod(0o500)
    try:
        with pytest.warns(RuntimeWarning, match="cannot write the cache entry"):
            register_fresh(spec, cache)
    finally:
        cache.chmod(0o700)


@pytest.mark.maniskill
def test_two_processes_filling_one_cold_entry_at_once_both_register(
    spec: Path, tmp_path: Path
) -> None:
    pytest.importorskip("mani_skill")
    cache = tmp_path / "cache"
    probe = (
        "import mani_skill.envs, robospec\n"
        f"print(sorted(robospec.register({str(spec)!r}, cache_dir={str(cache)!r})))\n"
    )
    processes = [
        subprocess.Popen(
            [sys.executable, "-c", probe],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(2)
    ]
    results = [p.communicate(timeout=300) for p in processes]
    assert [p.returncode for p in processes] == [0, 0], [err[-2000:] for _, err in results]
    assert all("rs_cache_" in out for out, _ in results)
    (entry,) = [p for p in cache.iterdir()]
    assert _entry_is_fresh(entry)


@given(st.text(max_size=40))
def test_the_module_name_of_any_uid_is_a_plain_identifier(uid: str) -> None:
    name = module_name_for(uid, set())
    assert name.isidentifier()
    assert "/" not in name and "\\" not in name and "." not in name


@pytest.mark.parametrize("uid", ["a..b", "x-..-y", "a.b.c", "0..", "rs-..-..-etc"])
def test_a_uid_with_dots_and_dashes_cannot_steer_cache_paths(tmp_path: Path, uid: str) -> None:
    spec = tmp_path / "specs" / "arm.yaml"
    spec.parent.mkdir()
    text = (ROOT / "tests/specs/positive/minimal.yaml").read_text()
    spec.write_text(text.replace("uid: rs_test", f"uid: {uid}"))
    cache = tmp_path / "cache"
    entry = fill(spec, cache)
    everything = [p.resolve() for p in tmp_path.rglob("*")]
    outside = [p for p in everything if not p.is_relative_to(cache.resolve())]
    assert outside == [p.resolve() for p in (spec.parent, spec)]
    assert uid not in entry.name  # named by a hash, not by what the spec says
    assert module_of(entry).parent == entry
