"""Facts from the installed ManiSkill, not from a list written for one version: the uids it
registers itself (read from its source), which distribution and version it is (the nightly's
``__version__`` says 3.0.1 too), the register cache's salt that follows from it, and what its
scenes give every robot."""

from __future__ import annotations

from pathlib import Path

import pytest

from robospec.maniskill import installed as facts
from robospec.maniskill.installed import installed, installed_at, scan_registered_uids
from robospec.output import register as register_module


def _package(site: Path, files: dict[str, str]) -> Path:
    package = site / "mani_skill"
    for name, text in {"__init__.py": "", **files}.items():
        (package / name).parent.mkdir(parents=True, exist_ok=True)
        (package / name).write_text(text)
    return package


def _dist_info(site: Path, name: str, record: str = "mani_skill/__init__.py,,\n") -> Path:
    info = site / f"{name}.dist-info"
    info.mkdir(parents=True)
    (info / "RECORD").write_text(record)
    return info


AGENTS = {
    "envs/__init__.py": "from mani_skill.agents import robots\n",
    "agents/__init__.py": "",
    "agents/robots/__init__.py": "from .arm import *\n# from .hidden import Hidden\n",
    "agents/robots/arm.py": (
        "from mani_skill.agents.registration import register_agent\n"
        "@register_agent()\nclass Arm:\n    uid = 'arm'\n"
        "@register_agent(asset_download_ids=['x'])\n"
        "class ArmWristcam(Arm):\n    uid: str = 'arm_cam'\n"
        "@register_agent()\nclass Same(Arm):\n    pass\n"
    ),
    # registers a uid, but nothing imports it: ManiSkill never registers it
    "agents/robots/hidden.py": "@register_agent()\nclass Hidden:\n    uid = 'hidden'\n",
}


def test_the_uids_are_those_of_the_modules_maniskill_imports(tmp_path: Path) -> None:
    package = _package(tmp_path, AGENTS)
    assert scan_registered_uids(package) == {"arm", "arm_cam"}


def test_the_nightly_is_told_apart_by_its_distribution(tmp_path: Path) -> None:
    package = _package(tmp_path, {})
    _dist_info(tmp_path, "mani_skill_nightly-2026.8.2.400")
    found = installed_at(package)
    assert found is not None
    assert (found.distribution, found.version, found.mixed) == (
        "mani-skill-nightly",
        "2026.8.2.400",
        (),
    )
    assert found.is_nightly and "mani-skill-nightly==2026.8.2.400#" in found.identity


def test_two_installs_of_one_version_have_different_identities(tmp_path: Path) -> None:
    one, other = tmp_path / "one", tmp_path / "other"
    _dist_info(one, "mani_skill-3.0.1", "mani_skill/__init__.py,sha256=a,1\n")
    _dist_info(other, "mani_skill-3.0.1", "mani_skill/__init__.py,sha256=b,1\n")
    first, second = installed_at(_package(one, {})), installed_at(_package(other, {}))
    assert first is not None and second is not None
    assert first.version == second.version == "3.0.1"
    assert first.identity != second.identity


def test_both_distributions_installed_is_mixed_and_the_last_installed_counts(
    tmp_path: Path,
) -> None:
    import os

    package = _package(tmp_path, {})
    nightly = _dist_info(tmp_path, "mani_skill_nightly-2026.8.2.400")
    stable = _dist_info(tmp_path, "mani_skill-3.0.1")
    os.utime(nightly / "RECORD", (1, 1))  # 3.0.1 was installed over the nightly
    found = installed_at(package)
    assert found is not None
    assert found.distribution == "mani-skill" and found.version == "3.0.1"
    assert found.mixed == ("mani-skill", "mani-skill-nightly")
    os.utime(stable / "RECORD", (0, 0))
    assert installed_at(package).distribution == "mani-skill-nightly"  # type: ignore[union-attr]


def test_the_cache_salt_follows_the_installed_maniskill(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    package = _package(tmp_path / "a", {})
    _dist_info(tmp_path / "a", "mani_skill-3.0.1")
    nightly_package = _package(tmp_path / "b", {})
    _dist_info(tmp_path / "b", "mani_skill_nightly-2026.8.2.400")
    salts = []
    for found in (installed_at(package), installed_at(nightly_package), None):
        monkeypatch.setattr(facts, "installed", lambda found=found: found)
        salts.append(register_module.cache_salt())
    assert len(set(salts)) == 3
    assert salts[2].endswith("/none")


def test_a_uid_the_installed_maniskill_does_not_register_is_free(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from robospec.pipeline import compile_spec

    spec = tmp_path / "spec.yaml"
    spec.write_text(
        "robospec: 1\nuid: stompy\ndescription: {urdf: arm.urdf}\n"
        "controllers: {arm: {type: pd_joint_pos, joints: '*', lower: null, upper: null,"
        " stiffness: 1, damping: 1}}\n"
        "control_modes: {pd_joint_pos: {arm: arm}}\n"
    )
    (tmp_path / "arm.urdf").write_text(
        '<robot name="a"><link name="base"/><link name="l1"/>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )

    def codes() -> list[str]:
        return [d.code for d in compile_spec(spec).diagnostics if d.is_error]

    # ManiSkill 3.0.1 registers stompy; the nightly removed it
    monkeypatch.setattr(facts, "registered_uids", lambda: facts.UIDS_OF_3_0_1)
    monkeypatch.setattr("robospec.pipeline.registered_uids", lambda: facts.UIDS_OF_3_0_1)
    assert codes() == ["RS306"]
    without = facts.UIDS_OF_3_0_1 - {"stompy"}
    monkeypatch.setattr("robospec.pipeline.registered_uids", lambda: without)
    assert codes() == []


@pytest.mark.usefixtures("maniskill")
def test_the_scan_equals_the_registry_of_the_installed_maniskill() -> None:
    import mani_skill.envs  # noqa: F401  (imports every agent module)
    from mani_skill.agents.registration import REGISTERED_AGENTS

    own = {
        uid
        for uid, entry in REGISTERED_AGENTS.items()
        if entry.agent_cls.__module__.startswith("mani_skill.")
    }
    found = installed()
    assert found is not None
    assert scan_registered_uids(found.package_dir) == own == facts.registered_uids()
    if (found.distribution, found.version) == ("mani-skill", "3.0.1"):
        assert own == facts.UIDS_OF_3_0_1  # the stand-in without ManiSkill


@pytest.mark.usefixtures("maniskill")
def test_the_scene_facts_are_the_installed_maniskills() -> None:
    from mani_skill.agents.robots.fetch.fetch import (
        FETCH_BASE_COLLISION_BIT,
        FETCH_WHEELS_COLLISION_BIT,
    )
    from mani_skill.utils.structs.types import SceneConfig

    from robospec.maniskill.scenes import CONTACT_OFFSET, GROUND_BITS

    assert GROUND_BITS == (FETCH_WHEELS_COLLISION_BIT, FETCH_BASE_COLLISION_BIT)
    assert CONTACT_OFFSET == SceneConfig().contact_offset


def test_both_distributions_installed_is_a_warning_of_check(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from robospec.maniskill.installed import mixed_install_problem
    from robospec.physics.command import run_check

    package = _package(tmp_path, {})
    _dist_info(tmp_path, "mani_skill_nightly-2026.8.2.400")
    assert mixed_install_problem(installed_at(package)) is None  # one distribution: nothing
    _dist_info(tmp_path, "mani_skill-3.0.1")
    found = installed_at(package)
    problem = mixed_install_problem(found)
    assert problem is not None and problem.code == "RS520" and not problem.is_error
    assert "mani-skill and mani-skill-nightly" in problem.message
    assert problem.location.file == str(package)

    monkeypatch.setattr(facts, "installed", lambda: found)
    spec = tmp_path / "broken.yaml"
    spec.write_text("robospec: 1\n")
    code, output = run_check([spec], None, "text", gpu=False, num_envs=1, render_dir=None)
    assert code == 1  # the spec's own errors
    assert "warning[RS520]" in output and "error[RS103]" in output


@pytest.mark.usefixtures("maniskill")
def test_the_task_scan_finds_every_registered_task_and_what_it_calls() -> None:
    from mani_skill.utils.registration import REGISTERED_ENVS

    from robospec.maniskill.tasks import TASKS_OF_3_0_1, installed_tasks, scan_tasks

    found = installed()
    assert found is not None
    scan = scan_tasks(found.package_dir)
    own = {k: v for k, v in REGISTERED_ENVS.items() if v.cls.__module__.startswith("mani_skill.")}
    # every task a register_env decorator registers; the only others are the scene-builder
    # variants scenes/__init__.py registers in a loop (exploration scenes, no task)
    assert set(scan.tasks) <= set(own)
    assert {own[k].cls.__name__ for k in set(own) - set(scan.tasks)} <= {"SceneManipulationEnv"}
    assert installed_tasks().tasks == scan.tasks  # the cached scan is the scan
    # what PickCube-v1 reads off its agent: BaseAgent leaves is_grasping and is_static
    # unimplemented and has no tcp at all
    assert scan.needed("PickCube-v1") == ("is_grasping", "is_static", "tcp_pose")
    assert "tabletop" in scan.families and "PickCube-v1" in scan.family("tabletop")
    if (found.distribution, found.version) == ("mani-skill", "3.0.1"):
        # the stand-in without ManiSkill
        assert {k: (t.family, scan.needed(k)) for k, t in scan.tasks.items()} == TASKS_OF_3_0_1
