"""The motion planner ManiSkill's solutions drive, for any arm with a two-finger gripper.

ManiSkill's solutions (``mani_skill.examples.motionplanning.panda.solutions``) build a
``PandaArmMotionPlanningSolver`` and call ``move_to_pose_with_screw``, ``open_gripper`` and
``close_gripper`` on it. Upstream's solver plans with mplib, which needs numpy 1 (mplib 0.1.1,
which ManiSkill 3.0.1 pins, and 0.2.1 alike segfault building a planner under numpy 2:
docs/solve.md). :class:`GripperArmSolver` has the same methods and the same screw motion, with
the kinematics SAPIEN itself builds from the loaded articulation (its Pinocchio model: no URDF
needed, so MJCF robots plan too): from the current joints, steps of 0.1 rad along the
pseudo-inverse of the tcp's Jacobian until the tcp's twist to the target is used up, within the
joint limits; then time-optimal parametrisation by TOPP-RA under 0.9 rad/s and 0.9 rad/s²
(mplib's defaults scaled by ManiSkill's 0.9), sampled at the control step. What mplib adds and
this does not: collision checks against the robot itself and point clouds, which the pick, push
and stack solutions never set.

The robot's facts come from :class:`~robospec.solve.gripper.GripperFacts`: which joints
the arm moves, the action layout of ``pd_joint_pos``, the gripper's open and closed actions, and
the fixed transform from the solutions' grasp frame to the tcp link's.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, cast

import numpy as np

from robospec.solve.gripper import GripperFacts

if TYPE_CHECKING:
    import sapien
    from mani_skill.envs.sapien_env import BaseEnv
    from mani_skill.envs.scene import ManiSkillScene
    from mani_skill.utils.structs import Pose
    from sapien.physx import PhysxCpuSystem

QPOS_STEP = 0.1  # rad per screw step (mplib's qpos_step)
# mplib's default joint limits, 1 rad/s and 1 rad/s², which ManiSkill's solvers scale by 0.9
MPLIB_LIMIT = 1.0
LIMIT_TOLERANCE = 1e-3  # rad past a joint limit that a screw step may go (mplib's)
# screw steps at most (20 rad of joint motion): near a singularity (an arm at full stretch) the
# pseudo-inverse's steps barely move the tcp, and an unbounded screw ran for minutes into
# paths of thousands of control steps
MAX_SCREW_STEPS = 200
# rad: how far a joint of the arm may end from its planned position after a path (and its
# refine steps); past it the arm did not follow the plan (the planner checks no collisions: an
# arm swinging through its own body stops against it), which the episode's note says
FOLLOW_TOLERANCE = 0.1


class PlanFailed(Exception):
    """No screw motion reaches the pose within the joint limits."""


class GripperArmSolver:
    """``TwoFingerGripperMotionPlanningSolver``'s interface, planned with SAPIEN's kinematics."""

    facts: GripperFacts  # set per robot by :func:`solver_class`
    # what kept the arm from its plans, one line per path, across the class's instances (the
    # solutions build their own solver: robospec.solve.episodes reads and clears it per episode)
    notes: list[str]

    def __init__(
        self,
        env: BaseEnv,  # as the solutions hand it (robospec.solve.solutions' view of one)
        debug: bool = False,
        vis: bool = False,
        base_pose: sapien.Pose | None = None,
        visualize_target_grasp_pose: bool = False,
        print_env_info: bool = False,
        joint_vel_limits: float = 0.9,
        joint_acc_limits: float = 0.9,
    ) -> None:
        self.env = env
        self.base_env = cast("BaseEnv", env.unwrapped)
        self.robot = self.base_env.agent.robot
        self.control_mode = self.base_env.control_mode
        # one value per dimension of the gripper's action (upstream's solvers: one number)
        self.OPEN: float | Sequence[float] = self.facts.open_action
        self.CLOSED: float | Sequence[float] = self.facts.closed_action
        self.gripper_state: float | Sequence[float] = self.OPEN
        self.elapsed_steps = 0
        self.velocity_limit = MPLIB_LIMIT * joint_vel_limits
        self.acceleration_limit = MPLIB_LIMIT * joint_acc_limits
        self.model = self.robot.create_pinocchio_model()  # (the CPU simulation's)
        self.tcp_index = self.facts.tcp_index
        self.arm = np.asarray(self.facts.arm_joints)
        self.limits = self.robot.get_qlimits()[0].cpu().numpy().astype(np.float64)

    # -- what the solutions call ---------------------------------------------------------------

    def move_to_pose_with_screw(
        self, pose: sapien.Pose | Pose, dry_run: bool = False, refine_steps: int = 0
    ):
        try:
            result = self.plan_screw(pose)
        except PlanFailed:
            return -1
        if dry_run:
            return result
        return self.follow_path(result, refine_steps)

    # no obstacles are ever added for the tasks robospec solves: the straight screw is the plan
    move_to_pose_with_RRTConnect = move_to_pose_with_screw
    move_to_pose_with_RRTStar = move_to_pose_with_screw

    def open_gripper(self, t: int = 6, gripper_state: float | Sequence[float] | None = None):
        return self._hold_gripper(self.OPEN if gripper_state is None else gripper_state, t)

    def close_gripper(self, t: int = 6, gripper_state: float | Sequence[float] | None = None):
        return self._hold_gripper(self.CLOSED if gripper_state is None else gripper_state, t)

    def add_box_collision(self, extents: np.ndarray, pose: sapien.Pose) -> None:
        raise NotImplementedError("robospec's planner plans no motion around obstacles")

    add_collision_pts = add_box_collision

    def clear_collisions(self) -> None:
        return None

    def render_wait(self) -> None:
        return None

    def close(self) -> None:
        return None

    # -- planning ------------------------------------------------------------------------------

    def plan_screw(self, pose: sapien.Pose | Pose) -> dict[str, np.ndarray]:
        """mplib's ``plan_screw``: joint positions of the arm along the screw from the tcp's
        pose now to ``pose`` (world frame, in the solutions' grasp frame), time-parametrised."""
        import sapien
        from mani_skill.utils.structs.pose import to_sapien_pose

        target = to_sapien_pose(pose) * self.facts.grasp_to_tcp
        base = self.robot.pose.sp
        goal = (base.inv() * target).to_transformation_matrix()
        qpos = self.robot.get_qpos()[0].cpu().numpy().astype(np.float64)
        self.model.compute_forward_kinematics(qpos)
        current = self.model.get_link_pose(self.tcp_index)
        assert isinstance(current, sapien.Pose)
        twist = _exp_coordinates(goal @ np.linalg.inv(current.to_transformation_matrix()))
        path = [qpos[self.arm].copy()]
        mask = np.zeros(len(qpos))
        mask[self.arm] = 1
        while True:
            self.model.compute_full_jacobian(qpos)
            jacobian = self.model.get_link_jacobian(self.tcp_index, local=False) * mask
            delta_q = np.linalg.pinv(jacobian) @ twist
            norm = np.linalg.norm(delta_q)
            if norm == 0:
                raise PlanFailed("the arm cannot move the tcp toward the pose")
            delta_q *= QPOS_STEP / norm
            delta_twist = jacobian @ delta_q
            last = np.linalg.norm(delta_twist) > np.linalg.norm(twist)
            if last:
                ratio = np.linalg.norm(twist) / np.linalg.norm(delta_twist)
                delta_q, delta_twist = delta_q * ratio, delta_twist * ratio
            qpos = qpos + delta_q
            twist = twist - delta_twist
            inside = np.all(qpos >= self.limits[:, 0] - LIMIT_TOLERANCE) and np.all(
                qpos <= self.limits[:, 1] + LIMIT_TOLERANCE
            )
            if np.linalg.norm(delta_twist) < 1e-4 or not inside or len(path) > MAX_SCREW_STEPS:
                raise PlanFailed("the screw leaves the joint limits or stalls")
            path.append(qpos[self.arm].copy())
            if last:
                return self._timed(np.vstack(path))

    def _timed(self, path: np.ndarray) -> dict[str, np.ndarray]:
        """mplib's ``TOPP``: TOPP-RA under the velocity and acceleration limits, sampled at the
        control step."""
        import toppra
        from toppra import algorithm, constraint

        toppra.setup_logging("WARNING")
        dof = path.shape[1]
        spline = toppra.SplineInterpolator(np.linspace(0, 1, len(path)), path)
        velocity = constraint.JointVelocityConstraint(np.full(dof, self.velocity_limit))
        acceleration = constraint.JointAccelerationConstraint(np.full(dof, self.acceleration_limit))
        instance = algorithm.TOPPRA(
            [velocity, acceleration], spline, parametrizer="ParametrizeConstAccel"
        )
        trajectory = instance.compute_trajectory()
        if trajectory is None:
            raise PlanFailed("the path cannot be timed within the limits")
        step = self.base_env.control_timestep
        times = np.linspace(0, trajectory.duration, int(trajectory.duration / step))
        return {
            "status": "Success",
            "time": times,
            "position": trajectory(times),
            "velocity": trajectory(times, 1),
            "acceleration": trajectory(times, 2),
            "duration": trajectory.duration,
        }

    # -- acting --------------------------------------------------------------------------------

    def follow_path(self, result: dict[str, np.ndarray], refine_steps: int = 0):
        positions = result["position"]
        velocities = result["velocity"]
        outcome = None
        for i in range(len(positions) + refine_steps):
            at = min(i, len(positions) - 1)
            velocity = velocities[at] if self.control_mode == "pd_joint_pos_vel" else None
            outcome = self._step(positions[at], velocity)
        self._check_followed(positions[-1])
        return outcome

    def _check_followed(self, planned: np.ndarray) -> None:
        """Note where the arm ended short of the path's end: the joint farthest off, and the
        robot's links pressing on each other (the planner checks no collisions)."""
        reached = self.robot.get_qpos()[0].cpu().numpy()[self.arm]
        off = np.abs(reached - planned)
        worst = int(np.argmax(off))
        if off[worst] <= FOLLOW_TOLERANCE:
            return
        joint = self.robot.active_joints[int(self.arm[worst])].name
        note = f"the arm did not follow its plan: {joint} ended {off[worst]:.2f} rad from it"
        touching = _self_contacts(self.base_env.scene, {link.name for link in self.robot.links})
        if touching:
            note += " (" + ", ".join(f"{a} pressed on {b}" for a, b in touching) + ")"
        self.notes.append(note)

    def _hold_gripper(self, state: float | Sequence[float], steps: int):
        self.gripper_state = state
        arm = self.robot.get_qpos()[0].cpu().numpy()[self.arm]
        outcome = None
        for _ in range(steps):
            zero = arm * 0 if self.control_mode == "pd_joint_pos_vel" else None
            outcome = self._step(arm, zero)
        return outcome

    def _step(self, arm: np.ndarray, velocity: np.ndarray | None):
        action = self.facts.action(arm, self.gripper_state, velocity)
        outcome = self.env.step(action)
        self.elapsed_steps += 1
        return outcome


def _self_contacts(scene: ManiSkillScene, links: set[str]) -> list[tuple[str, str]]:
    """Pairs of the robot's links pressing on each other now (a contact with an impulse)."""
    pairs: set[tuple[str, str]] = set()
    for contact in cast("PhysxCpuSystem", scene.px).get_contacts():  # (solve's: on the CPU)
        names = [body.entity.name for body in contact.bodies]
        if not all(name in links for name in names):
            continue
        if sum(float(np.linalg.norm(point.impulse)) for point in contact.points) > 1e-3:
            first, second = sorted(names)
            pairs.add((first, second))
    return sorted(pairs)


def _exp_coordinates(transform: np.ndarray) -> np.ndarray:
    """The twist (v, ω)·θ whose exponential is ``transform`` (mplib's pose2exp_coordinate)."""
    rotation = transform[:3, :3]
    trace = np.trace(rotation)
    if np.isclose(trace, 3):
        omega, theta = np.zeros(3), 1.0
    elif np.isclose(trace, -1):
        raise PlanFailed("the target is a half turn away: the screw is not unique")
    else:
        theta = float(np.arccos((trace - 1) / 2))
        omega = np.array(
            [
                rotation[2, 1] - rotation[1, 2],
                rotation[0, 2] - rotation[2, 0],
                rotation[1, 0] - rotation[0, 1],
            ]
        ) / (2 * np.sin(theta))
    skew = np.array([[0, -omega[2], omega[1]], [omega[2], 0, -omega[0]], [-omega[1], omega[0], 0]])
    inverse_left_jacobian = (
        np.eye(3) / theta - 0.5 * skew + (1.0 / theta - 0.5 / np.tan(theta / 2)) * skew @ skew
    )
    v = inverse_left_jacobian @ transform[:3, 3]
    return np.concatenate([v, omega]) * theta


def solver_class(facts: GripperFacts) -> type[GripperArmSolver]:
    """The solver for one robot: ``GripperArmSolver`` with its facts (the solutions construct
    the class themselves, with the environment as the only robot-specific argument)."""
    return type("RobospecSolver", (GripperArmSolver,), {"facts": facts, "notes": []})
