"""Episodes of one task, solved and recorded in ManiSkill's trajectory format, in one process.

As ``mani_skill.examples.motionplanning.panda.run``'s ``_main`` does: ``gym.make`` in
``pd_joint_pos`` with no observations (``replay_trajectory`` makes them later, in any mode),
``RecordEpisode`` writing ``NAME.h5`` and ``NAME.json``, one solution per seed, each episode
flushed, its success as the task judges it (``info["success"]`` after the solution's last step).
Here the scene is headless (``render_backend="none"``) and the robot's sim config is the one its
spec recommends.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

if TYPE_CHECKING:
    import gymnasium as gym
    from mani_skill.envs.sapien_env import BaseEnv

    from robospec.solve.gripper import Closing
    from robospec.solve.solutions import _View

SOURCE = "robospec solve: ManiSkill's motion-planning solution, robospec's planner"


@dataclass(frozen=True)
class Episode:
    seed: int
    success: bool
    steps: int
    planned: bool  # False: some motion of the solution had no plan (the episode still counts)
    error: str | None = None  # the solution raised (ManiSkill's run script counts it a failure)

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def make_env(uid: str, task: str) -> gym.Env:
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers the tasks)

    from robospec.maniskill.headless import headless_loading
    from robospec.output.register import sim_config_for

    with headless_loading():
        return gym.make(
            task,
            robot_uids=uid,
            obs_mode="none",
            control_mode="pd_joint_pos",
            render_mode=None,
            sim_backend="physx_cpu",
            render_backend="none",
            sim_config=sim_config_for(uid),
        )


def record(
    uid: str,
    task: str,
    finger_links: tuple[str, str],
    seeds: list[int],
    folder: Path,
    name: str,
    on_episode: Callable[[Episode], None],
    loops: tuple[Closing, ...] = (),
) -> Path:
    """Solve and record ``seeds``; the trajectory file written (``folder/name.h5``)."""
    from mani_skill.utils.wrappers.record import RecordEpisode

    from robospec.solve.gripper import read_facts
    from robospec.solve.planner import solver_class
    from robospec.solve.solutions import in_grasp_frame, lend_grasp_pose, solution

    env = make_env(uid, task)
    env = RecordEpisode(
        cast("BaseEnv", env),  # (it takes any environment of ManiSkill's, wrapped: its unwrapped)
        output_dir=str(folder),
        trajectory_name=name,
        save_video=False,
        source_type="motionplanning",
        source_desc=SOURCE,
        record_reward=False,
        save_on_reset=False,
    )
    try:
        env.reset(seed=seeds[0] if seeds else 0)
        agent = cast("BaseEnv", env.unwrapped).agent
        lend_grasp_pose(agent)
        facts = read_facts(agent, finger_links, loops)
        solver = solver_class(facts)
        solve = solution(task, solver)
        seen = in_grasp_frame(env, facts.grasp_to_tcp)
        for seed in seeds:
            on_episode(_episode(seen, solve, seed, solver.notes))
            env.flush_trajectory()
        return Path(env._h5_file.filename)
    finally:
        env.close()


def _episode(env: _View, solve: Callable[..., Any], seed: int, notes: list[str]) -> Episode:
    """One seed solved; a failure's note: the solution's exception, else the first path the arm
    did not follow (the solver's notes)."""
    error = None
    notes.clear()
    try:
        result = solve(env, seed=seed, debug=False, vis=False)
    except Exception as exc:  # a solution's own failure, as ManiSkill's run script counts it
        result, error = -1, f"{type(exc).__name__}: {exc}"
    steps = int(env.unwrapped.elapsed_steps[0])
    # as ManiSkill's run script judges it: the task's success after the solution's last step;
    # a last motion with no plan is a failure
    planned = not (isinstance(result, int) and result == -1)
    success = planned and bool(result[-1]["success"].item())
    if error is None and not success and notes:
        error = notes[0]
    return Episode(seed, success, steps, planned, error)
