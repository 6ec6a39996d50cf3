"""``robospec solve``: ManiSkill's own solutions, planned by robospec, pick the cube with the
Panda's spec, write ManiSkill's trajectory format, and ManiSkill's replay tool reproduces each
success; where a solution cannot apply the command says why, located, before any episode.

A few episodes only (each costs about two seconds): the success-rate sweeps are
benchmarks/solve.py's and docs/robots.md's.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]

ROOT = Path(__file__).resolve().parent.parent
PANDA = ROOT / "specs" / "maniskill" / "panda.yaml"


def test_the_panda_picks_the_cube_and_the_replay_reproduces_each_success(
    tmp_path: Path,
) -> None:
    from robospec.authoring.commands import run_doc
    from robospec.solve.command import render_report, run_solve
    from robospec.solve.replay import main as replay

    report = run_solve(PANDA, "PickCube-v1", 2, tmp_path, 1, 0, progress=False)
    assert not report.diagnostics, render_report(report, "text")
    assert [e.success for e in report.episodes] == [True, True]
    assert report.trajectory == tmp_path / "PickCube-v1.h5"
    assert report.trajectory.with_suffix(".json").is_file()
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        replay([str(PANDA), "--traj-path", str(report.trajectory)])
    assert re.search(r"Replayed 2 episodes, 2/2=100\.00% demos saved", printed.getvalue())
    # the robot card shows the success rate from that record (doc --demos)
    card = tmp_path / "card" / "panda.md"
    done = run_doc(PANDA, card, demos=tmp_path)
    assert not done.failed, done.diagnostics
    text = {o.path: o.content for o in done.outputs}[card]
    assert isinstance(text, str)
    assert "| `PickCube-v1` | 2 | 2 | 100% | [PickCube-v1.json](<../PickCube-v1.json>) |" in text


def test_the_pandas_grasp_reaches_down_to_every_cube_the_task_places() -> None:
    """The measure of the refusal above (RS526 for an arm that cannot reach down to most of
    the task's placements): the Panda's grasp frame, pointing straight down at the cube's
    height, reaches 0.8 m from its root; PickCube-v1 puts the cube 0.52 to 0.72 m away."""
    import numpy as np
    from solve_scene import solve_scene

    from robospec.maniskill.reach import chain_reach
    from robospec.solve.reach import DownwardReach, beyond_downward_reach, dynamic_actors

    with solve_scene(PANDA) as (_, env, agent, facts):
        reach = DownwardReach(agent, facts)
        cube = dynamic_actors(env.unwrapped)["cube"]
        assert reach.reaches(cube)
        assert not reach.reaches(cube + np.array([0.5, 0.0, 0.0]))  # 1.1 m from its root
        bound = chain_reach(agent.robot)
        assert bound is not None
        farthest = reach.farthest(cube, bound)
        assert farthest is not None and 0.75 < farthest < 0.85
        assert beyond_downward_reach(env, facts, list(range(5)), bound) is None


def test_a_task_without_a_solution_is_refused_at_the_task_option() -> None:
    from robospec.solve.command import run_solve

    arguments = ["solve", str(PANDA), "--task", "PushT-v1"]
    report = run_solve(PANDA, "PushT-v1", 1, None, 1, 0, arguments, progress=False)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS680"
    assert diagnostic.location.file == "<command line>" and diagnostic.location.column > 1
    assert not report.episodes


def test_a_robot_without_a_grasp_check_is_refused_at_its_uid() -> None:
    from robospec.solve.command import run_solve

    report = run_solve(ROOT / "specs" / "twolink.toml", "PickCube-v1", 1, None, 1, 0)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS681"
    assert (diagnostic.location.line, diagnostic.location.column) == (6, 1)


def test_a_gripper_arm_without_absolute_joint_positions_is_refused_at_its_control_modes(
    tmp_path: Path,
) -> None:
    """The solutions act in pd_joint_pos: a spec that offers only joint deltas cannot be
    driven by planned joint positions."""
    from robospec.solve.command import run_solve

    text = PANDA.read_text(encoding="utf-8")
    head, modes = text.split("control_modes:\n")
    kept = "".join(line for line in modes.splitlines(True) if "pd_joint_delta_pos:" in line)
    rest = modes[modes.index("\ntcp:") :]
    spec = tmp_path / "panda.yaml"
    head = head.replace("uid: rs_panda\n", "uid: rs_panda_deltas\n")  # rs_panda is registered
    spec.write_text(head + "control_modes:\n" + kept + rest, encoding="utf-8")
    report = run_solve(spec, "PickCube-v1", 1, None, 1, 0, progress=False)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS682"
    assert "pd_joint_pos" in diagnostic.message
    line = text[: text.index("control_modes:")].count("\n") + 1
    assert diagnostic.location.line == line
    assert not report.episodes


def test_a_velocity_controlled_arm_in_pd_joint_pos_is_refused_at_its_controllers(
    tmp_path: Path,
) -> None:
    """A mode named pd_joint_pos whose arm takes joint velocities: the solutions' planned
    positions cannot be its action, and it has no position controller's settings to read."""
    from robospec.solve.command import run_solve

    text = PANDA.read_text(encoding="utf-8")
    mode = "  pd_joint_pos: {arm: arm_pos, gripper: gripper}\n"
    assert mode in text
    text = text.replace(mode, mode.replace("arm_pos", "arm_vel"))
    spec = tmp_path / "panda.yaml"
    spec.write_text(text.replace("uid: rs_panda\n", "uid: rs_panda_vel\n"), encoding="utf-8")
    report = run_solve(spec, "PickCube-v1", 1, None, 1, 0, progress=False)
    (diagnostic,) = report.diagnostics
    assert diagnostic.code == "RS682"
    assert "'arm' controller is a PDJointVelControllerConfig" in diagnostic.message
    assert not report.episodes


def test_min_success_fails_a_report_below_it_and_passes_one_at_it() -> None:
    from robospec.solve.command import SolveReport, below_min_success
    from robospec.solve.episodes import Episode

    report = SolveReport("rs_panda", "PickCube-v1", [Episode(0, True, 70, True)])
    report.episodes.append(Episode(1, False, 90, False))
    short = below_min_success(report, 0.9, ["solve", "x.yaml", "--min-success", "0.9"])
    assert short is not None and short.code == "RS683"
    assert below_min_success(report, 0.5, []) is None


def test_check_solve_asks_each_task_for_its_episodes() -> None:
    from robospec.physics.command import task_requests

    (request,), problems = task_requests(["PickCube-v1"], ["check", "x.yaml"], solve=3)
    assert not problems and request.solve == 3


@pytest.mark.slow
def test_check_solve_reports_the_success_of_the_tasks_solution() -> None:
    """About two minutes: the whole of check, then two episodes."""
    from conftest import run_robospec

    done = run_robospec("check", str(PANDA), "--task", "PickCube-v1", "--solve", "2", timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert re.search(r"solve .* PickCube-v1 +pass +ManiSkill's solution: 2 of 2", done.stdout)


def test_a_failed_episode_says_which_joint_did_not_follow_its_plan_and_what_it_struck() -> None:
    """The planner checks no collisions: an arm whose path runs through its own body stops
    against it (Baxter's scaffold: right_s0 1 rad short, its shoulder on the torso), and the
    episode's note says so rather than nothing."""
    import types

    import numpy as np

    from robospec.solve.episodes import _episode
    from robospec.solve.planner import FOLLOW_TOLERANCE, GripperArmSolver

    env = types.SimpleNamespace(unwrapped=types.SimpleNamespace(elapsed_steps=np.array([7])))
    notes: list[str] = []

    def solve(env: object, **_: object) -> list[dict[str, np.ndarray]]:
        solver = GripperArmSolver.__new__(GripperArmSolver)
        solver.notes = notes
        joint = types.SimpleNamespace(name="shoulder")
        qpos = np.array([[0.0, 0.0]])
        solver.robot = types.SimpleNamespace(
            get_qpos=lambda: _Tensor(qpos),
            active_joints=[joint, joint],
            links=[],
        )
        solver.arm = np.array([0, 1])
        solver.base_env = types.SimpleNamespace(
            scene=types.SimpleNamespace(px=types.SimpleNamespace(get_contacts=list))
        )
        solver._check_followed(np.array([0.0, 0.0]))  # reached: no note
        solver._check_followed(np.array([0.0, 2 * FOLLOW_TOLERANCE]))
        return [{"success": np.array(False)}]

    episode = _episode(env, solve, seed=3, notes=notes)
    assert not episode.success and episode.steps == 7
    assert episode.error == "the arm did not follow its plan: shoulder ended 0.20 rad from it"


class _Tensor:
    def __init__(self, value: object) -> None:
        import numpy as np

        self.value = np.asarray(value)

    def __getitem__(self, index: int) -> _Tensor:
        return _Tensor(self.value[index])

    def cpu(self) -> _Tensor:
        return self

    def numpy(self) -> object:
        return self.value
