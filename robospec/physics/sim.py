"""One robot in one control mode, in a headless ManiSkill environment: the only place the physics
checks touch ManiSkill, SAPIEN and torch.

Everything a check reads comes back as numpy arrays shaped ``(num_envs, ...)``: one row on the
CPU, one row per parallel environment on ``physx_cuda``. Controllers are looked at through what
ManiSkill's own classes expose (``single_action_space``, ``active_joint_indices``, the mimic
controller's ``control_joint_indices``), so the checks see exactly what a task would drive; what
kind each is comes from its config's class (:mod:`robospec.model.controller_kinds`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

import numpy as np

from robospec.geometry import Vector
from robospec.maniskill.headless import headless_loading, make_empty_env
from robospec.model.controller_kinds import ControllerKind, kind_of_config
from robospec.resolve.resolved import ResolvedKeyframe

if TYPE_CHECKING:
    from gymnasium import spaces
    from mani_skill.agents.controllers.base_controller import BaseController
    from mani_skill.agents.controllers.pd_joint_pos import PDJointPosControllerConfig
    from mani_skill.agents.controllers.pd_joint_vel import PDJointVelControllerConfig
    from mani_skill.envs.tasks.empty_env import EmptyEnv
    from mani_skill.utils.structs import Articulation, Link, Pose
    from sapien.physx import PhysxGpuSystem
    from torch import Tensor

# m: how far a floating robot is lifted for a test stand (its root held there): clear of the
# ground of ManiSkill's scenes for any robot of a sensible size
TEST_STAND_HEIGHT = 5.0


@dataclass(frozen=True)
class Backend:
    """Where the checks run: ``physx_cpu`` with one environment, or ``physx_cuda`` with many."""

    sim_backend: str = "physx_cpu"
    num_envs: int = 1

    @property
    def gpu(self) -> bool:
        return self.sim_backend == "physx_cuda"


CPU = Backend()


@dataclass(frozen=True)
class ControllerGroup:
    """One controller of a mode, with where its action and its joints sit."""

    name: str  # the group in the mode (or the controller's name for a one-controller mode)
    controller: BaseController
    action_slice: slice
    joint_indices: tuple[int, ...]  # into the robot's active joints, in controller order

    @property
    def pd_config(self) -> PDJointPosControllerConfig | PDJointVelControllerConfig:
        """Its config as a PD controller's, by joint position or velocity (its damping, force
        limit, drive mode, normalize_action: ManiSkill's BaseController types it as any
        controller's)."""
        return cast(
            "PDJointPosControllerConfig | PDJointVelControllerConfig", self.controller.config
        )

    @property
    def controller_kind(self) -> ControllerKind | None:
        """Which kind its config is, or None for a config no spec can name."""
        return kind_of_config(type(self.controller.config).__name__)

    @property
    def kind(self) -> str:
        """``position``, ``velocity``, ``passive`` or ``other``: the drive targets it sets
        (an end effector's are joint positions too)."""
        kind = self.controller_kind
        if kind is None:
            return "other"
        if kind.sets_target_qpos:
            return "position"
        return "velocity" if kind.sets_target_qvel else "passive"

    @property
    def absolute_position(self) -> bool:
        """Whether its action is a joint-position target (``pd_joint_pos``, mimic, pos_vel)."""
        kind = self.controller_kind
        return (
            kind is not None
            and kind.joint_position_targets
            and not getattr(self.controller.config, "use_delta", False)
        )

    @property
    def with_velocities(self) -> bool:
        """Whether its action is joint positions followed by joint velocities
        (``pd_joint_pos_vel``)."""
        kind = self.controller_kind
        return kind is not None and kind.sets_target_qpos and kind.sets_target_qvel

    @property
    def action_joint_indices(self) -> tuple[int, ...]:
        """The robot joints its action dimensions stand for, one per dimension (joint
        controllers only): a mimic controller's action covers only its control joints."""
        control = getattr(self.controller, "control_joint_indices", None)
        if control is None:
            return self.joint_indices
        return tuple(self.joint_indices[int(i)] for i in control.cpu().numpy().reshape(-1))


class Sim:
    """A headless ``Empty-v1`` environment holding the robot ``uid`` in ``mode``."""

    def __init__(self, uid: str, mode: str, backend: Backend = CPU) -> None:
        self.uid = uid
        self.mode = mode
        self.backend = backend
        from robospec.output.register import sim_config_for

        # the robot as its spec means it to be simulated: the sim config it recommends
        self.env = make_empty_env(
            uid,
            mode,
            num_envs=backend.num_envs,
            sim_backend=backend.sim_backend,
            sim_config=sim_config_for(uid),
        )
        self.env.reset(seed=0)
        self._bind()

    def _bind(self) -> None:
        """Read what the checks use from the environment as (re)built."""
        self.base = cast("EmptyEnv", self.env.unwrapped)  # (Empty-v1's)
        self.agent = self.base.agent
        self.robot = self.agent.robot
        self.scene = self.base.scene
        self.joint_names: tuple[str, ...] = tuple(j.name for j in self.robot.get_active_joints())
        self.limits = self.robot.get_qlimits()[0].cpu().numpy().astype(np.float64)
        self.prismatic = np.array(
            [j.type[0] == "prismatic" for j in self.robot.get_active_joints()], dtype=bool
        )
        self.sim_freq: int = int(self.base.sim_freq)
        self.control_freq: int = int(self.base.control_freq)
        # what the loader made of it: ManiSkill's MJCF loader frees a root with a <freejoint>
        # whatever fix_root_link says
        self.fixed_root = has_fixed_root(self.robot)
        # the scene users get: Empty-v1's ground, whatever the robot (a fixed robot at the
        # origin that reaches through it meets it there too: robospec.physics.ground says so)
        self.ground = self.base.ground
        # the state the robot is loaded in: ``start(None)``. SAPIEN builds every joint at 0 (no
        # loader of ManiSkill's sets a qpos); the reset has since put a robospec agent at its
        # reset keyframe, so the joints are read as built, not as they are now
        self._loaded = (self.robot.get_qpos() * 0, self.robot.pose)
        self._used = False  # whether anything moved since the scene was built

    def _rebuild(self) -> None:
        """A new scene with the robot loaded afresh. Putting the robot back where it was is
        not enough: PhysX keeps the contact pairs of the last step (and the solver's state
        with them) across a teleport, so a measurement would depend on what ran before it —
        random actions on the Ability hand reached 531 rad/s from a fresh scene and 370 after
        a keyframe hold. Rebuilding costs about 30 ms once the process's long-lived objects are
        out of the garbage collector's way (``robospec.physics.worker`` freezes them)."""
        with headless_loading():
            self.env.reset(seed=0, options={"reconfigure": True})
        self._bind()

    def close(self) -> None:
        self.env.close()

    def __enter__(self) -> Sim:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- the mode's controllers ---------------------------------------------------------------

    def group(self, name: str) -> ControllerGroup:
        """The mode's controller group ``name``, of the scene as it is now (a rebuilt scene
        has new controllers)."""
        return next(g for g in self.groups() if g.name == name)

    def groups(self) -> list[ControllerGroup]:
        controller = self.agent.controller
        parts = getattr(controller, "controllers", None)
        items = list(parts.items()) if parts is not None else [(self.mode, controller)]
        index = {name: i for i, name in enumerate(self.joint_names)}
        groups = []
        start = 0
        for name, part in items:
            shape = part.single_action_space.shape
            assert shape is not None  # (a controller's action space: a Box)
            width = int(shape[0])
            joints = tuple(index[j.name] for j in part.joints)
            groups.append(ControllerGroup(name, part, slice(start, start + width), joints))
            start += width
        return groups

    @property
    def action_low(self) -> np.ndarray:
        return np.asarray(cast("spaces.Box", self.agent.single_action_space).low, dtype=np.float64)

    @property
    def action_high(self) -> np.ndarray:
        return np.asarray(cast("spaces.Box", self.agent.single_action_space).high, dtype=np.float64)

    def hold_action(self, qpos: np.ndarray) -> np.ndarray | None:
        """The action that commands ``qpos`` (all active joints), or None when some controller
        of the mode does not take absolute joint positions."""
        action = np.zeros(self.action_low.shape, dtype=np.float64)
        for group in self.groups():
            if not group.absolute_position:
                return None
            target = qpos[list(group.action_joint_indices)]
            if group.with_velocities:
                target = np.concatenate([target, np.zeros_like(target)])  # held: at rest
            if group.pd_config.normalize_action:
                low = group.controller.action_space_low.cpu().numpy()
                high = group.controller.action_space_high.cpu().numpy()
                span = np.where(high > low, high - low, 1.0)
                target = 2.0 * (target - low) / span - 1.0
            action[group.action_slice] = target
        return action

    # -- state ---------------------------------------------------------------------------------

    def start(self, keyframe: ResolvedKeyframe | None) -> np.ndarray:
        """Put the robot at ``keyframe`` (or as it was loaded), at rest, with the controller
        reset there, in a scene nothing has run in yet (on the CPU: see :meth:`_rebuild`);
        returns the qpos it starts from, shape ``(J,)``. Every measurement starts here, so
        none depends on which ran before it. On ``physx_cuda`` the scene is reused (building
        one there costs seconds)."""
        if self._used and not self.backend.gpu:
            self._rebuild()
        self._used = True
        if keyframe is not None:
            set_keyframe(self.robot, keyframe, self.backend.num_envs)
        else:
            # as loaded, but inside the joint limits: a robot SAPIEN loads outside them (qpos
            # 0 where 0 is not allowed) is pushed back hard on the first step, which says
            # nothing about its controllers
            qpos, pose = self._loaded
            limits = self.robot.get_qlimits()
            qpos = qpos.clamp(limits[..., 0], limits[..., 1])
            self.robot.pose = pose
            self.robot.set_qpos(qpos)
            self.robot.set_qvel(qpos * 0)
        self._sync()
        self.agent.controller.reset()
        return self.qpos()[0]

    def qpos(self) -> np.ndarray:
        return self.robot.get_qpos().cpu().numpy().astype(np.float64)

    def qvel(self) -> np.ndarray:
        return self.robot.get_qvel().cpu().numpy().astype(np.float64)

    def root_position(self) -> np.ndarray:
        return self.robot.pose.p.cpu().numpy().astype(np.float64)

    def gravity_off(self) -> bool:
        """Whether ManiSkill turned gravity off on every link of the robot: what its
        ``balance_passive_force`` (true unless a mode says otherwise) does."""
        return all(bool(np.all(np.asarray(link.disable_gravity))) for link in self.robot.links)

    def gravity_loads(self) -> dict[str, float]:
        """What gravity puts on each active joint where the robot is now (N m, or N): the force
        its drive must give just to hold still (SAPIEN's passive force, first environment);
        empty on the GPU, where SAPIEN does not compute it."""
        if self.backend.gpu:
            return {}
        forces = self.robot._objs[0].compute_passive_force(
            gravity=True, coriolis_and_centrifugal=False
        )
        values = np.asarray(forces, dtype=np.float64).reshape(-1)
        return dict(zip(self.joint_names, (float(v) for v in values), strict=False))

    def root_speed(self) -> np.ndarray:
        """How fast the robot as a whole moves: :func:`centre_of_mass_speed`."""
        return centre_of_mass_speed(self.robot, self.backend.num_envs)

    # -- stepping ------------------------------------------------------------------------------

    def step(self, action: np.ndarray, pin_root: Pose | None = None) -> None:
        """One control step through ManiSkill's own path (``env.step``); ``action`` is one
        action for every environment, or one row per environment. With ``pin_root`` (a pose),
        a floating root is put back there, at rest, before every physics step."""
        import torch

        batch = np.broadcast_to(action, (self.backend.num_envs, action.shape[-1]))
        tensor = torch.tensor(np.ascontiguousarray(batch), dtype=torch.float32)
        if pin_root is None:
            self.base.step(tensor)
            return
        self.agent.set_action(tensor)
        for _ in range(self.sim_freq // self.control_freq):
            self.agent.before_simulation_step()
            self.sim_step(pin_root)

    def hold_drive_targets(self) -> None:
        """Hold every joint where it is, below the controllers: position drives get the current
        qpos as their target, velocity drives zero."""
        qpos = self.robot.get_qpos()
        for group in self.groups():
            indices = list(group.joint_indices)
            if group.kind == "position":
                self._drive(group, qpos[:, indices])
            elif group.kind == "velocity":
                self._drive(group, qpos[:, indices] * 0)
        self._apply()

    def set_joint_targets(self, group: ControllerGroup, values: np.ndarray) -> None:
        """Set ``group``'s drive targets (positions or velocities) directly, shape ``(J_g,)``."""
        import torch

        targets = torch.tensor(
            np.broadcast_to(values, (self.backend.num_envs, len(values))).copy(),
            dtype=torch.float32,
            device=self.robot.get_qpos().device,
        )
        self._drive(group, targets)
        self._apply()

    def set_drive(
        self,
        group: ControllerGroup | str,
        stiffness: float | np.ndarray,
        damping: float | np.ndarray,
        force_limit: float | np.ndarray | None = None,
    ) -> None:
        """Give ``group``'s joints other drive gains on the live robot, without recompiling:
        one number for all of its joints or one per joint, in the group's joint order
        (:attr:`ControllerGroup.joint_indices`); ``force_limit`` None keeps the controller's.
        The drive mode (force or acceleration) stays the controller's. Applies to the scene
        as it is now: :meth:`start` builds a new one from the spec's gains, so set the drive
        after it (and before stepping)."""
        if isinstance(group, str):
            group = self.group(group)
        controller = group.controller
        config = group.pd_config
        n = len(controller.joints)
        limits = config.force_limit if force_limit is None else force_limit
        stiffness_ = np.broadcast_to(np.asarray(stiffness, dtype=np.float64), n)
        damping_ = np.broadcast_to(np.asarray(damping, dtype=np.float64), n)
        limits_ = np.broadcast_to(np.asarray(limits, dtype=np.float64), n)
        for i, joint in enumerate(controller.joints):
            mode = config.drive_mode if isinstance(config.drive_mode, str) else config.drive_mode[i]
            joint.set_drive_properties(
                float(stiffness_[i]), float(damping_[i]), force_limit=float(limits_[i]), mode=mode
            )
        self._apply()

    def mass_matrix(self, group: ControllerGroup | str) -> np.ndarray:
        """The joint-space mass matrix of ``group``'s joints (their block, armature on the
        diagonal) at the robot's configuration now, the root held. CPU only."""
        if isinstance(group, str):
            group = self.group(group)
        from sapien.physx import PhysxArticulation

        articulation = self.robot._objs[0]
        model = PhysxArticulation.create_pinocchio_model(articulation)
        qpos = self.robot.get_qpos()[0].cpu().numpy().astype(np.float64)
        mass = np.asarray(model.compute_generalized_mass_matrix(qpos), dtype=np.float64)
        joints = articulation.get_active_joints()
        armature = np.array([float(np.sum(j.armature)) for j in joints], dtype=np.float64)
        indices = list(group.joint_indices)
        block = mass[np.ix_(indices, indices)].copy()
        block[np.diag_indices_from(block)] += armature[indices]
        return block

    def inertia(self, group: ControllerGroup | str) -> np.ndarray:
        """Each of ``group``'s joints' effective inertia (kg m², or kg for a prismatic joint)
        at the robot's configuration now, with the root held and the other joints locked: the
        diagonal of the joint-space mass matrix plus the joint's armature. CPU only."""
        if isinstance(group, str):
            group = self.group(group)
        from sapien.physx import PhysxArticulation

        articulation = self.robot._objs[0]
        model = PhysxArticulation.create_pinocchio_model(articulation)
        qpos = self.robot.get_qpos()[0].cpu().numpy().astype(np.float64)
        mass = np.diag(np.asarray(model.compute_generalized_mass_matrix(qpos), dtype=np.float64))
        joints = articulation.get_active_joints()
        armature = np.array([float(np.sum(j.armature)) for j in joints], dtype=np.float64)
        indices = list(group.joint_indices)
        return mass[indices] + armature[indices]

    def _drive(self, group: ControllerGroup, targets: Tensor) -> None:
        controller = group.controller
        if group.kind == "position":
            self.robot.set_joint_drive_targets(
                targets, controller.joints, controller.active_joint_indices
            )
        else:
            self.robot.set_joint_drive_velocity_targets(
                targets, controller.joints, controller.active_joint_indices
            )

    def sim_step(self, pin_root: Pose | None = None) -> None:
        """One physics step with the drive targets as they are (no controller runs). With
        ``pin_root`` (a pose), a floating root is put back there, at rest, first."""
        if pin_root is not None:
            self.robot.pose = pin_root
            zero = self.robot.root_linear_velocity * 0
            self.robot.set_root_linear_velocity(zero)
            self.robot.set_root_angular_velocity(zero)
            self._apply()
        self.scene.step()
        if self.backend.gpu:
            self.scene._gpu_fetch_all()

    def solver_position_iterations(self) -> int:
        """The PhysX position iterations the robot is solved with now (as built: its scene
        config's)."""
        return int(self.robot._objs[0].get_solver_position_iterations())

    def set_solver_position_iterations(self, iterations: int) -> None:
        """Solve the robot with ``iterations`` PhysX position iterations from now on (what a
        scene config's ``solver_position_iterations`` gives it; ``start`` builds it afresh)."""
        for articulation in self.robot._objs:
            articulation.set_solver_position_iterations(iterations)

    def test_stand(self) -> Pose | None:
        """Put the robot on a test stand: lifted :data:`TEST_STAND_HEIGHT` clear of the ground
        (a mounted arm too: the floor it stands on would block half its motions); returns the
        pose to hold a floating root at (``pin_root``), None for a fixed one. Held where a
        keyframe stands it, a floating robot's feet would touch the ground while its root
        cannot give way, and the ground push on legs that no longer carry it (Solo-12's hind
        leg drifted 0.056 rad held so, not at all 5 m up)."""
        lifted = self.lifted_root(TEST_STAND_HEIGHT)
        return None if self.fixed_root else lifted

    def lifted_root(self, height: float) -> Pose:
        """The root's pose now, ``height`` metres higher, with the robot moved there."""
        from mani_skill.utils.structs.pose import Pose

        raw = self.robot.pose.raw_pose.clone()
        raw[..., 2] += height
        lifted = Pose.create(raw)
        self.robot.pose = lifted
        self._sync()
        return lifted

    @property
    def sim_dt(self) -> float:
        return 1.0 / self.sim_freq

    def _apply(self) -> None:
        if self.backend.gpu:
            self.scene._gpu_apply_all()

    def _sync(self) -> None:
        if self.backend.gpu:
            self.scene._gpu_apply_all()
            cast("PhysxGpuSystem", self.scene.px).gpu_update_articulation_kinematics()
            self.scene._gpu_fetch_all()

    # -- contacts ------------------------------------------------------------------------------

    def mounted_links(self) -> set[str]:
        """The links that cannot move: a fixed root and what is welded to it (no active joint
        between them). Empty for a floating robot."""
        if not self.fixed_root:
            return set()
        moving: set[str] = set()
        for joint in self.robot.get_active_joints():
            child = joint.child_link
            if child is not None:
                moving.add(child.name)
        # a link moves when an active joint lies on its path to the root
        mounted: set[str] = set()
        for link in self.robot.links:
            node: Link | None = link
            moves = False
            while node is not None:
                if node.name in moving:
                    moves = True
                    break
                parent = node.joint.parent_link if node.joint is not None else None
                node = parent
            if not moves:
                mounted.add(link.name)
        return mounted

    def moved_by(self, joint: str) -> set[str]:
        """The links ``joint`` moves: its child link and everything below it."""
        found = next((j for j in self.robot.get_active_joints() if j.name == joint), None)
        if found is None or found.child_link is None:
            return set()
        top = found.child_link.name
        moved = set()
        for link in self.robot.links:
            node: Link | None = link
            while node is not None:
                if node.name == top:
                    moved.add(link.name)
                    break
                node = node.joint.parent_link if node.joint is not None else None
        return moved

    def lowest_points(self) -> dict[str, float]:
        """Each link with collision shapes -> the height of its lowest point (m, world z; the
        ground is at 0), as the robot is now. CPU only."""
        found = {}
        for link in self.robot.links:
            body = link._objs[0]
            if body.collision_shapes:
                found[link.name] = float(body.compute_global_aabb_tight()[0][2])
        return found

    def shaped_links(self) -> set[str]:
        """The links with collision shapes (the only ones PhysX collides)."""
        return {link.name for link in self.robot.links if link._objs[0].collision_shapes}

    def hinge_axes(self) -> dict[str, tuple[Vector, Vector]]:
        """Each link that turns about its parent on a revolute joint -> the line it turns
        about, in the world as the robot is now: (a point on it, its direction); a PhysX joint
        turns about its frame's x axis. CPU only."""
        found = {}
        for link in self.robot.links:
            joint = link.joint
            if joint is None or not str(joint._objs[0].type).startswith("revolute"):
                continue
            matrix = joint._objs[0].get_global_pose().to_transformation_matrix()
            point = (float(matrix[0, 3]), float(matrix[1, 3]), float(matrix[2, 3]))
            found[link.name] = (
                point,
                (float(matrix[0, 0]), float(matrix[1, 0]), float(matrix[2, 0])),
            )
        return found

    def ground_contacts(self) -> list[tuple[str, Vector, float]]:
        """The robot's contacts with the ground now: (link, point, depth in m). CPU only."""
        links = {id(link._objs[0]): link.name for link in self.robot.links}
        ground = {id(body) for body in self.ground._bodies} if self.ground is not None else set()
        found = []
        for contact in self.scene.get_contacts():
            a, b = contact.bodies
            if id(a) in ground:
                a, b = b, a
            if id(b) not in ground or id(a) not in links:
                continue
            for point in contact.points:
                x, y, z = (float(v) for v in point.position)
                found.append((links[id(a)], (x, y, z), float(-point.separation)))
        return found

    def centre_of_mass(self) -> np.ndarray:
        """The robot's centre of mass now (world frame), shape (3,). CPU only."""
        total = 0.0
        weighted = np.zeros(3)
        for link in self.robot.links:
            body = link._objs[0]
            mass = float(body.mass)
            pose = body.entity_pose * body.cmass_local_pose
            weighted += mass * np.asarray(pose.p, dtype=np.float64)
            total += mass
        return weighted / total if total > 0 else weighted

    def self_contacts(self) -> dict[tuple[str, str], float]:
        """Pairs of the robot's links in contact now (CPU only): ``{(link_a, link_b): depth}``,
        the depth being the deepest penetration in metres — negative for a pair PhysX
        reports within its contact offset but apart by that much."""
        links = {id(link._objs[0]): link.name for link in self.robot.links}
        touching: dict[tuple[str, str], float] = {}
        for contact in self.scene.get_contacts():
            a, b = (links.get(id(body)) for body in contact.bodies)
            if a is None or b is None or a == b:
                continue
            if not contact.points:
                continue
            depth = max(-point.separation for point in contact.points)
            pair = (min(a, b), max(a, b))
            touching[pair] = max(touching.get(pair, -np.inf), float(depth))
        return touching


def has_fixed_root(robot: Articulation) -> bool:
    """Whether the loader fixed the robot's root (ManiSkill's MJCF loader frees a root with a
    ``<freejoint>`` whatever ``fix_root_link`` says): what the articulation says, not the spec."""
    return bool(robot._objs[0].root.joint.type == "fixed")


def centre_of_mass_speed(robot: Articulation, num_envs: int) -> np.ndarray:
    """How fast the robot (a ManiSkill articulation) as a whole moves: the speed of its centre
    of mass, one per environment. Not the root link's: ManiSkill's MJCF loader roots a
    free-jointed robot in a massless link at the world body's frame, which can lie far from
    the robot (the dm_control humanoid's, 1.5 m below its torso), and a robot turning in place
    swings it round fast (24 m/s while the humanoid's centre of mass moved at 1.7 m/s)."""
    total = None
    momentum = None
    for link in robot.links:
        mass = link.mass.reshape(-1, 1)  # (num_envs, 1)
        part = link.linear_velocity * mass  # the link's centre of mass's velocity
        momentum = part if momentum is None else momentum + part
        total = mass if total is None else total + mass
    if momentum is None or total is None:
        return np.zeros(num_envs)
    velocity = (momentum / total.clamp(min=1e-12)).cpu().numpy().astype(np.float64)
    return np.linalg.norm(velocity, axis=-1)


def set_keyframe(robot: Articulation, keyframe: ResolvedKeyframe, num_envs: int) -> None:
    """Put ManiSkill articulation ``robot`` (in ``num_envs`` environments) at ``keyframe``:
    its root pose, its qpos when given, and its qvel (zero when not given)."""
    import torch
    from mani_skill.utils.structs.pose import Pose

    robot.set_pose(
        Pose.create_from_pq(
            torch.tensor([keyframe.p] * num_envs, dtype=torch.float32),
            torch.tensor([keyframe.q] * num_envs, dtype=torch.float32),
        )
    )
    if keyframe.qpos is not None:
        robot.set_qpos(torch.tensor([keyframe.qpos] * num_envs, dtype=torch.float32))
    if keyframe.qvel is not None:
        robot.set_qvel(torch.tensor([keyframe.qvel] * num_envs, dtype=torch.float32))
    else:
        robot.set_qvel(robot.get_qvel() * 0)
