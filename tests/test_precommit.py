""".pre-commit-hooks.yaml: the manifest is valid for pre-commit and names real commands, and the
hooks work for real — pre-commit installs this repository (at HEAD: commit hook changes before
running this) into its own environment from PyPI, then guards `git commit` in a scratch
repository: a bad spec is rejected with its diagnostic, a good one passes, a stale generated
package fails robospec-build-check."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from importlib.metadata import entry_points
from pathlib import Path

import pytest
from conftest import ROOT, run_robospec
from pre_commit.clientlib import load_manifest

MANIFEST = ROOT / ".pre-commit-hooks.yaml"

ARM_URDF = """<robot name="arm">
  <link name="base"/>
  <link name="upper"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/>
    <child link="upper"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
</robot>
"""
GOOD_SPEC = """robospec: 1
uid: pc_good
description: {urdf: arm.urdf}
controllers:
  arm: {type: pd_joint_pos, joints: [shoulder], lower: -1, upper: 1, stiffness: 100, damping: 10}
control_modes:
  pd_joint_pos: {arm: arm}
"""
BAD_SPEC = GOOD_SPEC.replace("pc_good", "pc_bad").replace("[shoulder]", "[shouldr]")


def hooks() -> dict[str, dict]:
    return {hook["id"]: hook for hook in load_manifest(str(MANIFEST))}


def test_manifest_is_valid_for_pre_commit_and_offers_both_hooks() -> None:
    found = hooks()  # load_manifest raises on anything pre-commit would reject
    assert set(found) == {"robospec-validate", "robospec-build-check"}
    assert all(hook["language"] == "python" for hook in found.values())


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_hook_entries_are_real_commands_and_options() -> None:
    scripts = {script.name for script in entry_points(group="console_scripts")}
    for hook in hooks().values():
        program, command, *options = hook["entry"].split()
        assert program in scripts  # the console script pip installs into the hook's env
        help_text = run_robospec(command, "--help")
        assert help_text.returncode == 0, help_text.stderr
        for option in options:
            assert option in help_text.stdout


def test_validate_hook_selects_spec_files_only() -> None:
    hook = hooks()["robospec-validate"]
    assert hook["types_or"] == ["yaml", "toml"]
    assert hook["pass_filenames"] and hook["require_serial"]
    selected = re.compile(hook["files"])
    for spec in ["specs/maniskill/panda.yaml", "specs/twolink.toml", "robots/specs/a.yml"]:
        assert selected.search(spec), spec
    for other in [".github/workflows/ci.yml", "mkdocs.yml", "pyproject.toml", "myspecs/a.yaml"]:
        assert not selected.search(other), other


def test_build_check_hook_takes_its_paths_from_args() -> None:
    hook = hooks()["robospec-build-check"]
    assert hook["entry"] == "robospec build --check"
    assert hook["pass_filenames"] is False
    assert {"yaml", "toml", "xml", "python"} == set(hook["types_or"])


# -- for real: pre-commit guards git commit -----------------------------------------------------


def git(repo: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        ["git", "-c", "user.name=t", "-c", "user.email=t@example.org", *args],
        cwd=repo,
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.fixture(scope="session")
def pre_commit_home(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One pre-commit cache for the session: the hooks' environment is built once."""
    return tmp_path_factory.mktemp("pre-commit-home")


@pytest.fixture
def scratch_repo(tmp_path: Path, pre_commit_home: Path) -> Path:
    """A git repository whose .pre-commit-config.yaml uses both hooks from this repository."""
    head = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.strip()
    repo = tmp_path / "project"
    (repo / "specs").mkdir(parents=True)
    (repo / "specs/arm.urdf").write_text(ARM_URDF)
    (repo / "specs/good.yaml").write_text(GOOD_SPEC)
    (repo / ".pre-commit-config.yaml").write_text(
        "repos:\n"
        f"  - repo: {ROOT.as_uri()}\n"
        f"    rev: {head}\n"
        "    hooks:\n"
        "      - id: robospec-validate\n"
        "      - id: robospec-build-check\n"
        "        args: [specs/, -o, pkg]\n"
    )
    git(repo, "init", "-q")
    install = subprocess.run(
        [sys.executable, "-m", "pre_commit", "install"],
        cwd=repo,
        capture_output=True,
        text=True,
        env=hook_env(pre_commit_home),
    )
    assert install.returncode == 0, install.stdout + install.stderr
    return repo


def hook_env(pre_commit_home: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    env["PRE_COMMIT_HOME"] = str(pre_commit_home)
    env["PRE_COMMIT_COLOR"] = "never"
    return env


def commit(repo: Path, home: Path, message: str) -> subprocess.CompletedProcess[str]:
    """``git commit`` with the hooks installed; git hands the hooks' output to stderr, so the
    result's stdout is set to both streams."""
    git(repo, "add", "-A")
    result = subprocess.run(
        ["git", "-c", "user.name=t", "-c", "user.email=t@example.org", "commit", "-m", message],
        cwd=repo,
        capture_output=True,
        text=True,
        timeout=600,
        env=hook_env(home),
    )
    result.stdout += result.stderr
    return result


def commits(repo: Path) -> int:
    return int(git(repo, "rev-list", "--count", "HEAD").stdout.strip() or 0)


@pytest.mark.slow  # pre-commit builds its hook environment (a pip install) first
def test_validate_hook_rejects_a_commit_with_a_bad_spec(
    scratch_repo: Path, pre_commit_home: Path
) -> None:
    assert run_robospec("build", "specs/", "-o", "pkg", cwd=scratch_repo).returncode == 0
    good = commit(scratch_repo, pre_commit_home, "a good spec")
    assert good.returncode == 0, good.stdout + good.stderr
    assert re.search(r"robospec validate\.+Passed", good.stdout), good.stdout
    assert re.search(r"robospec build --check\.+Passed", good.stdout), good.stdout

    (scratch_repo / "specs/bad.yaml").write_text(BAD_SPEC)
    bad = commit(scratch_repo, pre_commit_home, "a bad spec")
    assert bad.returncode != 0
    assert re.search(r"robospec validate\.+Failed", bad.stdout), bad.stdout
    assert "specs/bad.yaml:5:38: error[RS201] unknown joint 'shouldr'" in bad.stdout
    assert "hint: did you mean 'shoulder'?" in bad.stdout
    assert commits(scratch_repo) == 1


@pytest.mark.slow  # pre-commit builds its hook environment (a pip install) first
def test_build_check_hook_rejects_a_commit_that_leaves_the_package_stale(
    scratch_repo: Path, pre_commit_home: Path
) -> None:
    assert run_robospec("build", "specs/", "-o", "pkg", cwd=scratch_repo).returncode == 0
    assert commit(scratch_repo, pre_commit_home, "first").returncode == 0

    spec = scratch_repo / "specs/good.yaml"
    spec.write_text(GOOD_SPEC.replace("stiffness: 100", "stiffness: 200"))
    stale = commit(scratch_repo, pre_commit_home, "stiffer, package not rebuilt")
    assert stale.returncode != 0
    assert re.search(r"robospec validate\.+Passed", stale.stdout), stale.stdout
    assert re.search(r"robospec build --check\.+Failed", stale.stdout), stale.stdout
    assert "pkg: stale" in stale.stdout

    assert run_robospec("build", "specs/", "-o", "pkg", cwd=scratch_repo).returncode == 0
    rebuilt = commit(scratch_repo, pre_commit_home, "stiffer, package rebuilt")
    assert rebuilt.returncode == 0, rebuilt.stdout + rebuilt.stderr
    assert commits(scratch_repo) == 2


@pytest.mark.slow  # pre-commit builds its hook environment (a pip install) first
def test_yaml_outside_specs_is_not_validated(scratch_repo: Path, pre_commit_home: Path) -> None:
    assert run_robospec("build", "specs/", "-o", "pkg", cwd=scratch_repo).returncode == 0
    assert commit(scratch_repo, pre_commit_home, "first").returncode == 0
    workflows = scratch_repo / ".github/workflows"
    workflows.mkdir(parents=True)
    (workflows / "ci.yml").write_text("on: push\njobs: {}\n")  # not a spec: RS103 if validated
    result = commit(scratch_repo, pre_commit_home, "a workflow")
    assert result.returncode == 0, result.stdout + result.stderr
    assert re.search(r"robospec validate\.+\(no files to check\)Skipped", result.stdout)
