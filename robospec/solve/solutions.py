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
from typing import Any

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
PACKAGE = "mani_skill.examples.motionplanning.panda.solutions"
SOLVER_NAME = "PandaArmMotionPlanningSolver"
GRASP_NAME = "compute_grasp_info_by_obb"


def closing_as_the_fingers(compute: Callable[..., Any], solver: type) -> Callable[..., Any]:
    """``compute_grasp_info_by_obb`` choosing the grasp whose closing lies nearest the way the
    fingers close now. The solutions pass the tcp's y axis as that way (the Panda's tcp frame
    has y across its fingers); a robot's tcp link may be oriented any way (Unitree Z1's, as
    ``new`` finds it, has its x there), and a grasp a quarter turn off is one the wrist may not
    reach. The way the fingers close is the grasp frame's y (robospec.solve.gripper), read
    from the solver the solution has just built."""

    def compute_grasp(*args: Any, **kwargs: Any) -> Any:
        planner = getattr(solver, "current", None)
        if planner is not None and "target_closing" in kwargs:
            kwargs["target_closing"] = planner.closing()
        return compute(*args, **kwargs)

    return compute_grasp


def solution(task: str, solver: type) -> Callable[..., Any]:
    """ManiSkill's solution of ``task``, planning with ``solver``; its grasps close the way
    the robot's fingers close now (:func:`closing_as_the_fingers`)."""
    module = importlib.import_module(f"{PACKAGE}.{SOLUTIONS[task]}")
    solve = module.solve
    rebound = dict(solve.__globals__, **{SOLVER_NAME: solver})
    if GRASP_NAME in rebound:
        rebound[GRASP_NAME] = closing_as_the_fingers(rebound[GRASP_NAME], solver)
    return types.FunctionType(
        solve.__code__, rebound, solve.__name__, solve.__defaults__, solve.__closure__
    )


def lend_grasp_pose(agent: Any) -> None:
    """``agent.build_grasp_pose``, the Panda's, where the agent has none of its own."""
    if hasattr(agent, "build_grasp_pose"):
        return
    from mani_skill.agents.robots.panda.panda import Panda

    agent.build_grasp_pose = Panda.build_grasp_pose
