"""`robospec build`: deterministic, atomic, never overwrites what it did not write, --check."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT, SAME_ON_EVERY_MANISKILL

from robospec.output.package import MANIFEST, MANIFEST_HEADER

pytestmark = pytest.mark.minutes  # CI starts it first (tests/conftest.py)

# a TOML spec with a xacro description (a module and an expanded URDF) and a YAML one: enough
# for what does not depend on how many specs a build has, at a third of the cost of specs/
TWO_SPECS = ("specs/twolink.toml", "specs/maniskill/panda.yaml")


def build(
    out: Path,
    *extra: str,
    specs: str | tuple[str, ...] = "specs/",
    env: dict[str, str] | None = None,
) -> subprocess.CompletedProcess[str]:
    paths = [specs] if isinstance(specs, str) else list(specs)
    return subprocess.run(
        [sys.executable, "-m", "robospec.cli", "build", *paths, "-o", str(out), *extra],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, **(env or {})},
    )


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_build_writes_one_module_per_spec_and_an_init_that_imports_them(tmp_path: Path) -> None:
    out = tmp_path / "agents"
    result = build(out)
    assert result.returncode == 0, result.stdout + result.stderr
    names = set(snapshot(out))
    assert {
        "__init__.py",
        "rs_panda.py",
        "rs_fetch.py",
        "rs_humanoid.py",
        "twolink.py",
        "twolink.urdf",
    } <= names
    init = (out / "__init__.py").read_text()
    assert "from .rs_panda import RsPanda" in init
    for name in names:
        if name.endswith(".py"):
            compile((out / name).read_text(), name, "exec")


@pytest.mark.slow
@SAME_ON_EVERY_MANISKILL
def test_build_output_is_byte_identical_across_runs_and_hash_seeds(tmp_path: Path) -> None:
    states = []
    for seed in ("0", "1", "4242"):  # 0: no hash randomization at all
        out = tmp_path / seed / "agents"
        result = build(out, env={"PYTHONHASHSEED": seed})
        assert result.returncode == 0, result.stdout + result.stderr
        states.append(snapshot(out))
    # YAML and TOML specs, and a xacro expansion, are part of what is compared
    assert {"rs_panda.py", "twolink.py", "twolink.urdf"} <= set(states[0])
    assert states[0] == states[1] == states[2]


@pytest.mark.slow
@pytest.mark.parametrize("specs", ["specs/", str(ROOT / "specs")], ids=["relative", "absolute"])
def test_generated_files_name_no_path_of_this_machine(tmp_path: Path, specs: str) -> None:
    out = tmp_path / "agents"
    assert build(out, specs=specs).returncode == 0
    for name, data in snapshot(out).items():
        assert str(ROOT).encode() not in data, name
        assert str(tmp_path).encode() not in data, name


@pytest.mark.slow
def test_build_output_is_the_same_for_absolute_and_relative_spec_paths(tmp_path: Path) -> None:
    relative, absolute = tmp_path / "a" / "agents", tmp_path / "b" / "agents"
    assert build(relative, specs="specs/twolink.toml").returncode == 0
    assert build(absolute, specs=str(ROOT / "specs/twolink.toml")).returncode == 0
    assert snapshot(relative) == snapshot(absolute)


@pytest.mark.parametrize(
    "name",
    [
        "rs_panda.py",
        "__init__.py",
        "twolink.urdf",
        "_robospec_manifest.txt",
    ],
)
def test_build_refuses_to_overwrite_a_file_it_did_not_generate(tmp_path: Path, name: str) -> None:
    # a user's file named like a module, the package's __init__, an expanded xacro, the manifest
    out = tmp_path / "agents"
    out.mkdir()
    mine = out / name
    mine.write_text("# my own work\n")
    result = build(out, specs=TWO_SPECS)
    assert result.returncode == 1
    assert f"{mine}:1:1: error[RS604] refusing to overwrite" in result.stdout
    assert mine.read_text() == "# my own work\n"
    assert sorted(p.name for p in out.iterdir()) == [name]  # nothing half-written


def test_a_manifest_robospec_did_not_write_names_nothing_as_robospecs(tmp_path: Path) -> None:
    # a file named like the manifest, listing the user's notes: build neither trusts it to
    # remove the notes as stale nor overwrites it
    out = tmp_path / "agents"
    out.mkdir()
    (out / "NOTES.txt").write_text("keep me\n")
    (out / MANIFEST).write_text("NOTES.txt\n")
    result = build(out, specs=TWO_SPECS)
    assert result.returncode == 1 and "RS604" in result.stdout
    assert (out / "NOTES.txt").read_text() == "keep me\n"
    assert (out / MANIFEST).read_text() == "NOTES.txt\n"


@pytest.mark.slow
def test_a_build_from_before_the_manifest_header_is_still_robospecs(tmp_path: Path) -> None:
    # a manifest without the header, beside the __init__.py robospec generated, is trusted
    out = tmp_path / "agents"
    assert build(out, specs=TWO_SPECS).returncode == 0
    manifest = out / MANIFEST
    manifest.write_text(manifest.read_text().removeprefix(MANIFEST_HEADER))
    (out / "rs_panda.py").write_text("stale\n")
    assert build(out, specs=TWO_SPECS).returncode == 0
    assert "class RsPanda" in (out / "rs_panda.py").read_text()
    assert manifest.read_text().startswith(MANIFEST_HEADER)


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_build_keeps_the_users_other_files_and_replaces_its_own(tmp_path: Path) -> None:
    out = tmp_path / "agents"
    assert build(out, specs=TWO_SPECS).returncode == 0
    (out / "NOTES.txt").write_text("keep me\n")
    (out / "rs_panda.py").write_text("stale\n")
    assert build(out, specs=TWO_SPECS).returncode == 0
    assert (out / "NOTES.txt").read_text() == "keep me\n"
    assert "class RsPanda" in (out / "rs_panda.py").read_text()


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_check_reports_stale_output_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "agents"
    assert build(out, "--check", specs=TWO_SPECS).returncode == 1
    assert not out.exists()
    assert build(out, specs=TWO_SPECS).returncode == 0
    assert build(out, "--check", specs=TWO_SPECS).returncode == 0
    (out / "rs_panda.py").write_text("edited\n")
    result = build(out, "--check", specs=TWO_SPECS)
    assert result.returncode == 1 and "rs_panda.py" in result.stdout
    assert (out / "rs_panda.py").read_text() == "edited\n"


def test_a_spec_with_errors_builds_nothing(tmp_path: Path) -> None:
    out = tmp_path / "agents"
    result = build(out, specs="docs/examples/codes/RS201/fail.yaml")
    assert result.returncode == 1
    assert not out.exists()


def test_an_invalid_package_name_is_a_diagnostic(tmp_path: Path) -> None:
    result = build(tmp_path / "not-a-package", specs=TWO_SPECS)
    assert result.returncode == 1
    assert "RS105" in result.stdout


@pytest.mark.maniskill
def test_importing_the_built_package_registers_the_agents(tmp_path: Path) -> None:
    pytest.importorskip("mani_skill")
    out = tmp_path / "built_agents"
    assert build(out).returncode == 0
    probe = (
        "import sys, mani_skill.envs\n"
        f"sys.path.insert(0, {str(tmp_path)!r})\n"
        "import built_agents\n"
        "from mani_skill.agents.registration import REGISTERED_AGENTS as R\n"
        "A = built_agents.AGENTS\n"
        "print(sorted(u for u in A if R[u].agent_cls is A[u]))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=300
    )
    # every spec under specs/, by the uid it says
    uids = [
        re.search(r'^uid\s*[:=]\s*"?([\w.-]+)', path.read_text(), re.MULTILINE).group(1)  # type: ignore[union-attr]
        for path in sorted((ROOT / "specs").rglob("*"))
        if path.suffix in (".yaml", ".toml")
    ]
    assert len(uids) > 20
    assert str(sorted(uids)) in result.stdout, result.stderr
