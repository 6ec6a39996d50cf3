"""Arms as ``robospec new`` scaffolds them pick the cube with ManiSkill's own solution
(``robospec solve``), or ``solve`` says why not before any episode: new writes the start pose the
solution needs (a ``ready`` keyframe, fingers pointing down, that every episode resets to) and
recognises camel-case gripper joints; solve grasps where the fingers close whatever the tcp
link, holds a mode's controllers beyond the arm and the gripper, and refuses fingers that have
nothing to touch with.

A few seeds each (an episode costs about two seconds): docs/robots.md's PickCube-v1 column is the
corpus's measurement of every arm with a gripper.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from corpus import BY_KEY, CorpusMissing, locate

from robospec.authoring.commands import run_new

pytestmark = [
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]


def _description(key: str) -> Path:
    try:
        return locate(BY_KEY[key])
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)


def _scaffold(key: str, folder: Path, uid: str) -> Path:
    """The spec as ``robospec new`` writes it, without the probe's search in ManiSkill (the
    members and keyframes are what these tests need, not the refined gains)."""
    out = folder / f"{key}.yaml"
    result = run_new(_description(key), out, uid, force=True, simulate=False).write()
    assert not result.failed, result.diagnostics
    return out


@pytest.mark.slow
def test_new_reads_a_camel_case_gripper_joint_as_a_gripper() -> None:
    """Unitree Z1's ``jointGripper``: a lower-case letter then a capital starts a word, so it
    is the gripper, not the arm's seventh joint (new wrote no grasp check for the Z1 before)."""
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.new.analysis import analyse

    source, problems = read_description_file(_description("erd_z1"))
    assert source is not None, problems
    groups = analyse(source).groups
    assert "jointGripper" not in groups.groups["arm"]
    (gripper,) = [name for name, kind in groups.kinds.items() if kind == "gripper"]
    assert groups.groups[gripper] == ["jointGripper"]


@pytest.mark.slow
@pytest.mark.maniskill
def test_a_scaffolded_arm_resets_to_a_ready_pose_with_its_fingers_pointing_down(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """pybullet's Panda rests straight up, fingers to the sky: no screw reaches a grasp from
    there. new's ready keyframe points them down, and PickCube-v1 resets the robot to it; the
    way they point is measured in ManiSkill (the solver's grasp frame), not by new's kinematics."""
    import numpy as np
    from solve_scene import solve_scene

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold("pb_panda", tmp_path, "ready_pb_panda")
    text = spec.read_text(encoding="utf-8")
    assert "\n  ready:" in text and "\nreset: " in text and "  keyframe: ready\n" in text
    with solve_scene(spec) as (_, _, agent, facts):
        tcp = agent.tcp.pose.sp
        grasp = (tcp * facts.grasp_to_tcp.inv()).to_transformation_matrix()
        assert grasp[:3, 2] @ np.array([0.0, 0.0, -1.0]) > 0.99  # the fingers point down
        assert grasp[2, 3] > 0.05  # above the table
        # and close along y, as ManiSkill's Panda's do (its hand is turned 45° on its flange)
        assert abs(grasp[:3, 1] @ np.array([0.0, 1.0, 0.0])) > 0.99


@pytest.mark.slow
@pytest.mark.maniskill
def test_pybullets_panda_as_new_writes_it_pushes_the_cube_home(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """0 of 20 while its ready pose left the hand turned 45°: pushing along x, one closed
    finger's corner met the cube and slid it off sideways."""
    from robospec.solve.command import render_report, run_solve

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold("pb_panda", tmp_path, "push_pb_panda")
    report = run_solve(spec, "PushCube-v1", 2, None, 1, 0, progress=False)
    assert not report.diagnostics, render_report(report, "text")
    assert [e.success for e in report.episodes] == [True, True], render_report(report, "text")


@pytest.mark.slow
@pytest.mark.maniskill
def test_pybullets_panda_as_new_writes_it_picks_the_cube(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """0 of 5 before the ready keyframe (the first motion had no plan); its tcp is the
    description's panda_grasptarget, its gripper a mimic pair."""
    from robospec.solve.command import render_report, run_solve

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold("pb_panda", tmp_path, "pick_pb_panda")
    report = run_solve(spec, "PickCube-v1", 2, None, 1, 0, progress=False)
    assert not report.diagnostics, render_report(report, "text")
    assert [e.success for e in report.episodes] == [True, True], render_report(report, "text")


@pytest.mark.slow
@pytest.mark.maniskill
def test_a_finger_without_collision_shapes_is_refused_at_the_grasp_check(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The QUT Panda's fingers (rtb-data) have visuals only: nothing of them touches the cube.
    solve says so, located at `grasping` (it raised a bare RuntimeError from SAPIEN before)."""
    from robospec.solve.command import run_solve

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold("rtb_panda", tmp_path, "pick_rtb_panda")
    report = run_solve(spec, "PickCube-v1", 1, None, 1, 0, progress=False)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS682"
    assert "no collision shape" in diagnostic.message and "panda_leftfinger" in diagnostic.message
    text = spec.read_text(encoding="utf-8")
    assert diagnostic.location.line == text[: text.index("\ngrasping:")].count("\n") + 2
    assert not report.episodes


@pytest.mark.slow
@pytest.mark.maniskill
def test_an_arm_that_cannot_reach_down_to_the_cube_is_refused_with_its_reach_measured(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The Unitree Z1 reaches the cube lying flat (its links end to end: 0.8 m), but its grasp
    frame sits 0.31 m beyond its wrist's pitch joint: pointing it straight down at the cube's
    height, as the solution grasps, it reaches 0.58 m from its root, and PickCube-v1 puts the
    cube farther in 15 of seeds 0 to 19. solve says so at --task before any episode (0 of 20
    episodes before, each "a motion had no plan")."""
    import re

    from robospec.solve.command import run_solve

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold("erd_z1", tmp_path, "pick_z1")
    arguments = ["solve", str(spec), "--task", "PickCube-v1", "-n", "20"]
    report = run_solve(spec, "PickCube-v1", 20, None, 1, 0, arguments, progress=False)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS526"
    assert diagnostic.location.file == "<command line>"
    assert diagnostic.location.column > len(str(spec))  # at --task's value
    found = re.search(
        r"'cube' lies (0\.\d\d) to (0\.\d\d) m .* in (\d+) of the 20 seeds asked, beyond its "
        r"reach from above, as the solution grasps it \((0\.\d\d) m with its grasp straight "
        r"down at the cube's height\)",
        diagnostic.message,
    )
    assert found, diagnostic.message
    nearest, farthest, beyond, reach = found.groups()
    assert 0.55 <= float(reach) < float(nearest) <= 0.62 and float(farthest) <= 0.72
    assert int(beyond) > 10
    assert not report.episodes


@pytest.mark.slow
@pytest.mark.maniskill
def test_the_solver_holds_a_controller_that_is_neither_arm_nor_gripper(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The WidowX 250's pd_joint_pos drives its arm, its fingers (a mimic pair) and the
    gripper's motor horn (a joint of its own): the horn is held where the reset put it, where
    solve refused the mode before (RS682)."""
    import numpy as np

    from robospec.solve.command import compile_robot
    from robospec.solve.episodes import make_env
    from robospec.solve.gripper import read_facts

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _scaffold("rtb_wx250s", tmp_path, "pick_wx250s")
    robot, problems = compile_robot(spec)
    assert robot is not None, problems
    env = make_env(robot.uid, "PickCube-v1")
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        facts = read_facts(agent, robot.fingers)
        roles = [role for role, _ in facts.layout]
        assert sorted(roles) == ["arm", "gripper", "held"]
        arm = agent.robot.get_qpos()[0].numpy()[list(facts.arm_joints)]
        action = facts.action(arm, facts.open_action, None)
        horn = agent.robot.active_joints_map["gripper"].active_index[0]
        start = roles.index("held")
        at = sum(width for _, width in facts.layout[:start])
        qpos = agent.robot.get_qpos()[0].numpy()
        assert np.isclose(action[at], qpos[int(horn)])
    finally:
        env.close()


@pytest.mark.slow
def test_a_robot_on_a_free_root_keeps_its_rest_pose_as_its_start(tmp_path: Path) -> None:
    """TALOS has grippers, but stands on a free root: an arm thrown forward to point its
    fingers down tips a standing body (check's hold failed, RS501), and no tabletop task mounts
    a humanoid where it mounts an arm. Its episodes start at rest; an arm's at ready."""
    from ruamel.yaml import YAML

    humanoid = YAML().load(_scaffold("erd_talos", tmp_path, "rs_talos").read_text())
    assert humanoid["loader"]["fix_root_link"] is False
    assert "ready" not in humanoid["keyframes"]
    assert humanoid["reset"] == {"keyframe": "rest"}
    arm = YAML().load(_scaffold("pb_panda", tmp_path, "rs_pb_panda").read_text())
    assert "ready" in arm["keyframes"] and arm["reset"] == {"keyframe": "ready"}


def _with_declared_linkages(spec: Path) -> Path:
    """The xArm gripper's scaffold with its two four-bars declared as loops, as a user writes
    them (new infers no URDF linkage: robospec.authoring.new.linkages): each inner knuckle's
    far end pinned to its finger, the knuckles' drives the gripper, the rest passive."""
    from ruamel.yaml import YAML

    yaml = YAML()
    data = yaml.load(spec.read_text(encoding="utf-8"))
    drivers = ["drive_joint", "right_outer_knuckle_joint"]
    data["groups"]["gripper"] = drivers
    data["groups"]["linkage"] = [
        "left_inner_knuckle_joint",
        "right_inner_knuckle_joint",
        "left_finger_joint",
        "right_finger_joint",
    ]
    for keyframe in data["keyframes"].values():
        keyframe["qpos"]["linkage"] = 0.0
    gripper = data["controllers"]["gripper"]
    for gains in ("stiffness", "damping"):
        if isinstance(gripper[gains], dict):
            gripper[gains] = {j: v for j, v in gripper[gains].items() if j in drivers}
    gripper["mimic"] = {"right_outer_knuckle_joint": "drive_joint"}
    data["controllers"]["linkage"] = {"type": "passive", "joints": "linkage", "damping": 0}
    for mode in data["control_modes"].values():
        mode["linkage"] = "linkage"
    data["loops"] = {
        f"{side}_linkage": {
            "links": [f"{side}_inner_knuckle", f"{side}_finger"],
            "at": [[0, sign * 0.035465, 0.042039], [0, -sign * 0.015, 0.015]],
        }
        for side, sign in (("left", 1), ("right", -1))
    }
    out = spec.with_name("linkages.yaml")
    with out.open("w", encoding="utf-8") as stream:
        yaml.dump(data, stream)
    return out


@pytest.mark.slow
@pytest.mark.maniskill
def test_a_closed_linkages_passive_joints_are_no_second_gripper_to_the_solver(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The xArm gripper with its four-bars closed by loops: the passive controller of the
    linkage's joints takes no action, and the loops move the fingers; solve refused the mode
    before, two controllers moving the fingers (RS682). (18 of 20 PickCube-v1 seeds so.)"""
    from robospec.solve.command import compile_robot
    from robospec.solve.episodes import make_env
    from robospec.solve.gripper import read_facts

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = _with_declared_linkages(_scaffold("pb_xarm6_gripper", tmp_path, "pick_xarm_loops"))
    robot, problems = compile_robot(spec)
    assert robot is not None, problems
    env = make_env(robot.uid, "PickCube-v1")
    try:
        env.reset(seed=0)
        facts = read_facts(env.unwrapped.agent, robot.fingers)
        assert [role for role, width in facts.layout if width] == ["arm", "gripper"]
        assert facts.closed_action != facts.open_action
    finally:
        env.close()


@pytest.mark.slow
@pytest.mark.maniskill
def test_an_arm_new_finds_no_ready_pose_for_says_what_stopped_it(tmp_path: Path) -> None:
    """example-robot-data's Baxter: its lower shoulder's collision shape overlaps its torso
    whenever the arm turns forward (s0 ≥ 0), so every pose with the fingers pointing down in
    front of the arm touches, and the episodes start at rest; the reset's comment says why."""
    out = tmp_path / "baxter.yaml"
    result = run_new(_description("erd_baxter"), out, "ready_baxter", force=True).write()
    assert not result.failed, result.diagnostics
    text = out.read_text(encoding="utf-8")
    assert "\n  ready:" not in text
    (reset,) = [line for line in text.splitlines() if line.startswith("reset:")]
    assert "every episode starts at rest" in reset and "no ready pose" in reset
    assert "right_lower_shoulder + torso touch" in reset, reset
