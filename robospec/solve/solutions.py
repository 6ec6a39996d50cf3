"""ManiSkill's own motion-planning solutions, run with robospec's solver for the robot.

Each solution (``mani_skill/examples/motionplanning/panda/solutions/*.py``) builds
``PandaArmMotionPlanningSolver(env, ...)`` itself and calls the Panda's
``agent.build_grasp_pose``. :func:`solution` returns the same function with the solver's name
bound to robospec's class for the robot instead (a copy of the function with other globals:
ManiSkill's modules are left as they are), and :func:`lend_grasp_pose` gives an agent that lacks
it the Panda's ``build_grasp_pose``, which is geometry only: the grasp frame, z along the
approach and y along the closing direction, that the solver turns into the robot's tcp frame.
"""

from __future__ import annotations

import importlib
import types
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import gymnasium as gym
    import sapien
    from mani_skill.agents.base_agent import BaseAgent
    from mani_skill.envs.sapien_env import BaseEnv
    from mani_skill.utils.structs import Link, Pose

# the tasks whose solutions need nothing but a two-finger gripper on an arm (no obstacles
# added to the planner, no tool of the Panda's): task id -> module under panda/solutions
SOLUTIONS: dict[str, str] = {
    "PickCube-v1": "pick_cube",
    "PushCube-v1": "push_cube",
    "StackCube-v1": "stack_cube",
    "PullCube-v1": "pull_cube",
    "LiftPegUpright-v1": "lift_peg_upright",
    "PlaceSphere-v1": "place_sphere",
    "StackPyramid-v1": "stack_pyramid",
}
# the solutions that grasp from above (``approaching = [0, 0, -1]``) wherever the task put the
# objects; push and pull move the tcp as the reset holds it
GRASPED_FROM_ABOVE = frozenset(SOLUTIONS) - {"PushCube-v1", "PullCube-v1"}
PACKAGE = "mani_skill.examples.motionplanning.panda.solutions"
SOLVER_NAME = "PandaArmMotionPlanningSolver"


def solution(task: str, solver: type) -> Callable[..., Any]:
    """ManiSkill's solution of ``task``, planning with ``solver`` (run it on
    :func:`in_grasp_frame`'s view of the environment)."""
    module = importlib.import_module(f"{PACKAGE}.{SOLUTIONS[task]}")
    solve = module.solve
    rebound = dict(solve.__globals__, **{SOLVER_NAME: solver})
    return types.FunctionType(
        solve.__code__, rebound, solve.__name__, solve.__defaults__, solve.__closure__
    )


def lend_grasp_pose(agent: Any) -> None:
    """``agent.build_grasp_pose``, the Panda's, where the agent has none of its own."""
    if hasattr(agent, "build_grasp_pose"):
        return
    from mani_skill.agents.robots.panda.panda import Panda

    agent.build_grasp_pose = Panda.build_grasp_pose


def in_grasp_frame(env: gym.Env, grasp_to_tcp: sapien.Pose) -> _View:
    """``env`` as the solutions read it, with ``agent.tcp.pose`` the grasp frame's pose
    (robospec.solve.gripper): the solutions take the tcp's frame for the Panda's, z along its
    fingers and y across them, to choose a grasp's closing (its y axis) and to hold the gripper
    as it is while pushing (its orientation); a robot's tcp link may be framed any way (the
    Z1's, as ``new`` finds it, has its x across the jaws). Everything else is ``env``'s."""
    return _View(env, grasp_to_tcp)


class _View:
    """An environment, its base environment or its agent, with the tcp seen in the grasp
    frame; every other attribute the object's own."""

    def __init__(self, target: gym.Env | BaseEnv | BaseAgent, grasp_to_tcp: sapien.Pose) -> None:
        self._target = target
        self._grasp_to_tcp = grasp_to_tcp

    def __getattr__(self, name: str) -> Any:
        value = getattr(self._target, name)
        if name in ("unwrapped", "agent"):
            return _View(value, self._grasp_to_tcp)
        if name == "tcp":
            return _Tcp(value, self._grasp_to_tcp)
        return value


class _Tcp:
    def __init__(self, link: Link, grasp_to_tcp: sapien.Pose) -> None:
        self._link = link
        self._grasp_to_tcp = grasp_to_tcp

    def __getattr__(self, name: str) -> Any:
        return getattr(self._link, name)

    @property
    def pose(self) -> Pose:
        from mani_skill.utils.structs.pose import Pose

        return self._link.pose * Pose.create(self._grasp_to_tcp.inv())
