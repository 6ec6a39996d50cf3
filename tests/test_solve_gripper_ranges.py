"""``robospec solve`` drives a gripper whose fingers' joints have ranges of their own, one value
per action dimension, and measures a two-armed robot's reach from the arm that carries the tcp.

gym-aloha's ALOHA (an MJCF, loaded by the mujoco route): each ViperX 300 S finger slides on a
joint of its own, the left one over [0.021, 0.057] m, the right one over [-0.057, -0.021] m, and
``new`` gives all four fingers of both arms one controller. solve refused it (RS682: "the gripper
controller's range differs between its joints"); it opens and closes each dimension to the end
of its range that parts or closes the grasp check's fingers, and holds the other hand's where the
reset put them. From PickCube-v1's mount the cube lies beyond the left arm's reach, which solve
says before any episode (RS526, measured from that arm's own base): it ran episodes that had no
plan before, the whole robot's chain (1.66 m from the root, across the weld to the arm) being
taken as the arm's reach.

gym-xarm's xArm7 (an MJCF): its fingers move through two closed four-bars, and the gripper's
open and closed actions are read by closing the loops' kinematics again.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from corpus import BY_KEY, CorpusMissing, locate

from robospec.authoring.commands import run_new

pytestmark = [
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
    pytest.mark.slow,
    pytest.mark.maniskill,
]


@pytest.fixture(scope="module")
def aloha(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """ALOHA's spec as ``robospec new`` writes it (without the probe's search in ManiSkill)."""
    try:
        description = locate(BY_KEY["aloha_bimanual"])
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    out = tmp_path_factory.mktemp("aloha") / "aloha.yaml"
    result = run_new(description, out, "ranges_aloha", force=True, simulate=False).write()
    assert not result.failed, result.diagnostics
    return out


def test_each_dimension_of_the_gripper_opens_to_the_end_of_its_own_range(
    aloha: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import numpy as np
    from solve_scene import solve_scene

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    with solve_scene(aloha) as (_, _, agent, facts):
        gripper = next(
            c
            for c in agent.controller.controllers.values()
            if "vx300s_left/left_finger" in [j.name for j in c.joints]
        )
        names = [j.name for j in gripper.joints]
        qpos = agent.robot.get_qpos()[0].numpy()
        ends = zip(facts.open_action, facts.closed_action, strict=True)
        by_joint = dict(zip(names, ends, strict=True))
        # the grasp check's fingers: each to its own ends, opposite in sign
        assert np.allclose(by_joint["vx300s_left/left_finger"], (0.057, 0.021))
        assert np.allclose(by_joint["vx300s_left/right_finger"], (-0.057, -0.021))
        # the other hand's fingers stay where the reset put them, open or closed
        for name in ("vx300s_right/left_finger", "vx300s_right/right_finger"):
            held = qpos[agent.robot.active_joints_map[name].active_index[0]]
            assert np.allclose(by_joint[name], (held, held), atol=1e-6)
        # the action the solution appends has the mode's shape
        arm = qpos[list(facts.arm_joints)]
        shape = agent.action_space.shape
        assert facts.action(arm, facts.closed_action, None).shape == shape
        assert facts.action(arm, -0.6, None).shape == shape  # a solution's own gripper_state


def test_the_cube_beyond_the_tcps_arm_is_refused_with_that_arms_reach(
    aloha: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from robospec.solve.command import run_solve

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    report = run_solve(aloha, "PickCube-v1", 3, None, 1, 0, progress=False)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS526", diagnostic.message
    assert "vx300s_left (the base of the tcp's arm)" in diagnostic.message
    distance, reach = (float(v) for v in re.findall(r"(\d+\.\d+) m", diagnostic.message))
    assert reach < distance < 1.3 and 0.8 < reach < 1.1  # the arm's own: not the robot's 1.66
    assert not report.episodes


def test_a_gripper_closed_through_loops_opens_and_closes_its_fingers_as_its_facts_say(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """gym-xarm's xArm7 (MJCF): each finger hangs on a four-bar closed by a loop, so where the
    fingers are at a gripper action is found by closing the loops' kinematics again (least
    squares, robospec.solve.gripper); the open and closed actions read so, driven in the task's
    scene, part the fingers and bring them together (a sign turned in that solve makes the
    "open" action the narrower)."""
    import numpy as np
    from solve_scene import solve_scene

    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    try:
        description = locate(BY_KEY["gx_xarm7"])
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    spec = tmp_path / "xarm7.yaml"
    result = run_new(description, spec, "loops_xarm7", force=True, simulate=False).write()
    assert not result.failed, result.diagnostics
    with solve_scene(spec) as (robot, env, agent, facts):
        assert len(robot.loops) == 2
        links = [agent.robot.links_map[name] for name in robot.fingers]
        arm = agent.robot.get_qpos()[0].numpy()[list(facts.arm_joints)]

        def span_after(gripper: object) -> float:
            for _ in range(40):
                env.step(facts.action(arm, gripper, None))
            a, b = (link.pose.p[0].numpy() for link in links)
            return float(np.linalg.norm(a - b))

        wide = span_after(facts.open_action)
        shut = span_after(facts.closed_action)
    assert wide > shut + 0.01, (wide, shut)
