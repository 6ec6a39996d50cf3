"""A spec's robot in a task's scene as ``robospec solve`` builds it, for the tests that read
what the solver reads there (the grasp frame, the reach, the gripper's ends)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any


@contextmanager
def solve_scene(spec: Path, task: str = "PickCube-v1") -> Iterator[tuple[Any, Any, Any, Any]]:
    """(the compiled robot, the task's env reset at seed 0, its agent, the solver's facts of
    it); the env closed after."""
    from robospec.solve.command import compile_robot
    from robospec.solve.episodes import make_env
    from robospec.solve.gripper import read_facts

    robot, problems = compile_robot(spec)
    assert robot is not None, problems
    env = make_env(robot.uid, task)
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        yield robot, env, agent, read_facts(agent, robot.fingers, robot.loops)
    finally:
        env.close()
