"""An MJCF robot with ``loader: mujoco`` is, in ManiSkill, the robot MuJoCo compiles: each
link's mass, centre of mass and inertia are MuJoCo's (relative 1e-4), and its links stand where
MuJoCo puts its bodies at random joint values (1e-5 m, 1e-4 rad) — for the zoo's humanoid, for
public MJCF robots beyond ManiSkill's loader (dm_control's rodent, 65 bodies; gymnasium-
robotics' Shadow hand, included from its scene, with visual-only bodies and tendons; the Jaco
arm's meshes) and for a model of what the loader cannot load at all (a ball joint, a ghost body,
an ellipsoid, joints off their body's origin, a ``ref``; two arms of a scene, each its own body
tree). Each robot is registered from its spec
and built by ``gym.make`` in Empty-v1 (physx_cpu, no renderer), as a user's would be."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import MANISKILL_SPECS
from corpus import install_folder

from robospec.derive.mjcf_files import compiled_model

pytestmark = pytest.mark.maniskill

COMPILED = Path(__file__).parent / "data" / "mjcf" / "compiled"
MASS_RTOL = 1e-4
POSITION_ATOL = 1e-5  # m
ROTATION_ATOL = 1e-4  # rad (a rotation matrix entry's difference bounds the angle's)
INERTIA_FLOOR = 1e-12  # kg m^2: PhysX keeps no principal moment under it (the writer says so)

SPEC = """\
robospec: 1
uid: {uid}
description: {{mjcf: "{path}", loader: mujoco, sites: {sites}}}
loader: {{fix_root_link: {fixed}}}
groups: {{all: "*"}}
controllers:
  all: {{type: pd_joint_pos, joints: all, lower: null, upper: null, stiffness: 100,
         damping: 10, normalize_action: false}}
control_modes:
  pd_joint_pos: {{all: all}}
"""


def _public(distribution: str, path: str) -> Path:
    return install_folder(distribution) / path


ROBOTS = {
    # ManiSkill's own MJCF humanoid: its zoo spec, read with loader: mujoco (below)
    "zoo_humanoid": None,
    # 65 bodies: ManiSkill's loader stops at 32 (RS081)
    "dmc_rodent": ("dm-control", "dm_control/locomotion/walkers/assets/rodent.xml", False),
    # meshes, a 1e-9 kg body
    "dmc_jaco_arm": ("dm-control", "dm_control/third_party/kinova/jaco_arm.xml", True),
    # the robot included from its scene, visual-only bodies, tendons
    "gymr_shadow_hand": (
        "gymnasium-robotics",
        "gymnasium_robotics/envs/assets/hand/reach.xml",
        True,
    ),
    "ball_ghost": None,
    # two arms, each its own tree welded to the world, and a free cube: the robot is both arms
    "two_arms": None,
    # a joint's armature, which the URDF cannot say: the agent sets it through SAPIEN
    "turntable": None,
}


# the sites each robot's spec names (description.sites): links of their own, where MuJoCo puts
# the sites
SITES = {
    "dmc_jaco_arm": ["wristsite"],
    "dmc_rodent": ["sole_L", "head"],
    "gymr_shadow_hand": ["robot0:S_fftip", "robot0:S_thtip"],
}


def _spec(key: str, tmp_path: Path) -> tuple[Path, Path, str]:
    """The spec of robot ``key`` (written into ``tmp_path``), its MJCF and its uid."""
    uid = f"mj_{key}"
    if key == "zoo_humanoid":
        from robospec.resolve.paths import maniskill_assets_dir

        text = (MANISKILL_SPECS / "humanoid.yaml").read_text(encoding="utf-8")
        mjcf = '  mjcf: "{maniskill_assets}/robots/humanoid/humanoid.xml"\n'
        assert mjcf in text
        text = text.replace(mjcf, mjcf + "  loader: mujoco\n").replace("rs_humanoid", uid)
        spec = tmp_path / "humanoid.yaml"
        spec.write_text(text, encoding="utf-8")
        assets = maniskill_assets_dir()
        assert assets is not None
        return spec, assets / "robots" / "humanoid" / "humanoid.xml", uid
    if key in ("ball_ghost", "two_arms", "turntable"):
        path, fixed = COMPILED / f"{key}.xml", True
    else:
        distribution, inside, fixed = ROBOTS[key]  # type: ignore[misc]
        path = _public(distribution, inside)
    spec = tmp_path / f"{key}.yaml"
    spec.write_text(
        SPEC.format(
            uid=uid,
            path=path.as_posix(),
            fixed=str(fixed).lower(),
            sites=json.dumps(SITES.get(key, [])),
        ),
        encoding="utf-8",
    )
    return spec, path, uid


@pytest.fixture(params=sorted(ROBOTS), scope="module")
def built(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Any:
    """(ManiSkill's robot as built in Empty-v1, MuJoCo's compiled model of the same file)."""
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    import robospec

    spec, path, uid = _spec(request.param, tmp_path_factory.mktemp(request.param))
    robospec.register(spec)
    env = gym.make(
        "Empty-v1",
        robot_uids=uid,
        obs_mode="state",
        sim_backend="physx_cpu",
        render_backend="none",
    )
    env.reset(seed=0)
    model = compiled_model(path.read_bytes(), str(path))
    yield env.unwrapped.agent.robot, model, SITES.get(request.param, [])
    env.close()


def _body(model: Any, name: str) -> int:
    """The body a link is named after: by its name, or ``body<id>`` for an unnamed body; -1
    for an intermediate link (or MuJoCo's world)."""
    import mujoco

    found = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name))
    if found < 0 and name.startswith("body") and name[4:].isdigit():
        unnamed = int(name[4:])
        if unnamed < model.nbody and not mujoco.mj_id2name(
            model, mujoco.mjtObj.mjOBJ_BODY, unnamed
        ):
            return unnamed
    return found


def _matrix(quaternion: Any) -> np.ndarray:
    import mujoco

    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, np.asarray(quaternion, dtype=float))
    return out.reshape(3, 3)


def _bodies(robot: Any, model: Any) -> list[tuple[Any, int]]:
    """Each link that is a MuJoCo body (not an intermediate link of a joint), with its body."""
    found = [(link, _body(model, link.name)) for link in robot.links]
    return [(link, body) for link, body in found if body > 0]


def test_each_link_weighs_what_mujoco_compiles_with_its_centre_of_mass_and_inertia(
    built: Any,
) -> None:
    robot, model, _ = built
    bodies = _bodies(robot, model)
    # every body below the robot's root tree is a link (none left out, none merged)
    assert {b for _, b in bodies} >= {
        b for b in range(1, model.nbody) if model.body_rootid[b] == model.body_rootid[bodies[0][1]]
    }
    for link, body in bodies:
        component = link._objs[0]
        mass = float(model.body_mass[body])
        assert component.mass == pytest.approx(mass, rel=MASS_RTOL), link.name
        centre = np.asarray(component.cmass_local_pose.p, dtype=float)
        assert np.allclose(centre, model.body_ipos[body], atol=POSITION_ATOL), link.name
        turn = _matrix(component.cmass_local_pose.q)
        loaded = turn @ np.diag(np.asarray(component.inertia, dtype=float)) @ turn.T
        moments = np.maximum(model.body_inertia[body], INERTIA_FLOOR)
        expected = (
            _matrix(model.body_iquat[body]) @ np.diag(moments) @ _matrix(model.body_iquat[body]).T
        )
        scale = float(np.abs(expected).max())
        assert np.abs(loaded - expected).max() <= MASS_RTOL * scale, link.name


def test_links_stand_where_mujoco_puts_its_bodies_and_sites_at_random_joint_values(
    built: Any,
) -> None:
    import mujoco
    import torch

    robot, model, sites = built
    data = mujoco.MjData(model)
    joints = robot.active_joints
    limits = np.array([j.limits[0].cpu().numpy() for j in joints], dtype=float).reshape(-1, 2)
    lower, upper = np.maximum(limits[:, 0], -1.5), np.minimum(limits[:, 1], 1.5)
    bodies = _bodies(robot, model)
    root = robot.links[0]
    root_body = _body(model, root.name)
    rng = np.random.default_rng(0)
    for _ in range(3):
        values = rng.uniform(lower, upper)
        robot.set_qpos(torch.tensor(values[None], dtype=torch.float32))
        _place(mujoco, model, data, dict(zip([j.name for j in joints], values, strict=True)))
        world_root = _pose(data.xpos[root_body], data.xquat[root_body])
        if root_body < 0:  # the root link is MuJoCo's world
            world_root = np.eye(4)
        loaded_root = np.linalg.inv(_loaded(root))
        for link, body in bodies:
            loaded = loaded_root @ _loaded(link)
            expected = np.linalg.inv(world_root) @ _pose(data.xpos[body], data.xquat[body])
            assert np.abs(loaded[:3, 3] - expected[:3, 3]).max() <= POSITION_ATOL, link.name
            assert np.abs(loaded[:3, :3] - expected[:3, :3]).max() <= ROTATION_ATOL, link.name
        links = {link.name: link for link in robot.links}
        for name in sites:
            site = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name))
            expected = np.eye(4)
            expected[:3, :3] = data.site_xmat[site].reshape(3, 3)
            expected[:3, 3] = data.site_xpos[site]
            loaded = loaded_root @ _loaded(links[name])
            expected = np.linalg.inv(world_root) @ expected
            assert np.abs(loaded[:3, 3] - expected[:3, 3]).max() <= POSITION_ATOL, name
            assert np.abs(loaded[:3, :3] - expected[:3, :3]).max() <= ROTATION_ATOL, name


def _place(mujoco: Any, model: Any, data: Any, values: dict[str, float]) -> None:
    """MuJoCo's bodies at ManiSkill's joint ``values``: a hinge or slide at ``ref`` + value, a
    ball at the turns of its three hinges about x, then y, then z."""
    data.qpos[:] = model.qpos0
    for joint in range(model.njnt):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        address = int(model.jnt_qposadr[joint])
        kind = int(model.jnt_type[joint])
        if kind in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
            data.qpos[address] += values.get(name, 0.0)
        elif kind == int(mujoco.mjtJoint.mjJNT_BALL):
            turned = np.array([1.0, 0.0, 0.0, 0.0])
            for axis, suffix in enumerate("xyz"):
                unit, step, product = np.eye(3)[axis], np.zeros(4), np.zeros(4)
                mujoco.mju_axisAngle2Quat(step, unit, values[f"{name}_{suffix}"])
                mujoco.mju_mulQuat(product, turned, step)
                turned = product
            data.qpos[address : address + 4] = turned
    mujoco.mj_kinematics(model, data)


def _pose(position: Any, quaternion: Any) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = _matrix(quaternion)
    pose[:3, 3] = position
    return pose


def _loaded(link: Any) -> np.ndarray:
    return link.pose.to_transformation_matrix()[0].cpu().numpy().astype(float)


@pytest.mark.parametrize("built", ["ball_ghost"], indirect=True)
def test_a_ball_joint_is_three_hinges_and_a_ghost_body_keeps_its_mass_without_a_shape(
    built: Any,
) -> None:
    robot, _, _ = built
    names = [j.name for j in robot.active_joints]
    assert names[:3] == ["socket_x", "socket_y", "socket_z"]
    links = {link.name: link for link in robot.links}
    ghost = links["ghost"]._objs[0]
    assert ghost.mass == pytest.approx(0.2, rel=MASS_RTOL)
    assert ghost.collision_shapes == []  # contype="0" conaffinity="0": MuJoCo collides it never
    assert len(links["hand"]._objs[0].collision_shapes) == 2  # the mesh and the ellipsoid


@pytest.mark.parametrize("built", ["turntable"], indirect=True)
def test_a_joints_armature_is_set_and_spins_it_up_as_in_mujoco(built: Any) -> None:
    """The same torque, from rest, without drives or gravity about the axis: the turntable's
    speed after 0.1 s is MuJoCo's, whose joint-space inertia counts the armature (0.05) beside
    the arm's own (0.054); without it, the turntable would spin up nearly twice as fast."""
    import mujoco
    import torch

    robot, model, _ = built
    (joint,) = robot.active_joints
    assert float(joint._objs[0].armature[0]) == pytest.approx(0.05)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    inertia = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, inertia)
    assert inertia[0, 0] == pytest.approx(0.05 + 0.0535, rel=1e-2)
    torque, steps = 0.2, 50
    joint.set_drive_properties(0.0, 0.0)
    robot.set_qvel(torch.zeros((1, 1)))
    timestep = robot.scene.timestep
    for _ in range(steps):
        robot.set_qf(torch.tensor([[torque]]))
        robot.scene.step()
    speed = float(robot.get_qvel()[0, 0])
    expected = torque / inertia[0, 0] * steps * timestep
    assert speed == pytest.approx(expected, rel=0.02)
    assert abs(speed - torque / (inertia[0, 0] - 0.05) * steps * timestep) > 0.3 * expected
