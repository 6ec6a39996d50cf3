"""Composed robots (``parts:``) loaded and simulated in ManiSkill, against the hand-made
combinations of the same two descriptions.

- ``specs/composed/xarm7_ability.yaml`` (xarm7.urdf + the Ability hand's spec) against
  ManiSkill's own ``xarm7_ability``: the same active joints in the same order, the same links at
  the same poses at random configurations, the same masses and inertias, and rollouts
  bit-identical in every control mode. Upstream's modes all go NaN on the CPU (the hand's URDF
  ``<mimic>`` joints, RS309), and so do the composed robot's, step for step; with the mimic tags
  taken out of both (the hand's ``mend: {mimic: controller}``, a stripped copy of upstream's
  file) every mode runs, still bit-identical.
- The QUT Panda arm and the Franka hand of rtb-data (the corpus) against rtb-data's own
  ``panda_arm_hand`` combination: bit-identical rollouts, and ``PickCube-v1`` headless.
- The dm_control Jaco arm and hand (MJCF), loaded with finite state.
- ``robospec check`` says where a part sits inside the robot (RS734).
"""

from __future__ import annotations

import importlib
import os
import re
import shutil
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

pytestmark = [
    pytest.mark.minutes,
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore:__array_wrap__ must accept context:DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
]
pytest.importorskip("mani_skill")

import numpy as np  # noqa: E402
import torch  # noqa: E402
from conftest import MANISKILL_VERSION, SPECS, maniskill_assets  # noqa: E402
from corpus import BY_KEY, locate  # noqa: E402
from maniskill_compare import make_env, random_actions, rollout, upstream_start  # noqa: E402

import robospec  # noqa: E402

COMPOSED = SPECS / "composed"
MODES = ("pd_joint_delta_pos", "pd_joint_pos", "pd_ee_delta_pose", "pd_ee_target_delta_pose")
SEED = 25
STEPS = 30


@contextmanager
def registered(folder: Path, cache: Path, *classes: type) -> Iterator[dict[str, type]]:
    """``robospec.register`` the specs in ``folder`` (and register ``classes``, ManiSkill agent
    classes of the test's own); everything leaves ManiSkill's registry on exit."""
    from mani_skill.agents.registration import register_agent

    registry = importlib.import_module("mani_skill.agents.registration").REGISTERED_AGENTS
    before = set(registry)
    for cls in classes:
        register_agent()(cls)
    agents = robospec.register(str(folder), cache_dir=cache)
    try:
        yield agents
    finally:
        for uid in set(registry) - before:
            registry.pop(uid)
        for cls in agents.values():  # the generated modules, imported from robospec's cache
            sys.modules.pop(cls.__module__, None)


def _same_rollouts(ours: str, theirs: str, mode: str) -> tuple[torch.Tensor, torch.Tensor]:
    """Both robots' rollouts under the same random actions, checked bit-identical (NaN equal
    to NaN); the qpos are returned."""
    a, b = make_env(ours, mode), make_env(theirs, mode)
    try:
        actions = random_actions(b.action_space, SEED, STEPS)
        assert a.action_space.shape == b.action_space.shape
        start = upstream_start(b, SEED)  # where ManiSkill's own agent starts
        qa, va = rollout(a, actions, SEED, start)
        qb, vb = rollout(b, actions, SEED, start)
    finally:
        a.close()
        b.close()
    for x, y in ((qa, qb), (va, vb)):
        assert torch.equal(torch.isnan(x), torch.isnan(y))
        assert torch.equal(torch.nan_to_num(x), torch.nan_to_num(y))
    return qa, qb


# -- xarm7_ability ---------------------------------------------------------------------------------


# specs/composed reproduces ManiSkill 3.0.1's end-effector controller, whose arguments upstream
# passes by position one place off (stiffness 0.1, ...); the nightly names them
# (tests/test_equivalence.py, UPSTREAM_FIXES): on the nightly the spec is compared with them
SHIFTED = "stiffness: 0.1,\n     damping: 1e3, force_limit: 1e2, friction: 500,"
NAMED = (
    "rot_lower: -0.1, rot_upper: 0.1, stiffness: 1e3,\n"
    "     damping: 1e2, force_limit: 500, friction: 0.0,"
)


def _arm_text() -> str:
    text = (COMPOSED / "xarm7_ability.yaml").read_text()
    assert SHIFTED in text
    return text.replace(SHIFTED, NAMED) if MANISKILL_VERSION == "nightly" else text


@pytest.fixture(scope="module")
def xarm7(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, type]]:
    folder = tmp_path_factory.mktemp("composed")
    shutil.copy(COMPOSED / "ability_hand_right.yaml", folder)
    (folder / "xarm7_ability.yaml").write_text(_arm_text())
    with registered(folder, tmp_path_factory.mktemp("cache")) as agents:
        yield agents


def test_composed_xarm7_ability_is_maniskills_robot_link_for_link(xarm7: dict[str, type]) -> None:
    ours, theirs = make_env("rs_xarm7_ability_composed"), make_env("xarm7_ability")
    try:
        a, b = ours.unwrapped.agent.robot, theirs.unwrapped.agent.robot
        assert [j.name for j in a.active_joints] == [j.name for j in b.active_joints]
        assert [link.name for link in a.links] == [link.name for link in b.links]
        for x, y in zip(a.links, b.links, strict=True):
            assert x._objs[0].mass == y._objs[0].mass, x.name
            assert np.array_equal(x._objs[0].inertia, y._objs[0].inertia), x.name
        low, high = (np.clip(v, -np.pi, np.pi) for v in b.get_qlimits()[0].numpy().T)
        rng = np.random.default_rng(SEED)
        for _ in range(10):
            qpos = torch.as_tensor(rng.uniform(low, high)[None], dtype=torch.float32)
            a.set_qpos(qpos)
            b.set_qpos(qpos)
            for x, y in zip(a.links, b.links, strict=True):
                assert float((x.pose.p - y.pose.p).abs().max()) < 1e-6, x.name
                assert float((x.pose.q - y.pose.q).abs().max()) < 1e-6, x.name
    finally:
        ours.close()
        theirs.close()


@pytest.mark.parametrize("mode", MODES)
def test_composed_xarm7_ability_rolls_out_as_maniskills_in_every_mode(
    xarm7: dict[str, type], mode: str
) -> None:
    qpos, _ = _same_rollouts("rs_xarm7_ability_composed", "xarm7_ability", mode)
    # upstream's mode goes NaN here (URDF <mimic>, RS309), the composed robot with it
    assert torch.isnan(qpos[-1]).any()


@pytest.fixture(scope="module")
def without_mimics(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, type]]:
    """The composed robot with the hand's mimic tags mended away, and upstream's class loading
    a copy of its file without them (its meshes named where they are, its SRDF beside it)."""
    from mani_skill.agents.robots.xarm.xarm7_ability import XArm7Ability

    folder = tmp_path_factory.mktemp("without_mimics")
    hand = (COMPOSED / "ability_hand_right.yaml").read_text()
    (folder / "hand.yaml").write_text(
        hand.replace("uid: rs_ability_hand_right", "uid: rs_hand_mended").replace(
            '/ability_hand_right.urdf"', '/ability_hand_right.urdf"\n  mend: {mimic: controller}'
        )
    )
    arm = _arm_text()
    (folder / "arm.yaml").write_text(
        arm.replace("uid: rs_xarm7_ability_composed", "uid: rs_xarm7_mended").replace(
            "spec: ability_hand_right.yaml", "spec: hand.yaml"
        )
    )
    assets = maniskill_assets()
    original = assets / "robots" / "xarm7" / "xarm7_ability_right_hand.urdf"
    text = re.sub(r"<mimic[^>]*/>", "", original.read_text())
    text = re.sub(
        r'filename="([^"]+)"',
        lambda m: f'filename="{os.path.normpath(original.parent / m.group(1))}"',
        text,
    )
    upstream = tmp_path_factory.mktemp("upstream") / "xarm7_ability.urdf"
    upstream.write_text(text)
    shutil.copy(original.with_suffix(".srdf"), upstream.with_suffix(".srdf"))
    stripped = type("XArm7AbilityMended", (XArm7Ability,), {"uid": "xarm7_mended"})
    stripped.urdf_path = str(upstream)
    with registered(folder, tmp_path_factory.mktemp("cache"), stripped) as agents:
        yield agents


@pytest.mark.parametrize("mode", MODES)
def test_without_mimic_tags_every_mode_runs_and_stays_bit_identical(
    without_mimics: dict[str, type], mode: str
) -> None:
    qpos, _ = _same_rollouts("rs_xarm7_mended", "xarm7_mended", mode)
    assert torch.isfinite(qpos).all()
    assert float((qpos[-1] - qpos[0]).abs().max()) > 0.01  # the actions moved it


# -- the QUT Panda and the Franka hand (rtb-data) -------------------------------------------

# rtb-data's hand.urdf.xacro instantiates the hand with safety_distance 0.03 (its collision
# spheres 3 cm larger); panda_arm_hand.urdf.xacro with 0. A user who wants the combination's
# shapes writes the instance the combination makes: this file.
HAND_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="hand">
  <xacro:include filename="$(find qut_frankie_description)/robots/hand.xacro"/>
  <xacro:hand ns="panda" safety_distance="0.00"/>
</robot>
"""
ARM_CONTROLLER = (
    "{type: pd_joint_pos, joints: arm, lower: null, upper: null, stiffness: 1e3,"
    " damping: 1e2, force_limit: 100, normalize_action: false}"
)
GRIPPER_CONTROLLER = (
    "{type: pd_joint_pos_mimic, joints: gripper, lower: -0.01, upper: 0.04, stiffness: 1e3,"
    " damping: 1e2, force_limit: 100, mimic: {panda_finger_joint2: panda_finger_joint1}}"
)


@pytest.fixture(scope="module")
def panda_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """arm.yaml (rtb-data's Panda arm with the Franka hand mounted as a part), hand.yaml, and
    combined.yaml (rtb-data's own combined description)."""
    combined = locate(BY_KEY["rtb_panda"])  # panda_arm_hand.urdf.xacro
    robots = combined.parent
    package = robots.parent
    folder = tmp_path_factory.mktemp("panda")
    (folder / "hand.urdf.xacro").write_text(HAND_XACRO)
    (folder / "hand.yaml").write_text(
        "robospec: 1\nuid: rtb_hand\n"
        "description: {xacro: hand.urdf.xacro,"
        f" packages: {{qut_frankie_description: '{package}'}}}}\n"
        "groups: {gripper: [panda_finger_joint1, panda_finger_joint2]}\n"
        "keyframes: {rest: {qpos: {gripper: 0.04}}}\n"
        f"controllers:\n  gripper: {GRIPPER_CONTROLLER}\n"
        "control_modes: {pd_joint_pos: {gripper: gripper}}\n"
        "tcp: panda_hand\n"
        "named_links: {finger1_link: panda_leftfinger, finger2_link: panda_rightfinger}\n"
        "grasping: {is_grasping: {fingers: [{link: finger1_link, opening: +y},"
        " {link: finger2_link, opening: -y}]}}\n"
    )
    common = (
        "groups: {arm: 'panda_joint[1-7]', gripper: [panda_finger_joint1, panda_finger_joint2]}\n"
        # rtb-data's base reaches 6 cm below its origin: stood on the ground (RS521 otherwise)
        "keyframes: {rest: {qpos: {arm: [0, pi/8, 0, -5*pi/8, 0, 3*pi/4, pi/4], gripper: 0.04},"
        " pose: {p: [0, 0, 0.06]}}}\n"
        "is_static: {joints: arm, threshold: 0.2}\n"
        f"controllers:\n  arm: {ARM_CONTROLLER}\n"
    )
    (folder / "arm.yaml").write_text(
        "robospec: 1\nuid: rtb_panda_composed\n"
        f"description: {{xacro: '{robots}/panda_arm.urdf.xacro'}}\n"
        "parts:\n  hand: {spec: hand.yaml, at: panda_link8, pose: {rpy: [0, 0, -pi/4]},"
        " joint: panda_hand_joint}\n" + common + "control_modes: {pd_joint_pos: {arm: arm}}\n"
    )
    (folder / "combined.yaml").write_text(
        f"robospec: 1\nuid: rtb_panda_combined\ndescription: {{xacro: '{combined}'}}\n"
        + common
        + f"  gripper: {GRIPPER_CONTROLLER}\n"
        + "control_modes: {pd_joint_pos: {arm: arm, gripper: gripper}}\n"
    )
    return folder


@pytest.fixture(scope="module")
def panda(
    panda_folder: Path, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[dict[str, type]]:
    with registered(panda_folder, tmp_path_factory.mktemp("cache")) as agents:
        yield agents


def test_composed_panda_rolls_out_as_rtb_datas_combined_panda(panda: dict[str, type]) -> None:
    ours, theirs = make_env("rtb_panda_composed"), make_env("rtb_panda_combined")
    try:
        a, b = ours.unwrapped.agent.robot, theirs.unwrapped.agent.robot
        assert [j.name for j in a.active_joints] == [j.name for j in b.active_joints]
        assert [link.name for link in a.links] == [link.name for link in b.links]
    finally:
        ours.close()
        theirs.close()
    qpos, _ = _same_rollouts("rtb_panda_composed", "rtb_panda_combined", "pd_joint_pos")
    assert torch.isfinite(qpos).all()


def test_composed_panda_runs_pick_cube_headless(panda: dict[str, type]) -> None:
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401

    from robospec.maniskill.headless import headless_loading

    with headless_loading():
        env = gym.make(
            "PickCube-v1",
            robot_uids="rtb_panda_composed",
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
        )
        try:
            obs, _ = env.reset(seed=SEED)
            agent = env.unwrapped.agent
            assert agent.tcp.name == "panda_hand"
            for action in random_actions(env.action_space, SEED, 10):
                obs, reward, _, _, info = env.step(torch.as_tensor(action))
            assert torch.isfinite(obs).all() and torch.isfinite(reward).all()
            assert "is_grasped" in info and "is_robot_static" in info
        finally:
            env.close()


# -- an MJCF arm and an MJCF hand (dm_control's Jaco) ---------------------------------------


def test_an_mjcf_arm_with_an_mjcf_hand_loads_in_maniskill_with_finite_state(
    tmp_path: Path,
) -> None:
    from test_compose import _jaco

    spec = _jaco(tmp_path)
    with registered(spec.parent, tmp_path / "cache"):
        env = make_env("jaco_with_hand", "pd_joint_pos")
        try:
            robot = env.unwrapped.agent.robot
            assert [j.name for j in robot.active_joints][-3:] == [
                "finger_1",
                "finger_2",
                "finger_3",
            ]
            limits = robot.get_qlimits()[0, -3:].numpy()
            assert np.allclose(limits, [[0.15, 1.35]] * 3)  # the hand's defaults, kept
            env.reset(seed=SEED)
            robot.set_qpos(torch.as_tensor(env.unwrapped.agent.keyframes["rest"].qpos[None]))
            states = []
            for action in random_actions(env.action_space, SEED, STEPS):
                env.step(torch.as_tensor(action))
                states.append(torch.cat([robot.get_qpos(), robot.get_qvel()], -1))
            state = torch.stack(states)
            assert torch.isfinite(state).all()

        finally:
            env.close()


# -- robospec check --------------------------------------------------------------------------


def test_the_composed_panda_and_jaco_pass_check_as_the_combined_panda_does(
    panda_folder: Path, tmp_path: Path
) -> None:
    from test_compose import _jaco

    from robospec.physics.batch import Options, check_paths

    specs = [panda_folder / "arm.yaml", panda_folder / "combined.yaml", _jaco(tmp_path)]
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
        reports, extra = check_paths(specs, Options(steps=20))
    assert extra == []
    found = {
        r.uid: sorted({(d.code, d.message) for d in r.all_diagnostics if d.is_error})
        for r in reports
    }
    assert found == {"rtb_panda_composed": [], "rtb_panda_combined": [], "jaco_with_hand": []}


def test_check_says_where_a_part_sits_inside_the_robot(tmp_path: Path) -> None:
    from conftest import CODE_EXAMPLES

    from robospec.physics.batch import Options, check_paths

    for name in ("arm.urdf", "gripper.urdf"):  # a gripper with a palm of some size
        shutil.copy(CODE_EXAMPLES / "RS730" / name, tmp_path / name)
    spec = tmp_path / "arm.yaml"
    spec.write_text(
        "robospec: 1\nuid: arm_with_sunken_gripper\ndescription: {urdf: arm.urdf}\n"
        "parts:\n  gripper: {description: {urdf: gripper.urdf}, at: tool0,"
        " pose: {p: [0, 0, -0.1]}}\n"
        "keyframes: {rest: {qpos: {shoulder: 0, left: 0, right: 0}}}\n"
        "controllers:\n  all: {type: pd_joint_pos, joints: [shoulder, left, right], lower: null,"
        " upper: null, stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes: {pd_joint_pos: all}\n"
    )
    (report,), _ = check_paths([spec], Options(steps=5), isolate=False)
    found = [d for f in report.findings for d in f.diagnostics if d.code == "RS734"]
    assert len(found) == 1
    (diagnostic,) = found
    assert (diagnostic.location.line, diagnostic.location.column) == (5, 59)
    assert "part 'gripper' is inside the robot at keyframe 'rest'" in diagnostic.message
    assert "'upper_arm'" in diagnostic.message
    assert not any(d.code == "RS508" for f in report.findings for d in f.diagnostics)


# -- robospec new --attach -------------------------------------------------------------------------


def test_new_attach_declares_the_seam_the_collision_matrix_finds(tmp_path: Path) -> None:
    # the arm scaffolded without its rest-pose search (which test_new covers), the hand given
    # by its spec: what --attach adds is sampled here
    from robospec.authoring.commands import run_new
    from robospec.authoring.new.attach import parse_attach, run_attach
    from robospec.pipeline import compile_spec

    assets = maniskill_assets()
    arm = assets / "robots" / "xarm7" / "xarm7.urdf"
    shutil.copy(COMPOSED / "ability_hand_right.yaml", tmp_path / "hand.yaml")
    out = tmp_path / "xarm7_hand.yaml"
    assert not run_new(arm, out, None, False, simulate=False).write().failed
    attach = [parse_attach(f"{tmp_path / 'hand.yaml'}@link_eef")]
    mounted = run_attach(out, arm, attach, force=False, simulate=True).write()
    assert not mounted.failed, [d.format_text() for d in mounted.diagnostics]
    text = out.read_text()
    assert "  hand: {spec: hand.yaml, at: link_eef}\n" in text
    # the hand's base and link7 touch in every pose (two empty frames apart, not adjacent)
    assert text.rstrip().endswith("never_collide:\n  - [base, link7]")
    compiled = compile_spec(out)
    assert compiled.robot is not None and compiled.robot.never_collide is not None
