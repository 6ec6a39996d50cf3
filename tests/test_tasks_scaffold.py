"""Robots in ManiSkill's tasks: the gripper arms ``robospec new`` scaffolds from the corpus run
PickCube-v1, PushCube-v1 and StackCube-v1 headless as written (tcp, grasping and is_static are
scaffolded); the tutorial's robot runs PickCube-v1 exactly as the tutorial shows; ``robospec
check --task`` reports what a task needs and the robot lacks, with its mend, and bad ``--task``
input as located errors."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import DOCS, PANDA_SPEC, ROOT, fast_first, maniskill_assets, run_robospec
from corpus import BY_KEY, CorpusMissing, locate

from robospec.authoring.commands import run_new

pytestmark = [pytest.mark.maniskill, pytest.mark.minutes]

TASKS = ("PickCube-v1", "PushCube-v1", "StackCube-v1")
# the corpus arms with a gripper new recognises: two fingers on one link, a mimic pair (with the
# tcp link the description names, and with a tcp new places between the fingers), a jaw; one
# arm per scaffold (rtb_px100 left: new scaffolds it exactly as rtb_wx250s, its Interbotix
# sibling, with the same groups, tcp and fingers)
GRIPPER_ARMS = ("rtb_wx250s", "pb_panda", "rtb_panda", "erd_so101")
STEPS = 50


def _scaffold(key: str, folder: Path) -> Path:
    try:
        description = locate(BY_KEY[key])
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    out = folder / f"{key}.yaml"
    # the analytic gains: the tasks need the members, not the refined gains
    result = run_new(description, out, f"task_{key}", force=True, simulate=False).write()
    assert not result.failed, result.diagnostics
    return out


@pytest.mark.parametrize("key", fast_first(GRIPPER_ARMS))
def test_scaffolded_gripper_arms_run_pick_push_and_stack_headless(
    key: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import gymnasium as gym
    import torch

    import robospec

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold(key, tmp_path)
    text = spec.read_text()
    assert "\ntcp:" in text and "\ngrasping:" in text and "\nis_static:" in text
    robospec.register(spec)
    for task in TASKS:
        env = gym.make(
            task,
            robot_uids=f"task_{key}",
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
        )
        try:
            env.reset(seed=0)
            env.action_space.seed(0)
            for _ in range(STEPS):
                obs, *_ = env.step(torch.as_tensor(env.action_space.sample()))
                qpos = env.unwrapped.agent.robot.get_qpos().numpy()
                assert np.isfinite(qpos).all(), (task, qpos)
                assert torch.isfinite(obs).all(), task
        finally:
            env.close()


def test_the_tutorials_robot_runs_pickcube_headless_as_the_tutorial_shows(tmp_path: Path) -> None:
    page = (DOCS / "tutorial.md").read_text(encoding="utf-8")
    (snippet,) = [
        block
        for block in re.findall(r"```python\n(.*?)```", page, re.S)
        if 'gym.make(\n    "PickCube-v1"' in block
    ]
    env = {**os.environ, "ROBOSPEC_CACHE_DIR": str(tmp_path / "cache")}
    done = subprocess.run(
        [sys.executable, "-c", snippet], cwd=ROOT, capture_output=True, text=True, env=env
    )
    assert done.returncode == 0, done.stderr[-3000:]


def test_check_task_says_what_the_task_calls_and_the_spec_lacks(tmp_path: Path) -> None:
    spec = tmp_path / "panda.yaml"
    text = PANDA_SPEC.read_text().replace("{maniskill_assets}", str(maniskill_assets()))
    # without its grasp check, PickCube-v1 fails at reset upstream: check says why, with the
    # mend, at the uid (line 4)
    text = re.sub(r"\ngrasping:\n(  .*\n)+", "\n", text).replace("uid: rs_panda", "uid: no_grasp")
    spec.write_text(text)
    done = run_robospec(
        "check",
        str(spec),
        "--task",
        "PickCube-v1",
        "--task",
        "PushCube-v1",
        "--steps",
        "1",
        env={**os.environ, "ROBOSPEC_CACHE_DIR": str(tmp_path / "cache"), "NO_COLOR": "1"},
        timeout=600,
    )
    assert done.returncode == 1
    (line,) = [ln for ln in done.stdout.splitlines() if "error[RS528]" in ln]
    assert line.startswith(f"{spec}:4:1: error[RS528] PickCube-v1 calls agent.is_grasping: add")
    assert "`grasping:" in line
    assert re.search(r"task +- +PushCube-v1 +pass", done.stdout)


def test_bad_task_input_is_a_located_error(tmp_path: Path) -> None:
    env = {**os.environ, "ROBOSPEC_CACHE_DIR": str(tmp_path / "cache"), "NO_COLOR": "1"}
    args = ("check", str(PANDA_SPEC), "--task", "PickCub-v1")
    done = run_robospec(*args, env=env)
    assert done.returncode == 1
    column = len("robospec check ") + len(str(PANDA_SPEC)) + len(" --task ") + 1
    assert f"<command line>:1:{column}: error[RS524] --task PickCub-v1" in done.stdout
    assert "did you mean 'PickCube-v1'?" in done.stdout
    assert "Traceback" not in done.stdout + done.stderr
    # a task that needs two robots, and one whose objects this robot cannot reach from where the
    # task loads it (the SO-101 arm is 0.57 m long; PickCube-v1's cube lies 0.62 m away)
    spec = _scaffold("erd_so101", tmp_path)
    done = run_robospec(
        "check",
        str(spec),
        "--task",
        "TwoRobotPickCube-v1",
        "--task",
        "PickCube-v1",
        "--steps",
        "1",
        env=env,
        timeout=600,
    )
    assert done.returncode == 1
    assert re.search(
        r"<command line>:1:\d+: error\[RS525\] --task TwoRobotPickCube-v1: it needs "
        r"several robots",
        done.stdout,
    )
    assert re.search(
        r"<command line>:1:\d+: error\[RS526\] --task PickCube-v1: its nearest "
        r"object, 'cube', lies 0\.6\d m",
        done.stdout,
    )


@pytest.mark.slow  # a sweep over the folder's 21 tasks (about 35 s)
def test_check_task_tabletop_runs_or_explains_every_task_of_the_folder(tmp_path: Path) -> None:
    from robospec.maniskill.tasks import installed_tasks

    spec = tmp_path / "panda.yaml"
    text = PANDA_SPEC.read_text().replace("{maniskill_assets}", str(maniskill_assets()))
    spec.write_text(text.replace("uid: rs_panda", "uid: tabletop_panda"))
    env = {**os.environ, "ROBOSPEC_CACHE_DIR": str(tmp_path / "cache"), "NO_COLOR": "1"}
    done = run_robospec(
        "check", str(spec), "--task", "tabletop", "--steps", "1", env=env, timeout=600
    )
    assert "Traceback" not in done.stdout + done.stderr
    rows = dict(re.findall(r"^  task +- +(\S+) +(pass|skip|FAIL) ", done.stdout, re.M))
    # every task of the folder was run and reported, each once
    assert sorted(rows) == sorted(installed_tasks().family("tabletop")), done.stdout
    assert {"PickCube-v1", "PushCube-v1", "StackCube-v1"} <= {
        t for t, r in rows.items() if r == "pass"
    }
    for task, result in rows.items():
        if result == "skip":
            # a task that cannot run here says why: it needs several robots, a download, a
            # robot of its own or a renderer — never a crash counted against the robot
            (line,) = re.findall(rf"^  task +- +{re.escape(task)} +skip +(.*)$", done.stdout, re.M)
            assert line.startswith("not run: it "), line
    # the Panda runs every task it can: nothing is blamed on it (a task's own needs are skips)
    assert "FAIL" not in rows.values() and "error[RS527]" not in done.stdout, done.stdout
    assert done.returncode == 0, done.stdout


# a two-joint chain whose `tcp` is a hook that raises (tests/hookmods/crash_hooks.py): the spec
# has every member PushCube-v1 calls, and the task crashes inside ManiSkill's reset calling it
CRASHING_SPEC = """robospec: 1
uid: rs_test_task_crash
description:
  urdf: chain.urdf
hooks:
  methods: {tcp: "hookmods.crash_hooks:lost_tcp"}
groups:
  arm: [j1, j2]
keyframes:
  rest: {qpos: {arm: 0.0}}
controllers:
  arm_pos: {type: pd_joint_pos, joints: arm, lower: null, upper: null, stiffness: 1000.0,
            damping: 100.0, force_limit: 100, normalize_action: false}
control_modes:
  pd_joint_pos: {arm: arm_pos}
"""


def test_a_task_that_crashes_with_the_robot_is_rs527_at_the_uid_naming_the_raising_frame(
    tmp_path: Path,
) -> None:
    shutil.copy(ROOT / "tests" / "data" / "check" / "chain.urdf", tmp_path / "chain.urdf")
    spec = tmp_path / "crash.yaml"
    spec.write_text(CRASHING_SPEC, encoding="utf-8")
    env = {
        **os.environ,
        "ROBOSPEC_CACHE_DIR": str(tmp_path / "cache"),
        "NO_COLOR": "1",
        "PYTHONPATH": os.pathsep.join([str(ROOT / "tests"), os.environ.get("PYTHONPATH", "")]),
    }
    done = run_robospec(
        "check", str(spec), "--task", "PushCube-v1", "--steps", "1", env=env, timeout=600
    )
    assert done.returncode == 1, done.stdout
    assert "Traceback" not in done.stdout + done.stderr
    (line,) = [ln for ln in done.stdout.splitlines() if "error[RS527]" in ln]
    # located at the uid (line 2), with what raised and where: the spec's own hook, not upstream
    assert line.startswith(f"{spec}:2:1: error[RS527] PushCube-v1 crashed at "), line
    assert "_TcpLost: this robot's tcp link was never found" in line
    assert "hookmods/crash_hooks.py:" in line and "the spec's own code (a hook)" in line
    assert re.search(r"task +- +PushCube-v1 +FAIL +crashed at ", done.stdout)
    assert "error[RS528]" not in done.stdout  # the member exists: it is not a missing one


def test_new_reads_each_fingers_opening_from_its_joint_and_grips_by_its_rating(
    tmp_path: Path,
) -> None:
    """panda_v2.urdf rests closed (both fingers at 0): the fingers' centres coincide and say
    nothing, while the joints open the left finger along its +y and the right along its -y
    (ManiSkill's Panda's own is_grasping)."""
    out = tmp_path / "panda.yaml"
    urdf = maniskill_assets() / "robots" / "panda" / "panda_v2.urdf"
    result = run_new(urdf, out, "new_panda", force=True, simulate=False).write()
    assert not result.failed, result.diagnostics
    text = out.read_text()
    assert "{link: panda_leftfinger, opening: +y}" in text
    assert "{link: panda_rightfinger, opening: -y}" in text
    # the gripper squeezes with its 100 N rating across its 4 cm stroke
    # (robospec.authoring.new.grip)
    assert "stiffness: 2500,\n     damping: 250, force_limit: 100" in text
