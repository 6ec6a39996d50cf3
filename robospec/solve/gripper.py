"""What ManiSkill's two-finger solutions need of a robot, read from the robot as loaded.

Upstream writes these by hand per robot (``PandaArmMotionPlanningSolver``: ``OPEN = 1``,
``CLOSED = -1``, ``MOVE_GROUP = "panda_hand_tcp"``, and a grasp frame the solutions assume: the
tcp's z along the fingers, its y across them). Here each comes from the spec's controllers and
the simulation:

- the arm: the ``pd_joint_pos`` controller whose joints carry the tcp (absolute positions, not
  normalised: the planned joint positions are its action); the gripper: the mode's other
  controller, whose joints move the fingers of the spec's grasp check;
- OPEN and CLOSED: the ends of the gripper controller's action range, the one that puts the
  fingers farther apart open (by the kinematics SAPIEN builds of the loaded robot, the mimic
  map included);
- the grasp frame: y from finger 2 to finger 1, z from the hand (the link both fingers hang
  from) toward them, both measured at the reset pose, and the fixed turn from that frame to
  the tcp link's (the identity for ManiSkill's Panda).

Anything that keeps the solver from driving the robot is a :class:`NotSolvable` with the
reason, before an episode runs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

MODE = "pd_joint_pos"  # the mode ManiSkill's solutions act in (their StackCube asserts it)
BETWEEN_MARGIN = 0.01  # m around the fingers' boxes where the tcp still counts as between them


class NotSolvable(Exception):
    """The solver cannot drive this robot: ``str()`` says why, ``hint`` what to change."""

    def __init__(self, message: str, hint: str, section: str = "tcp") -> None:
        super().__init__(message)
        self.hint = hint
        self.section = section  # the spec section at fault


@dataclass(frozen=True)
class GripperFacts:
    tcp_index: int  # the tcp link's index among the articulation's links
    arm_joints: tuple[int, ...]  # active-joint indices the arm controller drives, in its order
    layout: tuple[tuple[str, int], ...]  # the action: ("arm" | "gripper", width) in order
    open_action: float
    closed_action: float
    grasp_to_tcp: Any  # sapien.Pose: the tcp link's pose in the solutions' grasp frame
    with_velocities: bool = False  # the arm takes positions and velocities (pd_joint_pos_vel)

    def action(self, arm: np.ndarray, gripper: float, velocity: np.ndarray | None) -> np.ndarray:
        parts: list[np.ndarray] = []
        for role, width in self.layout:
            if role == "arm":
                parts.append(np.asarray(arm, dtype=np.float64))
                if self.with_velocities:
                    parts.append(np.zeros(len(arm)) if velocity is None else velocity)
            else:
                parts.append(np.full(width, gripper, dtype=np.float64))
        return np.concatenate(parts)


def read_facts(agent: Any, finger_links: tuple[str, str]) -> GripperFacts:
    """The facts of ``agent`` as the environment has just reset it (``pd_joint_pos``)."""
    import sapien

    robot = agent.robot
    tcp = getattr(agent, "tcp", None)
    if tcp is None or not hasattr(tcp, "joint"):
        raise NotSolvable(
            "the solutions move the tcp link (agent.tcp), and this spec's tcp is no link",
            "name a link as `tcp` (between the fingertips: `robospec new` writes one)",
        )
    controller = agent.controllers.get(MODE) if hasattr(agent, "controllers") else None
    if controller is None or agent.control_mode != MODE:
        raise NotSolvable(
            f"the solutions act in control mode {MODE}, which the spec does not offer",
            f"add a control mode {MODE} with absolute arm and gripper position controllers",
            "control_modes",
        )
    carried = _ancestor_joints(tcp)
    parts = dict(controller.controllers)
    arms = [n for n, c in parts.items() if {j.name for j in c.joints} <= carried]
    grippers = [n for n in parts if n not in arms]
    if len(arms) != 1 or len(grippers) != 1:
        raise NotSolvable(
            f"{MODE} has controllers {', '.join(parts)}: the solutions drive one arm, whose "
            "joints carry the tcp, and one gripper",
            f"give {MODE} exactly an arm controller and a gripper controller",
            "control_modes",
        )
    arm, gripper = parts[arms[0]], parts[grippers[0]]
    if arm.config.use_delta or arm.config.normalize_action:
        raise NotSolvable(
            f"{MODE}'s arm controller '{arms[0]}' takes "
            + ("joint deltas" if arm.config.use_delta else "normalised actions")
            + ": the planned joint positions cannot be its action",
            "use_delta: false and normalize_action: false for that controller",
            "controllers",
        )
    links = robot.links_map
    fingers = [links[name] for name in finger_links]
    model = robot._objs[0].create_pinocchio_model()
    qpos = robot.get_qpos()[0].cpu().numpy().astype(np.float64)
    ends = (-1.0, 1.0) if gripper.config.normalize_action else _raw_ends(gripper)
    spans = [_finger_span(model, qpos, gripper, end, fingers) for end in ends]
    if abs(spans[1] - spans[0]) < 1e-4:
        raise NotSolvable(
            f"the gripper controller '{grippers[0]}' does not move the fingers "
            f"{finger_links[0]} and {finger_links[1]} apart or together",
            "the grasp check's fingers must be the ones the gripper controller moves",
            "grasping",
        )
    open_action, closed_action = (ends[1], ends[0]) if spans[1] > spans[0] else ends
    _require_between(tcp, fingers)
    grasp = _grasp_rotation(model, robot, tcp, fingers, qpos, gripper, open_action)
    tcp_rotation = tcp.pose.sp.to_transformation_matrix()[:3, :3]
    turn = np.eye(4)
    turn[:3, :3] = grasp.T @ tcp_rotation
    layout = tuple(
        ("arm" if name == arms[0] else "gripper", int(c.single_action_space.shape[0]))
        for name, c in parts.items()
    )
    return GripperFacts(
        tcp_index=robot.links.index(tcp),
        arm_joints=tuple(int(j.active_index[0]) for j in arm.joints),
        layout=layout,
        open_action=float(open_action),
        closed_action=float(closed_action),
        grasp_to_tcp=sapien.Pose(turn),
    )


def _ancestor_joints(link: Any) -> set[str]:
    names = set()
    while link is not None and link.joint is not None:
        if link.joint.active_index is not None:
            names.add(link.joint.name)
        link = link.joint.parent_link
    return names


def _raw_ends(gripper: Any) -> tuple[float, float]:
    """The gripper controller's raw action range: its bounds, or (given as null) the limits of
    the joints its action sets, as ManiSkill's controller takes them."""
    limits = np.asarray(gripper._get_joint_limits(), dtype=np.float64).reshape(-1, 2)
    config = gripper.config
    low = limits[:, 0] if config.lower is None else np.atleast_1d(config.lower).astype(np.float64)
    high = limits[:, 1] if config.upper is None else np.atleast_1d(config.upper).astype(np.float64)
    if low.size != 1 and not (np.all(low == low[0]) and np.all(high == high[0])):
        raise NotSolvable(
            "the gripper controller's range differs between its joints: one action value "
            "cannot open or close it",
            "give the gripper controller one lower and one upper bound",
            "controllers",
        )
    return float(low[0]), float(high[0])


def _gripper_qpos(qpos: np.ndarray, gripper: Any, action: float) -> np.ndarray:
    """The joint positions the gripper controller targets for ``action``, the mimic map's
    followers included; the other joints as in ``qpos``."""
    config = gripper.config
    indices = gripper.active_joint_indices.cpu().numpy()
    if config.normalize_action:
        low, high = _raw_ends(gripper)
        raw = np.full(len(indices), low + (action + 1) / 2 * (high - low))
    else:
        raw = np.full(len(indices), float(action))
    targets = raw.copy()
    followers = getattr(gripper, "mimic_joint_indices", None)
    if followers is not None and len(followers):
        leaders = gripper.mimic_control_joint_indices.cpu().numpy()
        multiplier = gripper._multiplier.cpu().numpy()
        offset = gripper._offset.cpu().numpy()
        targets[followers.cpu().numpy()] = raw[leaders] * multiplier + offset
    out = qpos.copy()
    out[indices] = targets
    return out


def _finger_points(model: Any, qpos: np.ndarray, fingers: list[Any]) -> list[np.ndarray]:
    """Each finger's collision shapes' centre, in the robot's base frame, at ``qpos``."""
    model.compute_forward_kinematics(qpos)
    points = []
    for link in fingers:
        local = [s.local_pose.p for s in link._objs[0].collision_shapes] or [np.zeros(3)]
        pose = model.get_link_pose(link.index).to_transformation_matrix()
        centre = np.mean(np.asarray(local, dtype=np.float64), axis=0)
        points.append(pose[:3, :3] @ centre + pose[:3, 3])
    return points


def _finger_span(model: Any, qpos: np.ndarray, gripper: Any, action: float, fingers: list[Any]):
    first, second = _finger_points(model, _gripper_qpos(qpos, gripper, action), fingers)
    return float(np.linalg.norm(first - second))


def _grasp_rotation(
    model: Any,
    robot: Any,
    tcp: Any,
    fingers: list[Any],
    qpos: np.ndarray,
    gripper: Any,
    open_action: float,
) -> np.ndarray:
    """The solutions' grasp frame in the world (columns x, y, z), the gripper open."""
    first, second = _finger_points(model, _gripper_qpos(qpos, gripper, open_action), fingers)
    base = robot.pose.sp.to_transformation_matrix()
    y = base[:3, :3] @ (first - second)
    y /= np.linalg.norm(y)
    hand = fingers[0].joint.parent_link
    middle = base[:3, :3] @ ((first + second) / 2) + base[:3, 3]
    z = middle - hand.pose.sp.p
    z -= (z @ y) * y
    if np.linalg.norm(z) < 1e-6:
        z = tcp.pose.sp.p - hand.pose.sp.p
        z -= (z @ y) * y
    z /= np.linalg.norm(z)
    return np.stack([np.cross(y, z), y, z], axis=1)


def _require_between(tcp: Any, fingers: list[Any]) -> None:
    """The tcp lies in the box the fingers span (world frame, padded by BETWEEN_MARGIN)."""
    boxes = [link._objs[0].compute_global_aabb_tight() for link in fingers]
    low = np.min([box[0] for box in boxes], axis=0) - BETWEEN_MARGIN
    high = np.max([box[1] for box in boxes], axis=0) + BETWEEN_MARGIN
    p = tcp.pose.sp.p
    outside = np.maximum(low - p, 0) + np.maximum(p - high, 0)
    if np.any(outside > 0):
        raise NotSolvable(
            f"the tcp '{tcp.name}' lies {np.linalg.norm(outside) * 100:.1f} cm outside the box "
            "its fingers span: the solutions close the fingers where the tcp is",
            "put the tcp between the fingertips (`robospec new` writes a link there)",
        )
