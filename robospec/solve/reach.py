"""How far an arm reaches with its grasp pointing straight down: what the solutions that grasp
from above ask of it.

ManiSkill's pick, stack and place solutions grasp every object from above (``approaching =
[0, 0, -1]``: the grasp frame's z straight down, centred on the object) wherever the task put
it, and the tasks mount every robot where they mount the Panda. A links-end-to-end reach
(:func:`robospec.maniskill.reach.chain_reach`) says what no pose can touch; an arm that reaches
the cube's distance lying flat may still not reach it pointing its fingers down at the table
(measured: the Unitree Z1's grasp frame, 0.31 m beyond its wrist's pitch joint, reaches 0.58 m
from its root so at the cube's height, where PickCube-v1 puts the cube 0.52 to 0.72 m away).

:class:`DownwardReach` measures it on the kinematics SAPIEN builds of the loaded robot (its
Pinocchio model, as the planner plans on it): whether the arm's joints, within their limits,
put the grasp frame's origin at a point with its z straight down (any turn about z: the
solutions choose the closing by the object's faces), by damped least squares from the reset
pose, the middle of the joints' ranges and :data:`RANDOM_STARTS` poses drawn from a fixed seed;
and the farthest such point from the root, at an object's height and bearing, by bisection.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np

from robospec.solve.gripper import GripperFacts

if TYPE_CHECKING:
    import gymnasium as gym
    from mani_skill.agents.base_agent import BaseAgent
    from mani_skill.envs.sapien_env import BaseEnv

POSITION_TOLERANCE = 0.002  # m: the grasp frame's origin from the point
ANGLE_TOLERANCE = 0.02  # rad: its z from straight down
ANGLE_WEIGHT = 0.3  # m per unit of z's error: how much pointing counts against position
DAMPING = 0.05
STEP = 0.2  # rad a joint moves at most per iteration
ITERATIONS = 150
HALVINGS = 6
RANDOM_STARTS = 32
SEED = 0
RESOLUTION = 0.005  # m: the bisection's last interval
FINITE_DIFFERENCE = 1e-6


class DownwardReach:
    """Where ``agent``'s grasp frame (``facts``) reaches pointing straight down."""

    def __init__(self, agent: BaseAgent, facts: GripperFacts) -> None:
        robot = agent.robot
        self.model = robot.create_pinocchio_model()  # (the CPU simulation's)
        self.tcp_index = facts.tcp_index
        self.tcp_to_grasp = facts.grasp_to_tcp.inv().to_transformation_matrix()
        self.arm = np.asarray(facts.arm_joints)
        self.qpos = robot.get_qpos()[0].cpu().numpy().astype(np.float64)
        limits = robot.get_qlimits()[0].cpu().numpy().astype(np.float64)
        self.low, self.high = limits[self.arm, 0], limits[self.arm, 1]
        base = robot.pose.sp.to_transformation_matrix()
        self.to_base = np.linalg.inv(base)
        self.root = base[:3, 3]
        self.down = self.to_base[:3, :3] @ np.array([0.0, 0.0, -1.0])
        rng = np.random.default_rng(SEED)
        low, high = np.maximum(self.low, -np.pi), np.minimum(self.high, np.pi)
        self.starts = [
            np.clip(self.qpos[self.arm], self.low, self.high),
            (low + high) / 2,
            *(rng.uniform(low, high) for _ in range(RANDOM_STARTS)),
        ]

    def reaches(self, point: np.ndarray) -> bool:
        """Whether the grasp frame's origin reaches ``point`` (world) with its z straight down."""
        target = self.to_base[:3, :3] @ np.asarray(point, dtype=np.float64) + self.to_base[:3, 3]
        return any(self._descend(start.copy(), target) for start in self.starts)

    def farthest(self, point: np.ndarray, bound: float) -> float | None:
        """The farthest horizontal distance from the root, at most ``bound``, at ``point``'s
        height and bearing, at which the grasp reaches down (to :data:`RESOLUTION`); None where
        it reaches down nowhere out to ``point`` (tried at ``point`` and a half and a quarter
        of its distance)."""
        point = np.asarray(point, dtype=np.float64)
        flat = point[:2] - self.root[:2]
        distance = float(np.linalg.norm(flat))
        bearing = flat / distance if distance > 0 else np.array([1.0, 0.0])

        def at(d: float) -> np.ndarray:
            return np.array([*(self.root[:2] + d * bearing), point[2]])

        if self.reaches(point):
            low, high = distance, max(bound, distance)
            if self.reaches(at(high)):
                return high
        else:
            high = distance
            found = next((d for d in (distance / 2, distance / 4) if self.reaches(at(d))), None)
            if found is None:
                return None
            low = found
        while high - low > RESOLUTION:
            middle = (low + high) / 2
            if self.reaches(at(middle)):
                low = middle
            else:
                high = middle
        return low

    def _grasp(self, arm: np.ndarray) -> np.ndarray:
        qpos = self.qpos.copy()
        qpos[self.arm] = arm
        self.model.compute_forward_kinematics(qpos)
        tcp = self.model.get_link_pose(self.tcp_index).to_transformation_matrix()
        return tcp @ self.tcp_to_grasp

    def _error(self, arm: np.ndarray, target: np.ndarray) -> np.ndarray:
        grasp = self._grasp(arm)
        return np.concatenate([grasp[:3, 3] - target, ANGLE_WEIGHT * (grasp[:3, 2] - self.down)])

    def _descend(self, arm: np.ndarray, target: np.ndarray) -> bool:
        from robospec.kinematics.descent import damped_descent

        found = damped_descent(
            lambda joints: self._error(joints, target),
            arm,
            self.low,
            self.high,
            self._close,
            iterations=ITERATIONS,
            damping=DAMPING,
            step=STEP,
            halvings=HALVINGS,
            difference=FINITE_DIFFERENCE,
        )
        return found.converged or (not found.stalled and self._close(found.error))

    @staticmethod
    def _close(error: np.ndarray) -> bool:
        # |z - down| is 2 sin(angle / 2): about the angle, for the small ones here
        return bool(
            np.linalg.norm(error[:3]) < POSITION_TOLERANCE
            and np.linalg.norm(error[3:]) < ANGLE_WEIGHT * ANGLE_TOLERANCE
        )


def dynamic_actors(base_env: BaseEnv) -> dict[str, np.ndarray]:
    """The task's objects (its dynamic actors) and where the last reset put them (world)."""
    return {
        name: actor.pose.p[0].cpu().numpy().astype(np.float64)
        for name, actor in base_env.scene.actors.items()
        if actor.px_body_type == "dynamic"
    }


def beyond_downward_reach(
    env: gym.Env, facts: GripperFacts, seeds: list[int], bound: float
) -> str | None:
    """Why the solution's grasps from above cannot apply: the objects lie beyond the farthest
    the grasp reaches down at their height (measured at the first seed, each object's height
    and bearing) in more than half of ``seeds`` (each reset as the episode will be), or the
    grasp reaches down nowhere there; None where they do not. ``bound``: the chain's reach,
    which no point beyond needs trying. The environment is left reset at the last seed."""
    base = cast("BaseEnv", env.unwrapped)
    reach = DownwardReach(base.agent, facts)
    root = reach.root
    farthest: dict[str, float | None] = {}
    beyond: list[tuple[str, float]] = []  # per seed beyond: the object, its distance
    for seed in seeds:
        env.reset(seed=seed)
        for name, point in dynamic_actors(base).items():
            if name not in farthest:
                farthest[name] = reach.farthest(point, bound)
            limit = farthest[name]
            distance = float(np.linalg.norm(point[:2] - root[:2]))
            if limit is None or distance > limit + RESOLUTION:
                beyond.append((name, distance))
                break
    if 2 * len(beyond) <= len(seeds):
        return None
    name = max({n for n, _ in beyond}, key=lambda n: sum(m == n for m, _ in beyond))
    distances = [d for n, d in beyond if n == name]
    limit = farthest[name]
    nearest, farthest_seen = f"{min(distances):.2f}", f"{max(distances):.2f}"
    lies = nearest if nearest == farthest_seen else f"{nearest} to {farthest_seen}"
    measured = (
        f"it cannot point its grasp straight down at the {name}'s height"
        if limit is None
        else f"{limit:.2f} m with its grasp straight down at the {name}'s height"
    )
    return (
        f"'{name}' lies {lies} m from the robot's root where the task mounts it in "
        f"{len(distances)} of the {len(seeds)} seeds asked, beyond its reach from above, as "
        f"the solution grasps it ({measured})"
    )
