"""Closed-linkage grippers as ``robospec new`` writes them, simulated in ManiSkill (issue 35's
proof): robosuite's Robotiq 2F-85 and 2F-140 (MJCF; their four-bars are cut into trees and
coupled by tendons, which ManiSkill does not load) are scaffolded with one loop per finger, and

- closing drives the pads together, each pad keeping its orientation to within 2° over the
  stroke and the two faces parallel to within 2° (a parallel gripper's pads);
- each loop's two anchor points stay within 1 mm of each other while it closes and under
  random actions.

A small MJCF four-bar (tests/data/new/fourbar.xml, not a parallelogram) shows the stated case:
its ``<connect>`` becomes the loop, and turning its crank turns its follower through it.

No public URDF of a Robotiq gripper is on this machine (ManiSkill's own Robotiq agents load
theirs from its asset download, which the corpus does not have).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

pytestmark = [
    pytest.mark.minutes,
    pytest.mark.maniskill,  # scaffolded, registered and closed in ManiSkill
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]

PARALLEL = math.radians(2.0)  # a pad's orientation over the stroke (issue 35)
CLOSED = 0.001  # m: a loop's two anchor points apart (issue 35)
SETTLE = 2.0  # s: for the gripper to reach a commanded opening
RANDOM_STEPS = 100

# the grippers, and the command that closes each: the file's own actuators' ctrlrange ends
# (finger_1, finger_2), which the scaffold's drivers are
GRIPPERS = {
    "rsu_robotiq_2f85": {"finger_joint": 0.8, "right_outer_knuckle_joint": 0.8},
    "rsu_robotiq_2f140": {"finger_joint": 0.7, "right_outer_knuckle_joint": -0.7},
}


@pytest.fixture(scope="module", params=sorted(GRIPPERS))
def gripper(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory):
    """(key, the spec new wrote, its compiled robot), registered."""
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    from corpus import BY_KEY, locate

    from robospec import register
    from robospec.authoring.commands import run_new
    from robospec.pipeline import compile_spec

    key = request.param
    spec = tmp_path_factory.mktemp(key) / f"{key}.yaml"
    result = run_new(locate(BY_KEY[key]), spec, None, force=False).write()
    assert not result.failed, result.diagnostics
    compiled = compile_spec(spec)
    assert compiled.robot is not None
    assert [d.format_text() for d in compiled.diagnostics if d.is_error] == []
    register(spec)
    return key, spec, compiled.robot


def _world(link, point) -> np.ndarray:
    import sapien

    raw = link.pose.raw_pose[0].cpu().numpy().astype(np.float64)
    return np.asarray((sapien.Pose(raw[:3], raw[3:]) * sapien.Pose(list(point))).p)


def _anchor_gaps(sim, robot) -> list[float]:
    links = sim.robot.links_map
    return [
        float(
            np.linalg.norm(
                _world(links[loop.links[0]], loop.poses[0][0])
                - _world(links[loop.links[1]], loop.poses[1][0])
            )
        )
        for loop in robot.loops
    ]


def _rotation(link, root) -> np.ndarray:
    """The link's orientation in the root link's frame (3x3)."""
    from scipy.spatial.transform import Rotation

    def matrix(entity) -> np.ndarray:
        w, x, y, z = entity.pose.raw_pose[0, 3:].cpu().numpy().astype(np.float64)
        return Rotation.from_quat([x, y, z, w]).as_matrix()

    return matrix(root).T @ matrix(link)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    cosine = (np.trace(a.T @ b) - 1.0) / 2.0
    return float(np.arccos(np.clip(cosine, -1.0, 1.0)))


def _pads(robot) -> tuple[str, str]:
    """The pads the scaffold's is_grasping reads: each loop's finger."""
    fingers = robot.grasping[0].fingers if robot.grasping else ()
    return tuple(f.link for f in fingers)  # type: ignore[return-value]


class _Run:
    """The gripper in ``pd_joint_pos``: commanded openings, watched every control step."""

    def __init__(self, sim, robot) -> None:
        self.sim, self.robot = sim, robot
        self.pads = [sim.robot.links_map[name] for name in _pads(robot)]
        self.root = sim.robot.root
        self.start = sim.start(robot.keyframes[0])
        self.reference = [_rotation(pad, self.root) for pad in self.pads]
        self.fingers = robot.grasping[0].fingers
        self.worst_turn = 0.0
        self.worst_gap = 0.0
        self.worst_facing = 0.0  # the two pads' faces: the angle between their normals

    def command(self, targets: dict[str, float], seconds: float = SETTLE) -> None:
        sim = self.sim
        action = np.zeros(sim.action_low.shape)  # the gripper's is the mode's only action
        group = sim.group("gripper")
        assert group.action_slice == slice(0, action.shape[0])
        names = [sim.joint_names[i] for i in group.action_joint_indices]
        action[group.action_slice] = [targets[n] for n in names]
        for _ in range(int(seconds * sim.control_freq)):
            sim.step(action)
            self.watch()

    def watch(self) -> None:
        turns = [
            _angle(ref, _rotation(pad, self.root))
            for ref, pad in zip(self.reference, self.pads, strict=True)
        ]
        self.worst_turn = max(self.worst_turn, *turns)
        # each pad's face normal: its opening axis (the scaffold's is_grasping), the two facing
        normals = [
            _rotation(pad, self.root)[:, finger.axis] * finger.sign
            for pad, finger in zip(self.pads, self.fingers, strict=True)
        ]
        cosine = float(np.clip(-np.dot(normals[0], normals[1]), -1.0, 1.0))
        self.worst_facing = max(self.worst_facing, math.acos(cosine))
        self.worst_gap = max(self.worst_gap, *_anchor_gaps(self.sim, self.robot))

    def pad_distance(self) -> float:
        return float(
            np.linalg.norm(_world(self.pads[0], (0, 0, 0)) - _world(self.pads[1], (0, 0, 0)))
        )


def test_closing_a_scaffolded_robotiq_drives_its_pads_together_parallel_with_its_loops_closed(
    gripper,
) -> None:
    from robospec.physics.sim import Sim

    key, _, robot = gripper
    closed = GRIPPERS[key]
    opened = dict.fromkeys(closed, 0.0)
    assert len(robot.loops) == 2 and len(_pads(robot)) == 2
    with Sim(robot.uid, "pd_joint_pos") as sim:
        run = _Run(sim, robot)
        run.command(opened)
        run.reference = [_rotation(pad, run.root) for pad in run.pads]
        wide = run.pad_distance()
        run.worst_turn = 0.0
        run.command(closed)
        shut = run.pad_distance()
        qpos = dict(zip(sim.joint_names, sim.qpos()[0], strict=True))
    print(
        f"{key}: pads {wide * 1000:.1f} mm apart open, {shut * 1000:.1f} mm closed; worst pad "
        f"turn {math.degrees(run.worst_turn):.3f} deg, faces "
        f"{math.degrees(run.worst_facing):.3f} deg off parallel; worst anchor gap "
        f"{run.worst_gap * 1000:.4f} mm; drivers at {[round(qpos[j], 3) for j in closed]}"
    )
    assert all(abs(qpos[j] - target) < 0.1 for j, target in closed.items()), qpos
    assert shut < wide - 0.02, (wide, shut)  # the pads came at least 2 cm closer
    assert run.worst_turn < PARALLEL, math.degrees(run.worst_turn)
    assert run.worst_facing < PARALLEL, math.degrees(run.worst_facing)
    assert run.worst_gap < CLOSED, run.worst_gap


def test_a_scaffolded_robotiqs_loops_stay_closed_under_random_actions(gripper) -> None:
    from robospec.physics.sim import Sim

    key, _, robot = gripper
    rng = np.random.default_rng(0)
    with Sim(robot.uid, "pd_joint_delta_pos") as sim:
        run = _Run(sim, robot)
        low, high = sim.action_low, sim.action_high
        for _ in range(RANDOM_STEPS):
            sim.step(rng.uniform(low, high))
            run.watch()
        assert np.isfinite(sim.qpos()).all()
    print(
        f"{key}: {RANDOM_STEPS} random steps: worst anchor gap {run.worst_gap * 1000:.4f} mm, "
        f"worst pad turn {math.degrees(run.worst_turn):.3f} deg"
    )
    assert run.worst_gap < CLOSED, run.worst_gap
    assert run.worst_turn < PARALLEL, math.degrees(run.worst_turn)


FOURBAR = ROOT / "tests" / "data" / "new" / "fourbar.xml"


def test_an_mjcf_connect_becomes_a_loop_that_turns_the_follower_with_the_crank(
    tmp_path: Path,
) -> None:
    from ruamel.yaml import YAML

    from robospec import register
    from robospec.authoring.commands import run_new
    from robospec.physics.sim import Sim
    from robospec.pipeline import compile_spec

    spec = tmp_path / "fourbar.yaml"
    result = run_new(FOURBAR, spec, None, force=False).write()
    assert not result.failed, result.diagnostics
    data = YAML(typ="safe").load(spec.read_text())
    (loop,) = data["loops"].values()
    # the connect's anchor on the follower; on the coupler, where that point is at rest
    assert loop["links"] == ["follower", "coupler"]
    assert np.allclose(loop["at"], [[0, 0, 0.07], [0.06, 0, 0.02]], atol=1e-6)
    assert data["groups"]["gripper"] == ["crank_joint"]  # the actuated joint drives it
    compiled = compile_spec(spec)
    assert compiled.robot is not None
    register(spec)
    robot = compiled.robot
    with Sim(robot.uid, "pd_joint_pos") as sim:
        sim.start(robot.keyframes[0])
        worst = 0.0
        for target in (0.4, -0.4):
            for _ in range(int(SETTLE * sim.control_freq)):
                sim.step(np.array([target]))
                worst = max(worst, *_anchor_gaps(sim, robot))
            qpos = dict(zip(sim.joint_names, sim.qpos()[0], strict=True))
            assert abs(qpos["crank_joint"] - target) < 0.05, qpos
            # a four-bar's follower turns the crank's way (no drive of its own moves it)
            assert np.sign(qpos["follower_joint"]) == np.sign(target), qpos
            assert abs(qpos["follower_joint"]) > 0.1, qpos
    print(f"fourbar: worst anchor gap {worst * 1000:.4f} mm")
    assert worst < CLOSED, worst


CUBE = 0.02  # m: half the cube's side (PickCube-v1's)
HELD = 0.005  # m: how far the held cube may sink in two seconds (free, it falls 20 m)


def _cube_scene():
    """ManiSkill's empty scene with a cube (registered once)."""
    import sapien
    from mani_skill.envs.tasks.empty_env import EmptyEnv
    from mani_skill.utils.building import actors
    from mani_skill.utils.registration import REGISTERED_ENVS, register_env

    name = "RobospecCubeBetweenPads-v1"
    if name not in REGISTERED_ENVS:

        @register_env(name, max_episode_steps=1000)
        class CubeBetweenPads(EmptyEnv):
            def _load_scene(self, options: dict) -> None:
                super()._load_scene(options)
                self.cube = actors.build_cube(
                    self.scene,
                    half_size=CUBE,
                    color=[1, 0, 0, 1],
                    name="cube",
                    initial_pose=sapien.Pose([0, 0, 2]),
                )

    return name


def test_a_scaffolded_robotiq_closed_on_a_cube_holds_it_against_gravity(gripper) -> None:
    import gymnasium as gym
    import sapien
    import torch

    from robospec.maniskill.headless import headless_loading
    from robospec.output.register import sim_config_for

    key, _, robot = gripper
    closed = GRIPPERS[key]
    with headless_loading():
        env = gym.make(
            _cube_scene(),
            robot_uids=robot.uid,
            obs_mode="state",
            render_backend="none",
            control_mode="pd_joint_pos",
            sim_config=sim_config_for(robot.uid),
        )
    try:
        env.reset(seed=0)
        base = env.unwrapped
        agent, cube = base.agent, base.cube
        rest = robot.keyframes[0]  # mounted where its keyframe says (the 2F-140: 0.3 m up)
        agent.robot.set_pose(sapien.Pose(list(rest.p), list(rest.q)))
        names = [j.name for j in agent.controller.controllers["gripper"].joints]
        opened = np.zeros(len(names))
        for _ in range(base.control_freq):  # open, at the reset keyframe
            env.step(opened)
        # the cube at the tcp (between the pads), weightless while the pads close on it
        tcp = agent.tcp.pose.raw_pose[0].cpu().numpy().astype(np.float64)
        cube.set_pose(sapien.Pose(tcp[:3]))
        body = cube._bodies[0]
        body.disable_gravity = True
        shut = np.array([closed[n] for n in names])
        for _ in range(base.control_freq):
            env.step(shut)
        grasped = bool(agent.is_grasping(cube)[0])
        body.disable_gravity = False
        start = cube.pose.p[0].cpu().numpy().astype(np.float64)
        for _ in range(2 * base.control_freq):
            env.step(shut)
        end = cube.pose.p[0].cpu().numpy().astype(np.float64)
        still = bool(agent.is_grasping(cube)[0])
        assert torch.isfinite(agent.robot.get_qpos()).all()
    finally:
        env.close()
    sunk = float(start[2] - end[2])
    print(f"{key}: cube sank {sunk * 1000:.3f} mm in 2 s; is_grasping {grasped}, then {still}")
    assert sunk < HELD, sunk
    assert np.linalg.norm(end[:2] - start[:2]) < HELD, (start, end)
    assert grasped and still


def test_an_arms_parallelogram_gripper_gets_loops_and_the_solver_iterations_they_need(
    tmp_path: Path,
) -> None:
    """pybullet's xArm6 with its gripper: its <mimic> tags turn the cut parallelograms' joints
    at their own rates, and new still closes them (followers passive, the loops shape the
    fingers); whipped about on the arm, the loops open past half of check's max_gap at
    ManiSkill's 15 solver iterations, and the scaffold recommends as many as keep them
    within it."""
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    from corpus import BY_KEY, locate
    from mani_skill.utils.structs.types import SceneConfig

    from robospec import register
    from robospec.authoring.commands import run_new
    from robospec.authoring.new.refinement import LOOP_SHARE, loop_gap
    from robospec.physics.sim import Sim
    from robospec.pipeline import compile_spec

    spec = tmp_path / "xarm6_gripper.yaml"
    result = run_new(locate(BY_KEY["pb_xarm6_gripper"]), spec, None, force=False).write()
    assert not result.failed, result.diagnostics
    compiled = compile_spec(spec)
    robot = compiled.robot
    assert robot is not None and compiled.context is not None
    assert sorted(loop.links for loop in robot.loops) == [
        ("left_inner_knuckle", "left_finger"),
        ("right_inner_knuckle", "right_finger"),
    ]
    recommended = robot.simulation.solver_position_iterations
    scene_iterations = SceneConfig().solver_position_iterations  # ManiSkill's scenes' (15)
    assert recommended is not None and recommended > scene_iterations
    register(spec)
    checks = compiled.context.spec.checks
    limit = LOOP_SHARE * float(checks.loops.max_gap)
    rest = next(k for k in robot.keyframes if k.name == "rest")
    with Sim(robot.uid, robot.modes[0].name) as sim:
        gains: dict[str, tuple[float, float, float]] = {}  # the spec's own, as written
        at_default = loop_gap(sim, checks, rest, robot.loops, gains, scene_iterations)
        at_recommended = loop_gap(sim, checks, rest, robot.loops, gains, recommended)
    assert at_default > limit, at_default
    assert at_recommended <= limit, at_recommended
