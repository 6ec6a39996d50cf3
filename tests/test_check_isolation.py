"""`robospec check` checks each robot in isolation: a robot that ManiSkill cannot load, or that
kills the process, is a located diagnostic, and every other robot's results are still reported;
and every measurement starts from a freshly built scene, so no result depends on which checks
ran before it.

The robots (tests/data/check/isolation/, in the order they are checked): a chain that passes, a
robot whose <mimic> of a fixed joint makes ManiSkill raise while it builds the articulation
(tendon.urdf), a robot whose hook aborts the process as a native crash would, the chain again,
and a robot one of whose modes ManiSkill cannot make. `robospec check` runs them in its worker
processes, as users run them.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
from pathlib import Path
from typing import Any

import pytest
from conftest import MANISKILL_SPECS, ROOT, run_robospec

from robospec.physics.findings import Status
from robospec.physics.results import Options

pytestmark = pytest.mark.maniskill

DATA = ROOT / "tests" / "data" / "check"
ROBOTS = DATA / "isolation"


@pytest.fixture(scope="module")
def checked(tmp_path_factory: pytest.TempPathFactory) -> subprocess.CompletedProcess[str]:
    """``robospec check`` of the four robots, in a shell as a user runs it (the hook module is
    found on PYTHONPATH)."""
    env = {
        **os.environ,
        "ROBOSPEC_CACHE_DIR": str(tmp_path_factory.mktemp("cache")),
        "PYTHONPATH": os.pathsep.join([str(ROOT / "tests"), os.environ.get("PYTHONPATH", "")]),
    }
    return run_robospec(
        "check", str(ROBOTS), "--steps", "5", "--format", "json", env=env, timeout=600
    )


@pytest.fixture(scope="module")
def robots(checked: subprocess.CompletedProcess[str]) -> dict[str, dict[str, Any]]:
    report = json.loads(checked.stdout)
    return {Path(robot["spec"]).stem: robot for robot in report["robots"]}


def _line_of(path: Path, text: str) -> int:
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def _errors(robot: dict[str, Any]) -> list[dict[str, Any]]:
    return [d for d in robot["diagnostics"] if d["severity"] == "error"]


def test_check_exits_one_with_no_traceback_and_nothing_of_sapien_on_stderr(
    checked: subprocess.CompletedProcess[str],
) -> None:
    assert checked.returncode == 1
    assert "Traceback" not in checked.stdout + checked.stderr
    assert "[SAPIEN]" not in checked.stderr and "Fatal Python error" not in checked.stderr


def test_robots_before_and_after_the_crashes_are_checked_in_full(
    robots: dict[str, dict[str, Any]],
) -> None:
    assert list(robots) == ["a_chain", "b_tendon", "c_abort", "d_chain", "e_other_urdf"]
    for name in ("a_chain", "d_chain"):
        robot = robots[name]
        assert robot["status"] == "pass", robot["diagnostics"]
        checks = {f["check"] for f in robot["findings"]}
        assert {"keyframe_hold", "step_response", "random_actions", "action_layout"} <= checks


def test_a_robot_maniskill_cannot_load_is_rs514_at_the_element_with_upstreams_file_and_line(
    robots: dict[str, dict[str, Any]],
) -> None:
    robot = robots["b_tendon"]
    assert robot["status"] == "error"  # not checked: it cannot be loaded
    (diagnostic,) = _errors(robot)
    assert diagnostic["code"] == "RS514"
    # at the joint whose <mimic> ManiSkill turned into the tendon PhysX refused
    assert diagnostic["file"].endswith("tendon.urdf")
    assert diagnostic["line"] == _line_of(DATA / "tendon.urdf", '<joint name="j2"')
    message = diagnostic["message"]
    assert "failed to create tendon" in message and '<joint name="j2">' in message
    assert re.search(r"in ManiSkill's mani_skill/\S+\.py:\d+ ", message), message
    assert "upstream's code, not robospec's" in message


def test_a_robot_that_kills_the_process_is_rs515_saying_what_the_check_was_doing(
    robots: dict[str, dict[str, Any]],
) -> None:
    (diagnostic,) = _errors(robots["c_abort"])
    assert diagnostic["code"] == "RS515"
    spec = ROBOTS / "c_abort.yaml"
    assert (diagnostic["file"], diagnostic["line"]) == (
        str(spec),
        _line_of(spec, "description:"),
    )
    message = diagnostic["message"]
    assert "SIGABRT" in message
    assert "while loading the robot in mode pd_joint_pos" in message
    # the last Python frame before the crash: the hook, called while ManiSkill builds the agent
    assert "crash_hooks.py" in message
    assert "every other robot was still checked" in diagnostic["hint"]


def test_a_mode_maniskill_cannot_make_is_rs516_at_the_mode_and_the_other_modes_are_checked(
    robots: dict[str, dict[str, Any]],
) -> None:
    robot = robots["e_other_urdf"]
    (diagnostic,) = _errors(robot)
    assert diagnostic["code"] == "RS516"
    spec = ROBOTS / "e_other_urdf.yaml"
    assert (diagnostic["file"], diagnostic["line"]) == (
        str(spec),
        _line_of(spec, "  pd_ee_delta_pos:"),
    )
    message = diagnostic["message"]
    assert message.startswith("control mode 'pd_ee_delta_pos' cannot be made: ")
    assert re.search(r"in ManiSkill's mani_skill/agents/controllers/\S+\.py:\d+ ", message)
    assert "upstream's code, not robospec's" in message
    checked = {(f["check"], f["mode"]) for f in robot["findings"] if f["status"] != "fail"}
    assert ("random_actions", "pd_joint_pos") in checked
    assert not any(mode == "pd_ee_delta_pos" for check, mode in checked if check != "load")


def test_what_sapien_and_maniskill_print_is_told_once_per_message(
    robots: dict[str, dict[str, Any]],
) -> None:
    for robot in robots.values():
        texts = [(m["source"], m["level"], m["text"]) for m in robot["messages"]]
        assert len(texts) == len(set(texts))
        assert all(m["count"] >= 1 for m in robot["messages"])


# -- every measurement from the same state -----------------------------------------------------


def test_random_actions_measure_the_same_alone_and_after_a_keyframe_hold(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # PhysX keeps the last step's contact pairs across a teleport: on the Ability hand, random
    # actions "from load" reached 531 rad/s alone and 370 after a keyframe hold in the same
    # environment. Each measurement now starts in a freshly built scene.
    from robospec.output.register import register
    from robospec.physics import keyframe_hold, random_actions
    from robospec.physics.batch import _settings
    from robospec.physics.check_run import CheckRun
    from robospec.pipeline import compile_spec

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path))
    spec = MANISKILL_SPECS / "floating_ability_hand_right.yaml"
    item = compile_spec(spec)
    assert item.robot is not None and item.context is not None
    register(spec)

    def measured(*checks: object) -> list[tuple[object, ...]]:
        run = CheckRun(item.robot.uid, item.context, _settings(item, Options(steps=20)))
        try:
            findings = [f for check in checks for f in check.check(run)]  # type: ignore[attr-defined]
        finally:
            run.close()
        return [
            (f.mode, f.subject, f.status, repr(dict(f.metrics)))
            for f in findings
            if f.check == random_actions.NAME
        ]

    alone = measured(random_actions)
    after_hold = measured(keyframe_hold, random_actions)
    assert alone == after_hold
    assert [status for _, _, status, _ in alone] and all(
        status in (Status.PASS, Status.FAIL) for _, _, status, _ in alone
    )
