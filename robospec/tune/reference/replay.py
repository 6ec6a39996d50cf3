"""Play a reference's commanded targets to the robot in ManiSkill, with candidate drive
parameters, and read back its joint positions at the reference's sample times.

The targets go to the joints' drives directly, below the controllers (as ``check``'s step
response does): a recording's targets are joint positions, whatever a control mode's action
would be. Each target holds from its sample until the next (what a controller sends); the robot
starts at the first measured positions, at rest; joints the reference does not name hold where
they start. A floating robot is held by its root, lifted clear of the floor, as in ``check``.

A replay puts the robot back in the same state and steps it again; it does not rebuild the
scene (30 ms or more, against about as much for the replay itself): a robot held in the air
touches nothing, so PhysX carries no contact state from one replay to the next, and the same
parameters give bit-identical positions (the fit's finite differences rely on it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robospec.physics.sim import ControllerGroup, Sim
from robospec.resolve.resolved import ResolvedKeyframe
from robospec.tune.reference.trajectory import Reference


@dataclass(frozen=True)
class Drives:
    """Drive parameters of the reference's joints, in its joint order."""

    stiffness: np.ndarray
    damping: np.ndarray
    friction: np.ndarray


@dataclass(frozen=True)
class Slot:
    """Where a reference joint sits: its group, its index in the group's joints, and its index
    among the robot's active joints."""

    group: str
    member: int
    joint: int


class Replay:
    def __init__(self, sim: Sim, reference: Reference, keyframe: ResolvedKeyframe | None) -> None:
        self.sim = sim
        self.reference = reference
        sim.start(keyframe)
        groups = {g.name: g for g in sim.groups() if g.kind == "position"}
        self.slots: list[Slot] = []
        for name in reference.joints:
            joint = sim.joint_names.index(name)
            group = next(g for g in groups.values() if joint in g.joint_indices)
            self.slots.append(Slot(group.name, group.joint_indices.index(joint), joint))
        self.groups = [g for g in groups.values() if any(s.group == g.name for s in self.slots)]
        sim.hold_drive_targets()
        self.pin = sim.test_stand()
        self.pose = sim.robot.pose
        qpos = sim.robot.get_qpos().clone()
        for k, slot in enumerate(self.slots):
            qpos[:, slot.joint] = float(reference.qpos[0, k])
        self.qpos = qpos
        # what each group's drives hold before any target is sent: where its joints start
        self.hold = {g.name: qpos[0, list(g.joint_indices)].cpu().numpy() for g in self.groups}
        self.spec_drives = self._read_drives()
        # the physics steps: step k runs from t0 + k dt to t0 + (k + 1) dt with the target of
        # the last sample at or before its start
        dt = sim.sim_dt
        self.n_steps = int(np.ceil(reference.duration / dt - 1e-9))
        starts = reference.t[0] + np.arange(self.n_steps) * dt
        sample = np.searchsorted(reference.t, starts + 1e-9, side="right") - 1
        self.step_targets = reference.target[np.clip(sample, 0, None)]
        # steps whose target is new: only then are the drives told
        self.changes = np.r_[True, np.any(np.diff(self.step_targets, axis=0) != 0, axis=1)]
        self.times = reference.t[0] + np.arange(self.n_steps + 1) * dt

    def _group(self, name: str) -> ControllerGroup:
        return next(g for g in self.groups if g.name == name)

    def _read_drives(self) -> Drives:
        """The drive parameters the spec's controllers give the reference's joints."""
        values = np.zeros((3, len(self.slots)))
        for k, slot in enumerate(self.slots):
            joint = self._group(slot.group).controller.joints[slot.member]
            physx = joint._objs[0]
            values[:, k] = (physx.stiffness, physx.damping, physx.friction)
        return Drives(*values)

    def inertia(self) -> np.ndarray:
        """Each reference joint's effective inertia where the replay starts."""
        self.sim.robot.set_qpos(self.qpos)
        out = np.empty(len(self.slots))
        for group in self.groups:
            values = self.sim.inertia(group)
            for k, slot in enumerate(self.slots):
                if slot.group == group.name:
                    out[k] = values[slot.member]
        return out

    def run(self, drives: Drives) -> np.ndarray:
        """The joints' positions at the reference's sample times, (T, J), with ``drives``."""
        sim, robot = self.sim, self.sim.robot
        robot.pose = self.pose  # (what set_pose does: it takes a batched Pose too)
        robot.set_qpos(self.qpos)
        robot.set_qvel(self.qpos * 0)
        for group in self.groups:
            stiffness = _per_joint(group, self.slots, drives.stiffness, "stiffness")
            damping = _per_joint(group, self.slots, drives.damping, "damping")
            sim.set_drive(group, stiffness, damping)
            friction = _per_joint(group, self.slots, drives.friction, "friction")
            for joint, value in zip(group.controller.joints, friction, strict=True):
                joint.set_friction(float(value))
        # PhysX's own objects, not ManiSkill's batched wrappers: a replay is thousands of
        # steps, and the torch round trips cost more than the physics (CPU only, one env)
        articulation = robot._objs[0]
        for group in self.groups:
            for joint, value in zip(group.controller.joints, self.hold[group.name], strict=True):
                joint._objs[0].set_drive_target(float(value))
        drives_of = [self._group(s.group).controller.joints[s.member]._objs[0] for s in self.slots]
        trace = np.empty((self.n_steps + 1, len(self.slots)))
        index = [s.joint for s in self.slots]
        trace[0] = articulation.get_qpos()[index]
        for step in range(self.n_steps):
            if self.changes[step]:
                for drive, value in zip(drives_of, self.step_targets[step], strict=True):
                    drive.set_drive_target(float(value))
            sim.sim_step(self.pin)
            trace[step + 1] = articulation.get_qpos()[index]
        # the samples fall between physics steps: read them off the trace, linearly
        return np.stack(
            [np.interp(self.reference.t, self.times, trace[:, k]) for k in range(len(index))],
            axis=1,
        )


def _per_joint(
    group: ControllerGroup, slots: list[Slot], values: np.ndarray, attribute: str
) -> np.ndarray:
    """``group``'s joints' values: the reference's where it names the joint, else the value
    the drive has now."""
    out = np.array(
        [float(getattr(j._objs[0], attribute)) for j in group.controller.joints], dtype=np.float64
    )
    for k, slot in enumerate(slots):
        if slot.group == group.name:
            out[slot.member] = values[k]
    return out
