"""What ManiSkill's two-finger solutions need of a robot, read from the robot as loaded.

Upstream writes these by hand per robot (``PandaArmMotionPlanningSolver``: ``OPEN = 1``,
``CLOSED = -1``, ``MOVE_GROUP = "panda_hand_tcp"``, and a grasp frame the solutions assume: the
tcp's z along the fingers, its y across them). Here each comes from the spec's controllers and
the simulation:

- the arm: the ``pd_joint_pos`` controller whose joints carry the tcp (absolute positions, not
  normalised: the planned joint positions are its action); the gripper: the mode's controller
  whose joints move the fingers of the spec's grasp check (a passive controller, a closed
  linkage's joints that its loops move, takes no action and is none); any other controller of
  the mode (a gripper's motor horn that a mimic controller of the fingers leaves aside, a head)
  is held where the reset put its joints;
- OPEN and CLOSED: one value per dimension of the gripper controller's action, each an end of
  that dimension's range: the one that puts the fingers farther apart open (by the kinematics
  SAPIEN builds of the loaded robot, the mimic map included), so fingers whose joints have
  ranges of their own (ALOHA's, one sliding over [0.021, 0.057], the other over [-0.057,
  -0.021]) open and close together; a dimension that moves neither finger (the other hand's,
  in a controller of both) is held where the reset put it;
- the grasp frame, measured at the reset pose by the fingers' collision shapes: its origin
  where the fingers close (the middle of the moving fingers' shapes, open and closed), y the
  way the fingers part as they start to open (from finger 2 to finger 1), z from the hand (the
  link the fingers hang from) toward that middle; and the fixed transform from that frame to
  the tcp link's (a turn alone for ManiSkill's Panda, whose tcp sits there). The tcp link is
  planned at that offset, so a tcp that names the hand (a midpoint tcp binds ``agent.tcp`` to
  the fingers' parent) or a frame short of the fingertips still grasps between the fingers.

Anything that keeps the solver from driving the robot is a :class:`NotSolvable` with the
reason, before an episode runs.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from robospec.maniskill.reach import chain_up, moving_joints_above

if TYPE_CHECKING:
    import sapien
    from mani_skill.agents.base_agent import BaseAgent
    from mani_skill.agents.controllers.base_controller import BaseController, CombinedController
    from mani_skill.agents.controllers.pd_joint_pos import (
        PDJointPosController,
        PDJointPosControllerConfig,
        PDJointPosMimicController,
    )
    from mani_skill.utils.structs import Articulation, Link
    from sapien.physx import (
        PhysxCollisionShape,
        PhysxCollisionShapeConvexMesh,
        PhysxCollisionShapeTriangleMesh,
    )
    from sapien.wrapper.pinocchio_model import PinocchioModel
    from torch import Tensor

# m: how far short of the fingertips the grasp frame sits, along the fingers (ManiSkill's Panda:
# its tcp, panda_hand_tcp, 1 cm short of its fingers' tips)
TIP_MARGIN = 0.01
NUDGE = 0.05  # of the gripper's stroke: how far it opens from closed to see which way it parts
MODE = "pd_joint_pos"  # the mode ManiSkill's solutions act in (their StackCube asserts it)


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
    # the action: ("arm" | "gripper" | "held", width) in order; "held": a controller the solver
    # keeps where the reset put its joints (``hold``, their positions in the layout's order)
    layout: tuple[tuple[str, int], ...]
    # one value per dimension of the gripper controller's action
    open_action: tuple[float, ...]
    closed_action: tuple[float, ...]
    grasp_to_tcp: sapien.Pose  # the tcp link's pose in the solutions' grasp frame
    with_velocities: bool = False  # the arm takes positions and velocities (pd_joint_pos_vel)
    hold: tuple[float, ...] = ()

    def action(
        self, arm: np.ndarray, gripper: float | Sequence[float], velocity: np.ndarray | None
    ) -> np.ndarray:
        """The mode's action: the arm's joint positions (and velocities), the gripper's action
        (one value per dimension, or one value for all: a solution's ``gripper_state``), the
        held controllers' positions."""
        parts: list[np.ndarray] = []
        held = 0
        for role, width in self.layout:
            if role == "arm":
                parts.append(np.asarray(arm, dtype=np.float64))
                if self.with_velocities:
                    parts.append(np.zeros(len(arm)) if velocity is None else velocity)
            elif role == "held":
                parts.append(np.asarray(self.hold[held : held + width], dtype=np.float64))
                held += width
            else:
                parts.append(np.broadcast_to(np.asarray(gripper, dtype=np.float64), (width,)))
        return np.concatenate(parts)


@dataclass(frozen=True)
class Closing:
    """A closed loop of the spec: its two links, where they meet in each one's frame, and
    the joints of the cycle it closes."""

    links: tuple[str, str]
    points: tuple[tuple[float, ...], tuple[float, ...]]
    joints: tuple[str, ...]


class _Closed:
    """A gripper controller whose fingers move through closed loops: its targets leave the
    loops' other joints (passive, which the loops move) where they close the loops again, as
    the simulation does (the kinematics alone would leave them where the reset put them)."""

    def __init__(
        self,
        controller: PDJointPosController,
        model: PinocchioModel,
        robot: Articulation,
        loops: list[Closing],
    ) -> None:
        self._controller = controller
        self._model = model
        links = robot.links_map
        own = {j.name for j in controller.joints}
        names = [j.name for j in robot.active_joints]
        self._free = sorted(
            {names.index(j) for loop in loops for j in loop.joints if j in names and j not in own}
        )
        self._ends = [
            (links[a].index, np.asarray(pa), links[b].index, np.asarray(pb))
            for loop in loops
            for (a, b), (pa, pb) in [(loop.links, loop.points)]
        ]

    def __getattr__(self, name: str) -> Any:
        return getattr(self._controller, name)

    def close(self, qpos: np.ndarray) -> np.ndarray:
        from scipy.optimize import least_squares

        if not self._free:
            return qpos

        def gaps(free: np.ndarray) -> np.ndarray:
            q = qpos.copy()
            q[self._free] = free
            self._model.compute_forward_kinematics(q)
            out = []
            for a, pa, b, pb in self._ends:
                ta = self._model.get_link_pose(a).to_transformation_matrix()
                tb = self._model.get_link_pose(b).to_transformation_matrix()
                out.append(ta[:3, :3] @ pa + ta[:3, 3] - tb[:3, :3] @ pb - tb[:3, 3])
            return np.concatenate(out)

        # (SAPIEN's kinematics are float32: finite differences of 1e-3 rad, not 1e-8)
        found = least_squares(gaps, qpos[self._free], diff_step=1e-3, xtol=1e-9, ftol=1e-12)
        out = qpos.copy()
        out[self._free] = found.x
        return out


def _position_controllers(
    parts: Mapping[str, BaseController], arm_name: str, gripper_name: str
) -> tuple[PDJointPosController, PDJointPosController]:
    """The arm's and the gripper's controllers, each one that takes joint positions: the
    solutions plan positions, which a velocity or end-effector controller cannot take (and
    whose settings are not a joint-position controller's); the arm's absolute ones."""
    from mani_skill.agents.controllers.pd_joint_pos import PDJointPosController

    found = []
    for name in (arm_name, gripper_name):
        controller = parts[name]
        if not isinstance(controller, PDJointPosController):
            raise NotSolvable(
                f"{MODE}'s '{name}' controller is a {type(controller.config).__name__}: the "
                "planned joint positions cannot be its action",
                f"drive the arm and the gripper in {MODE} with pd_joint_pos controllers",
                "controllers",
            )
        found.append(controller)
    arm, positions = found
    if arm.config.use_delta or arm.config.normalize_action:
        raise NotSolvable(
            f"{MODE}'s arm controller '{arm_name}' takes "
            + ("joint deltas" if arm.config.use_delta else "normalised actions")
            + ": the planned joint positions cannot be its action",
            "use_delta: false and normalize_action: false for that controller",
            "controllers",
        )
    return arm, positions


def read_facts(
    agent: BaseAgent, finger_links: tuple[str, str], loops: tuple[Closing, ...] = ()
) -> GripperFacts:
    """The facts of ``agent`` as the environment has just reset it (``pd_joint_pos``);
    ``loops``: the spec's closed loops, each its two links."""
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
    parts = dict(cast("CombinedController", controller).controllers)  # a mode's: a dict of them
    links = robot.links_map
    fingers = [links[name] for name in finger_links]
    closing = [loop for loop in loops if set(loop.links) <= set(links)]
    arm_name, gripper_name = _arm_and_gripper(
        parts, tcp, fingers, [(links[a], links[b]) for a, b in (c.links for c in closing)]
    )
    arm, positions = _position_controllers(parts, arm_name, gripper_name)
    held = [n for n in parts if n not in (arm_name, gripper_name)]
    model = robot.create_pinocchio_model()  # (the CPU simulation's: its one articulation's)
    qpos = robot.get_qpos()[0].cpu().numpy().astype(np.float64)
    gripper = _Closed(positions, model, robot, closing) if closing else positions
    ends = _open_and_closed(model, qpos, gripper, fingers)
    if ends is None:
        raise NotSolvable(
            f"the gripper controller '{gripper_name}' does not move the fingers "
            f"{finger_links[0]} and {finger_links[1]} apart or together",
            "the grasp check's fingers must be the ones the gripper controller moves",
            "grasping",
        )
    open_action, closed_action = ends
    grasp, middle = _grasp_frame(
        model, robot, tcp, fingers, qpos, gripper, closed_action, open_action
    )
    tcp_pose = tcp.pose.sp.to_transformation_matrix()
    frame = np.eye(4)
    frame[:3, :3] = grasp
    frame[:3, 3] = middle
    turn = np.linalg.inv(frame) @ tcp_pose
    role = {arm_name: "arm", gripper_name: "gripper"}
    layout = tuple((role.get(name, "held"), _width(c)) for name, c in parts.items())
    hold: list[float] = []
    for name in held:
        hold += _holding(name, parts[name], qpos)
    return GripperFacts(
        tcp_index=robot.links.index(tcp),
        arm_joints=tuple(int(j.active_index[0]) for j in arm.joints),
        layout=layout,
        open_action=tuple(float(v) for v in open_action),
        closed_action=tuple(float(v) for v in closed_action),
        grasp_to_tcp=sapien.Pose(turn),
        hold=tuple(hold),
    )


def _arm_and_gripper(
    parts: dict[str, BaseController],
    tcp: Link,
    fingers: list[Link],
    loops: Sequence[tuple[Link, Link]] = (),
) -> tuple[str, str]:
    """The names of the mode's one arm controller, whose joints carry the tcp, and its one
    gripper controller, whose joints move the grasp check's fingers (which must have collision
    shapes: they close on the cube), directly or through a closed loop (``loops``: its two
    links): a finger on one side of a loop moves with the joints that carry the other side
    (gym-xarm's fingers hang from the outer knuckles, linkage joints, and the inner knuckles
    the gripper drives close the loops)."""
    carried = moving_joints_above(tcp)
    arms = [n for n, c in parts.items() if {j.name for j in c.joints} <= carried]
    shapeless = [link.name for link in fingers if not link._objs[0].collision_shapes]
    if shapeless:
        raise NotSolvable(
            f"the grasp check's finger {' and '.join(shapeless)} has no collision shape: "
            "nothing of it touches what the gripper closes on",
            "give the finger links <collision> geometry in the description",
            "grasping",
        )
    moving = moving_joints_above(fingers[0]) | moving_joints_above(fingers[1])
    above = {link.name for finger in fingers for link in chain_up(finger)}
    for first, second in loops:
        for this, other in ((first, second), (second, first)):
            if this.name in above:
                moving |= moving_joints_above(other)
    # (a passive controller takes no action: a closed linkage's joints, which its loop moves)
    grippers = [
        n
        for n in parts
        if n not in arms and {j.name for j in parts[n].joints} & moving and _width(parts[n]) > 0
    ]
    if len(arms) != 1 or len(grippers) != 1:
        raise NotSolvable(
            f"{MODE} has controllers {', '.join(parts)}: the solutions drive one arm, whose "
            "joints carry the tcp, and one gripper, whose joints move the grasp check's fingers",
            f"give {MODE} one arm controller and one gripper controller",
            "control_modes",
        )
    return arms[0], grippers[0]


def _width(controller: BaseController | _Closed) -> int:
    """How many values the controller's action takes (its space a Box: its shape is known)."""
    shape = controller.single_action_space.shape
    assert shape is not None
    return int(shape[0])


def _holding(name: str, controller: BaseController, qpos: np.ndarray) -> list[float]:
    """The action that keeps a controller that is neither the arm nor the gripper where the
    reset put it: its joints' positions for absolute positions; nothing to add (zeros) for
    deltas and velocities (a mobile base, a head by velocity)."""
    config = controller.config
    width = _width(controller)
    if getattr(config, "use_delta", True):  # deltas, or a velocity controller (no use_delta)
        return [0.0] * width
    config = cast("PDJointPosControllerConfig", config)  # a use_delta of False: joint positions
    joints = controller.active_joint_indices.cpu().numpy()
    if config.normalize_action or len(joints) != width:
        raise NotSolvable(
            f"{MODE}'s controller '{name}' (neither the arm nor the gripper) takes normalised "
            "or coupled positions: the solver cannot hold it where it is",
            "normalize_action: false for that controller, or leave it out of the mode",
            "controllers",
        )
    return [float(v) for v in qpos[joints]]


def _action_range(gripper: PDJointPosController | _Closed) -> tuple[np.ndarray, np.ndarray]:
    """The gripper controller's action range, one (low, high) per dimension: ±1 for a
    normalised action, else its bounds or (given as null) the limits of the joints its action
    sets, as ManiSkill's controller takes them (a mimic controller's: its leaders')."""
    width = _width(gripper)
    if gripper.config.normalize_action:
        return np.full(width, -1.0), np.full(width, 1.0)
    limits = np.asarray(gripper._get_joint_limits(), dtype=np.float64).reshape(-1, 2)
    return limits[:, 0].copy(), limits[:, 1].copy()


def _raw(gripper: PDJointPosController | _Closed, action: np.ndarray) -> np.ndarray:
    """The joint positions ``action`` sets (a normalised action scaled as ManiSkill scales it:
    -1 to the lower bound, 1 to the upper)."""
    if not gripper.config.normalize_action:
        return np.asarray(action, dtype=np.float64)
    limits = np.asarray(gripper._get_joint_limits(), dtype=np.float64).reshape(-1, 2)
    low, high = limits[:, 0], limits[:, 1]
    return low + (np.clip(action, -1, 1) + 1) / 2 * (high - low)


def _action_at(gripper: PDJointPosController | _Closed, qpos: np.ndarray) -> np.ndarray:
    """The action that keeps the gripper's joints where ``qpos`` has them, within its range."""
    joints = _action_joints(gripper)
    values = qpos[joints].astype(np.float64)
    if gripper.config.normalize_action:
        limits = np.asarray(gripper._get_joint_limits(), dtype=np.float64).reshape(-1, 2)
        low, high = limits[:, 0], limits[:, 1]
        span = np.where(high > low, high - low, 1.0)
        values = 2 * (values - low) / span - 1
    low, high = _action_range(gripper)
    return np.clip(values, low, high)


def _action_joints(gripper: PDJointPosController | _Closed) -> np.ndarray:
    """The active-joint indices (of the articulation) that the action's dimensions set, in
    order: every joint's, or a mimic controller's leaders'."""
    indices = gripper.active_joint_indices.cpu().numpy()
    leaders = getattr(gripper, "control_joint_indices", None)
    if leaders is not None and getattr(gripper, "mimic_joint_indices", None) is not None:
        return indices[leaders.cpu().numpy()]
    return indices


def _open_and_closed(
    model: PinocchioModel,
    qpos: np.ndarray,
    gripper: PDJointPosController | _Closed,
    fingers: list[Link],
) -> tuple[np.ndarray, np.ndarray] | None:
    """The gripper's open and closed actions, one value per dimension: for each dimension that
    moves the fingers, the end of its range that parts them most is open, the other closed (the
    other dimensions as the reset put them); None when no dimension moves them."""
    low, high = _action_range(gripper)
    rest = _action_at(gripper, qpos)
    opened, closed = rest.copy(), rest.copy()
    moved = False
    for d in range(len(rest)):
        spans = []
        for end in (low[d], high[d]):
            action = rest.copy()
            action[d] = end
            spans.append(_finger_span(model, qpos, gripper, action, fingers))
        if abs(spans[1] - spans[0]) < 1e-4:
            continue
        moved = True
        opened[d], closed[d] = (high[d], low[d]) if spans[1] > spans[0] else (low[d], high[d])
    if not moved:
        return None
    wide = _finger_span(model, qpos, gripper, opened, fingers)
    shut = _finger_span(model, qpos, gripper, closed, fingers)
    return (opened, closed) if wide - shut >= 1e-4 else None


def _gripper_qpos(
    qpos: np.ndarray, gripper: PDJointPosController | _Closed, action: np.ndarray
) -> np.ndarray:
    """The joint positions the gripper controller targets for ``action`` (one value per
    dimension), the mimic map's followers included; the other joints as in ``qpos``."""
    indices = gripper.active_joint_indices.cpu().numpy()
    raw = _raw(gripper, np.asarray(action, dtype=np.float64))
    targets = qpos[indices].astype(np.float64)
    followers = getattr(gripper, "mimic_joint_indices", None)
    if followers is not None:
        mimic = cast("PDJointPosMimicController | _Closed", gripper)
        targets[mimic.control_joint_indices.cpu().numpy()] = raw
        if len(followers):
            leaders = (
                cast("Tensor", mimic.mimic_control_joint_indices).cpu().numpy()
            )  # (a list at first)
            multiplier = mimic._multiplier.cpu().numpy()
            offset = mimic._offset.cpu().numpy()
            targets[followers.cpu().numpy()] = targets[leaders] * multiplier + offset
    else:
        targets[:] = raw
    out = qpos.copy()
    out[indices] = targets
    return gripper.close(out) if isinstance(gripper, _Closed) else out


def _finger_points(
    model: PinocchioModel, qpos: np.ndarray, fingers: list[Link]
) -> list[np.ndarray]:
    """Each finger's collision shapes' centre (the middle of the box round them), in the
    robot's base frame, at ``qpos``."""
    return [(p.min(axis=0) + p.max(axis=0)) / 2 for p in _finger_shapes(model, qpos, fingers)]


def _finger_shapes(
    model: PinocchioModel, qpos: np.ndarray, fingers: list[Link]
) -> list[np.ndarray]:
    """Each finger's collision shapes as points (a mesh's vertices, a primitive's centre), in
    the robot's base frame, at ``qpos``."""
    model.compute_forward_kinematics(qpos)
    out = []
    for link in fingers:
        pose = model.get_link_pose(link.index).to_transformation_matrix()
        local = _shape_points(link._objs[0].collision_shapes)
        out.append(local @ pose[:3, :3].T + pose[:3, 3])
    return out


def _shape_points(shapes: list[PhysxCollisionShape]) -> np.ndarray:
    """A link's collision shapes as points in its frame: a mesh's vertices (a mesh sits at its
    link's origin, often on the joint's axis: a jaw that turns about it would seem not to
    move), a primitive's centre."""
    points = []
    for shape in shapes:
        local = shape.local_pose.to_transformation_matrix()
        vertices = getattr(shape, "vertices", None)
        if vertices is not None and len(vertices):
            mesh = cast("PhysxCollisionShapeConvexMesh | PhysxCollisionShapeTriangleMesh", shape)
            scaled = np.asarray(vertices, dtype=np.float64) * np.asarray(mesh.scale)
            points.append(scaled @ local[:3, :3].T + local[:3, 3])
        else:
            points.append(local[None, :3, 3])
    return np.vstack(points) if points else np.zeros((1, 3))


def _finger_span(
    model: PinocchioModel,
    qpos: np.ndarray,
    gripper: PDJointPosController | _Closed,
    action: np.ndarray,
    fingers: list[Link],
) -> float:
    first, second = _finger_points(model, _gripper_qpos(qpos, gripper, action), fingers)
    return float(np.linalg.norm(first - second))


def _grasp_frame(
    model: PinocchioModel,
    robot: Articulation,
    tcp: Link,
    fingers: list[Link],
    qpos: np.ndarray,
    gripper: PDJointPosController | _Closed,
    closed_action: np.ndarray,
    open_action: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The solutions' grasp frame in the world (columns x, y, z) and its origin, where the
    fingers close: between them, the middle of the moving fingers' centres, open and closed (a
    fixed jaw does not move; the jaw that closes on it meets it at its closed end), and
    :data:`TIP_MARGIN` short of their tips along z. y: how the fingers part as they start to
    open from closed (from finger 2 to finger 1: a jaw that turns opens across the jaws,
    whatever its centres say); z: from the hand toward that middle."""
    nudged = closed_action + NUDGE * (open_action - closed_action)
    shut = _finger_points(model, _gripper_qpos(qpos, gripper, closed_action), fingers)
    wide = _finger_points(model, _gripper_qpos(qpos, gripper, open_action), fingers)
    parting = _finger_points(model, _gripper_qpos(qpos, gripper, nudged), fingers)
    base = robot.pose.sp.to_transformation_matrix()
    y = base[:3, :3] @ ((parting[0] - shut[0]) - (parting[1] - shut[1]))
    y /= np.linalg.norm(y)
    moving = [i for i in range(2) if np.linalg.norm(wide[i] - shut[i]) > 1e-6] or [0, 1]
    local = np.mean([(wide[i] + shut[i]) / 2 for i in moving], axis=0)
    middle = base[:3, :3] @ local + base[:3, 3]
    hand = fingers[0].joint.parent_link
    assert hand is not None  # a finger hangs from a link
    z = middle - hand.pose.sp.p
    z -= (z @ y) * y
    if np.linalg.norm(z) < 1e-6:
        z = tcp.pose.sp.p - hand.pose.sp.p
        z -= (z @ y) * y
    z /= np.linalg.norm(z)
    # along the fingers, as deep as the Panda's tcp sits: TIP_MARGIN short of their tips
    shapes = _finger_shapes(model, _gripper_qpos(qpos, gripper, open_action), fingers)
    reach = max(float(np.max((base[:3, :3] @ (p - local).T).T @ z)) for p in shapes)
    origin = middle + (reach - TIP_MARGIN) * z
    return np.stack([np.cross(y, z), y, z], axis=1), origin
