"""Parts: robots composed from two descriptions in one spec (``parts:``), without simulating.

The combined description robospec writes is compared with the hand-made combinations that
ship beside the parts: ManiSkill's ``xarm7_ability_right_hand.urdf`` (the xArm 7 with the Ability
hand) link by link — names, tree, active joints in qpos order, every link's pose at random
configurations, masses — and what comes along from the part's spec (controllers in every mode,
keyframes merged by joint, tcp, materials) is checked in the robot that comes out. Prefixes,
frames, rings of parts, MJCF parts and the carried files of ``build`` each have a test; the
diagnostics of bad input are the catalogue's (docs/examples/codes/RS730 ... RS741).
tests/test_compose_maniskill.py loads the composed robots in ManiSkill.
"""

from __future__ import annotations

import dataclasses
import math
import random
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import CODE_EXAMPLES, SPECS, maniskill_assets
from lxml import etree

from robospec.description import load_description
from robospec.diagnostics import Severity
from robospec.geometry import matrix_from_quaternion, matrix_from_rpy, quaternion_from_rpy
from robospec.kinematics.forward import kinematics_of
from robospec.pipeline import compile_spec

COMPOSED = SPECS / "composed" / "xarm7_ability.yaml"
HAND = SPECS / "composed" / "ability_hand_right.yaml"
EXAMPLES = CODE_EXAMPLES / "RS736"  # an arm and a gripper, small enough to write variants of


def _combined_file() -> Path:
    return maniskill_assets() / "robots" / "xarm7" / "xarm7_ability_right_hand.urdf"


def _compiled(path: Path) -> object:
    result = compile_spec(path)
    errors = [d.format_text() for d in result.diagnostics if d.is_error]
    assert result.robot is not None and not errors, errors
    return result


# -- the xArm 7 with the Ability hand, against ManiSkill's hand-made file ----------------------


def test_composed_xarm7_ability_has_maniskills_links_joints_and_masses() -> None:
    result = _compiled(COMPOSED)
    ours = result.description
    theirs, _ = load_description(str(_combined_file()), "urdf")
    assert ours is not None and theirs is not None
    assert ours.link_names == theirs.link_names
    assert ours.active_joint_names == theirs.active_joint_names
    assert [(j.name, j.type, j.parent, j.child, j.lower, j.upper) for j in ours.joints] == [
        (j.name, j.type, j.parent, j.child, j.lower, j.upper) for j in theirs.joints
    ]
    text = result.robot.description.generated_text
    assert _masses(text) == _masses(_combined_file().read_text())


def _masses(text: str) -> dict[str, float]:
    from lxml import etree

    root = etree.fromstring(text.encode())
    return {
        str(link.get("name")): float(mass.get("value"))
        for link in root.findall("link")
        if (mass := link.find("inertial/mass")) is not None
    }


def test_composed_xarm7_ability_puts_every_link_where_maniskills_file_does() -> None:
    result = _compiled(COMPOSED)
    text = result.robot.description.generated_text
    ours = kinematics_of(result.description, text.encode(), str(COMPOSED))
    combined = _combined_file()
    theirs_description, _ = load_description(str(combined), "urdf")
    assert theirs_description is not None
    theirs = kinematics_of(theirs_description, combined.read_bytes(), str(combined))
    assert ours is not None and theirs is not None
    joints = result.description.active_joints
    rng = random.Random(25)
    for _ in range(20):
        qpos = {j.name: rng.uniform(j.lower or -3.0, j.upper or 3.0) for j in joints}
        a, b = ours.at(qpos).links, theirs.at(qpos).links
        assert a.keys() == b.keys()
        for link in a:
            assert abs(a[link] - b[link]).max() < 1e-6, link


def test_the_parts_controller_joins_every_mode_and_its_keyframe_merges_by_joint() -> None:
    robot = _compiled(COMPOSED).robot
    # upstream's modes: each of the arm's, with the hand's controller as 'gripper'
    assert [(m.name, m.groups) for m in robot.modes] == [
        ("pd_joint_delta_pos", (("arm", "arm_delta_pos"), ("gripper", "hand_target_delta_pos"))),
        ("pd_joint_pos", (("arm", "arm_pos"), ("gripper", "hand_target_delta_pos"))),
        ("pd_ee_delta_pose", (("arm", "arm_ee_delta_pose"), ("gripper", "hand_target_delta_pos"))),
        (
            "pd_ee_target_delta_pose",
            (("arm", "arm_ee_target_delta_pose"), ("gripper", "hand_target_delta_pos")),
        ),
    ]
    (rest,) = robot.keyframes
    assert rest.qpos == (0, -0.4, 0, 0.5, 0, 0.9, -3.0, *[0.0] * 10)
    assert robot.tcp is not None and robot.tcp.link == "base"  # the hand's
    assert robot.urdf_config["_materials"] == {
        "front_finger": {"static_friction": 2.0, "dynamic_friction": 1.5, "restitution": 0.0}
    }
    assert list(robot.urdf_config["link"]) == ["index_L2", "middle_L2", "ring_L2", "pinky_L2"]
    assert dict(robot.named_links)["finger_tip_links"][0] == "thumb_tip"
    (part,) = robot.parts
    assert (part.name, part.at, part.joint, part.root) == ("hand", "link_eef", "joint_eef", "base")
    assert part.folded == ("link_eef", "base_link", "base_joint")


def test_the_hands_description_problems_point_into_the_hands_file() -> None:
    result = compile_spec(COMPOSED)
    mimics = [d for d in result.diagnostics if d.code == "RS309"]
    assert mimics and all(
        d.location.file == "{maniskill_assets}/robots/ability_hand/ability_hand_right.urdf"
        for d in mimics
    )
    hand = maniskill_assets() / "robots/ability_hand/ability_hand_right.urdf"
    lines = hand.read_text().splitlines()
    for d in mimics:  # the line of the joint the warning names
        assert re.search(rf'joint name="{d.message.split(chr(39))[1]}"', lines[d.location.line - 1])


def test_fold_frames_leaves_out_the_arms_flange_and_the_hands_root_frame() -> None:
    text = _compiled(COMPOSED).robot.description.generated_text
    assert '<link name="link_eef"' not in text and '<link name="base_link"' not in text
    joint = re.search(r'<joint name="joint_eef".*?</joint>', text, re.S)
    assert joint is not None and '<child link="base"/>' in joint.group(0)


# -- names, modes and keyframes of parts ---------------------------------------------------------


def _arm_and_gripper(tmp_path: Path, part: str, extra: str = "", gripper_extra: str = "") -> Path:
    """The catalogue's arm with a gripper whose root is base_link, as the arm's is."""
    for name in ("arm.urdf", "gripper.urdf"):
        (tmp_path / name).write_text((EXAMPLES / name).read_text())
    (tmp_path / "gripper.yaml").write_text(
        "robospec: 1\nuid: my_gripper\ndescription: {urdf: gripper.urdf}\n"
        "materials: {rubber: {static_friction: 1, dynamic_friction: 1}}\n"
        "links: {left_finger: {material: rubber}}\n"
        "keyframes: {rest: {qpos: {left: 0.02}}, wide: {qpos: {left: 0.03}}}\n"
        "controllers:\n"
        "  arm: {type: pd_joint_pos, joints: [left], lower: 0, upper: 0.03, stiffness: 100,"
        " damping: 10, normalize_action: false}\n"
        "control_modes: {pd_joint_pos: {arm: arm}}\n"
        "tcp: left_finger\n" + gripper_extra
    )
    spec = tmp_path / "arm.yaml"
    spec.write_text(
        "robospec: 1\nuid: my_arm\ndescription: {urdf: arm.urdf}\n"
        f"parts:\n  gripper: {part}\n"
        "materials: {rubber: {static_friction: 2, dynamic_friction: 2}}\n"
        "keyframes: {rest: {qpos: {shoulder: 0.5}}}\n"
        "controllers:\n"
        "  arm: {type: pd_joint_pos, joints: [shoulder], lower: -3, upper: 3, stiffness: 100,"
        " damping: 10, normalize_action: false}\n"
        "control_modes:\n  pd_joint_pos: {arm: arm}\n" + extra
    )
    return spec


def test_clashing_names_get_the_parts_prefix_and_only_those(tmp_path: Path) -> None:
    spec = _arm_and_gripper(tmp_path, "{spec: gripper.yaml, at: tool0}")
    result = _compiled(spec)
    (note,) = [d for d in result.diagnostics if d.code == "RS736"]
    assert note.severity is Severity.NOTE and "'base_link' -> 'gripper_base_link'" in note.message
    robot = result.robot
    assert "gripper_base_link" in result.description.link_names
    assert "left_finger" in result.description.link_names  # no clash: kept
    # the part's controller 'arm' clashes with the robot's: prefixed, and used in every mode
    assert [c.name for c in robot.controllers] == ["arm", "gripper_arm"]
    assert robot.modes[0].groups == (("arm", "arm"), ("gripper_arm", "gripper_arm"))
    # its material 'rubber' is another than the robot's: prefixed, and its link rule follows
    assert robot.urdf_config["link"]["left_finger"]["material"] == "gripper_rubber"
    assert robot.tcp is not None and robot.tcp.link == "left_finger"


def test_a_part_turned_into_gimbal_lock_is_mounted_at_its_quaternion(tmp_path: Path) -> None:
    # pitch π/2 with roll 0.3 and yaw 0.1: only roll - yaw is defined there, and roll and yaw
    # read off the quaternion are rounding (they were written 2.5° off)
    q = quaternion_from_rpy(0.3, math.pi / 2, 0.1)
    pose = ", ".join(repr(v) for v in q)
    result = _compiled(
        _arm_and_gripper(tmp_path, f"{{spec: gripper.yaml, at: tool0, pose: {{q: [{pose}]}}}}")
    )
    mount = etree.fromstring(result.robot.description.generated_text).find(
        "joint[@name='gripper_mount']/origin"
    )
    rpy = [float(v) for v in mount.get("rpy").split()]
    written, meant = matrix_from_rpy(*rpy), matrix_from_quaternion(q)
    np.testing.assert_allclose(written, meant, atol=1e-12)


def test_keyframes_merge_by_joint_and_a_parts_own_keyframe_comes_along(tmp_path: Path) -> None:
    robot = _compiled(_arm_and_gripper(tmp_path, "{spec: gripper.yaml, at: tool0}")).robot
    frames = {k.name: k.qpos for k in robot.keyframes}
    assert frames == {"rest": (0.5, 0.02), "wide": (0.5, 0.03)}


def test_a_mode_that_already_drives_the_part_is_left_as_the_spec_writes_it(
    tmp_path: Path,
) -> None:
    spec = _arm_and_gripper(
        tmp_path,
        "{spec: gripper.yaml, at: tool0}",
        "  both: {arm: arm, fingers: gripper_arm}\n",
    )
    robot = _compiled(spec).robot
    modes = {m.name: m.groups for m in robot.modes}
    assert modes["both"] == (("arm", "arm"), ("fingers", "gripper_arm"))
    assert modes["pd_joint_pos"] == (("arm", "arm"), ("gripper_arm", "gripper_arm"))


def test_a_problem_of_a_part_controller_is_reported_in_the_parts_spec(tmp_path: Path) -> None:
    # a normalized action over unbounded limits (RS319), written in the gripper's spec
    spec = _arm_and_gripper(tmp_path, "{spec: gripper.yaml, at: tool0}")
    urdf = tmp_path / "gripper.urdf"
    urdf.write_text(urdf.read_text().replace('type="prismatic"', 'type="continuous"'))
    gripper = tmp_path / "gripper.yaml"
    gripper.write_text(
        gripper.read_text().replace(
            "lower: 0, upper: 0.03, stiffness: 100, damping: 10, normalize_action: false",
            "lower: null, upper: null, stiffness: 100, damping: 10, normalize_action: true",
        )
    )
    result = compile_spec(spec)
    found = [d for d in result.diagnostics if d.code == "RS319"]
    assert found and {d.location.file for d in found} == {str(gripper)}


def test_parts_hang_from_parts_in_any_order(tmp_path: Path) -> None:
    (tmp_path / "camera.urdf").write_text((CODE_EXAMPLES / "RS733" / "camera.urdf").read_text())
    spec = _arm_and_gripper(
        tmp_path,
        "{spec: gripper.yaml, at: tool0}\n"
        "  camera: {description: {urdf: camera.urdf}, at: left_finger}",
    )
    # the camera comes first in the file, on a link of the gripper, mounted after it
    text = spec.read_text()
    lines = text.splitlines()
    gripper, camera = lines[4], lines[5]
    spec.write_text(text.replace(gripper + "\n" + camera, camera + "\n" + gripper))
    result = _compiled(spec)
    assert {p.name: p.at for p in result.robot.parts} == {
        "gripper": "tool0",
        "camera": "left_finger",
    }
    assert "camera_link" in result.description.link_names


def test_the_combined_description_loads_from_the_robots_folder_and_names_the_parts_files(
    tmp_path: Path,
) -> None:
    text = _compiled(COMPOSED).robot.description.generated_text
    meshes = re.findall(r'filename="([^"]+)"', text)
    assert any(m.startswith("../ability_hand/meshes/") for m in meshes)
    folder = _combined_file().parent
    assert all((folder / m).is_file() for m in meshes), "every file, from the arm's folder"


def test_build_writes_a_composed_robot_self_contained(tmp_path: Path) -> None:
    from conftest import invoke_robospec

    out = tmp_path / "pkg"
    result = invoke_robospec("build", str(COMPOSED), "-o", str(out))
    assert result.exit_code == 0, result.output
    urdf = (out / "rs_xarm7_ability_composed.urdf").read_text()
    assert "with part 'hand' mounted" in urdf
    for mesh in re.findall(r'filename="([^"]+)"', urdf):
        assert "/" not in mesh and (out / mesh).is_file(), mesh


def test_register_recompiles_when_a_parts_spec_or_description_changes() -> None:
    from robospec.output.register import _dependencies

    deps = _dependencies(_compiled(COMPOSED).robot)
    assert str(HAND.resolve()) in deps
    assert any(d.endswith("ability_hand/ability_hand_right.urdf") for d in deps)


# -- MJCF ------------------------------------------------------------------------------------------


def _jaco(tmp_path: Path) -> Path:
    from corpus import BY_KEY, CorpusMissing, locate

    try:
        arm, hand = locate(BY_KEY["dmc_jaco_arm"]), locate(BY_KEY["dmc_jaco_hand"])
    except CorpusMissing as missing:
        pytest.fail(str(missing))
    (tmp_path / "hand.yaml").write_text(
        # (its finger joints write no axis: ManiSkill's loader would turn them about x, RS095)
        f"robospec: 1\nuid: jaco_hand\ndescription: {{mjcf: '{hand}', mend: {{axes: mujoco}}}}\n"
        "groups: {fingers: 'finger_[123]'}\n"
        "keyframes: {rest: {qpos: {fingers: 0.2}}}\n"
        "controllers:\n  fingers: {type: pd_joint_pos, joints: fingers, lower: null,"
        " upper: null, stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes: {pd_joint_pos: {gripper: fingers}}\ntcp: hand\n"
    )
    spec = tmp_path / "jaco.yaml"
    spec.write_text(
        f"robospec: 1\nuid: jaco_with_hand\n"
        f"description: {{mjcf: '{arm}', mend: {{axes: mujoco}}}}\n"
        "parts: {hand: {spec: hand.yaml, at: b_6}}\n"
        "groups: {arm: 'joint_[1-6]'}\n"
        "keyframes: {rest: {qpos: {arm: [0, 3.14, 3.14, 0, 0, 0]}}}\n"
        "controllers:\n  arm: {type: pd_joint_pos, joints: arm, lower: null, upper: null,"
        " stiffness: 1000, damping: 100, normalize_action: false}\n"
        "control_modes: {pd_joint_pos: {arm: arm}}\n"
        # MuJoCo keeps the hand off the wrist with contype/conaffinity, which ManiSkill ignores
        "never_collide: [[b_4, hand], [b_5, hand]]\n"
    )
    return spec


def test_an_mjcf_hand_on_an_mjcf_arm_keeps_its_defaults_and_shares_alike_assets(
    tmp_path: Path,
) -> None:
    result = _compiled(_jaco(tmp_path))
    description = result.description
    assert description.active_joint_names[-3:] == ("finger_1", "finger_2", "finger_3")
    assert [j.lower for j in description.active_joints[-3:]] == [0.15, 0.15, 0.15]  # the hand's
    text = result.robot.description.generated_text
    assert '<default class="hand">' in text and 'childclass="hand"' in text
    assert "hand_dark_gray" not in text  # both include common.xml's materials: shared
    assert not any(d.code == "RS736" for d in result.diagnostics)


MOUNTED_ARM = """<mujoco model="arm"><compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <geom type="box" size=".1 .1 .02"/>
      <body name="link1" pos="0 0 .1">
        <joint name="j1" axis="0 0 1" range="-1 1"/>
        <geom type="capsule" size=".02 .1" pos="0 0 .1"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
# the part's root body stands 5 cm along x of its model's frame, turned 90° about x
MOUNTED_GRIPPER = """<mujoco model="gripper"><compiler angle="radian"/>
  <default><geom rgba=".5 .5 .5 1"/></default>
  <worldbody>
    <body name="palm" pos="0.05 0 0" quat="0.7071067811865476 0.7071067811865476 0 0">
      <geom type="box" size="0.02 0.04 0.02" mass="0.3"/>
      <body name="left_finger" pos="0 0.02 0.04">
        <joint name="left" type="slide" axis="0 1 0" range="0 0.03"/>
        <geom type="box" size="0.005 0.005 0.025" mass="0.05"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_an_mjcf_parts_root_is_posed_by_the_mount_pose_then_by_its_own(tmp_path: Path) -> None:
    (tmp_path / "arm.xml").write_text(MOUNTED_ARM)
    (tmp_path / "gripper.xml").write_text(MOUNTED_GRIPPER)
    spec = tmp_path / "arm.yaml"
    spec.write_text(
        "robospec: 1\nuid: mounted_arm\ndescription: {mjcf: arm.xml}\n"
        "parts:\n  gripper: {description: {mjcf: gripper.xml}, at: link1,"
        " pose: {p: [0, 0, 0.1], rpy: [0, 0, pi/2]}}\n"
        "controllers:\n  arm: {type: pd_joint_pos, joints: [j1], lower: -1, upper: 1,"
        " stiffness: 100, damping: 10, normalize_action: false}\n"
        "  fingers: {type: pd_joint_pos, joints: [left], lower: 0, upper: 0.03,"
        " stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes:\n  pd_joint_pos: {arm: arm, gripper: fingers}\n"
    )
    text = _compiled(spec).robot.description.generated_text
    palm = next(b for b in etree.fromstring(text).iter("body") if b.get("name") == "palm")
    # in link1's frame: the mount pose, then the root's own pose within it (turned 90° about
    # z, the root's 5 cm along x become 5 cm along y)
    position = [float(v) for v in palm.get("pos").split()]
    np.testing.assert_allclose(position, [0, 0.05, 0.1], atol=1e-9)
    about_z = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    about_x = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    quaternion = [float(v) for v in palm.get("quat").split()]
    np.testing.assert_allclose(matrix_from_quaternion(quaternion), about_z @ about_x, atol=1e-9)


def test_an_mjcf_part_without_defaults_gets_no_default_class(tmp_path: Path) -> None:
    (tmp_path / "arm.xml").write_text(MOUNTED_ARM)
    (tmp_path / "gripper.xml").write_text(
        MOUNTED_GRIPPER.replace('  <default><geom rgba=".5 .5 .5 1"/></default>\n', "")
    )
    spec = tmp_path / "arm.yaml"
    spec.write_text(
        "robospec: 1\nuid: plain_arm\ndescription: {mjcf: arm.xml}\n"
        "parts:\n  gripper: {description: {mjcf: gripper.xml}, at: link1}\n"
        "controllers:\n  arm: {type: pd_joint_pos, joints: [j1, left], lower: null,"
        " upper: null, stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes:\n  pd_joint_pos: {arm: arm}\n"
    )
    text = _compiled(spec).robot.description.generated_text  # no RS052: no unknown class
    palm = next(b for b in etree.fromstring(text).iter("body") if b.get("name") == "palm")
    assert palm.get("childclass") is None


NAMED_ARM = """<mujoco model="arm"><compiler angle="radian"/>
  <default><geom rgba=".8 .8 .8 1"/></default>
  <asset><material name="grey" rgba=".5 .5 .5 1"/><material name="paint" rgba="0 0 1 1"/></asset>
  <worldbody>
    <body name="base">
      <geom type="box" size=".1 .1 .02" material="grey"/>
      <body name="link1" pos="0 0 .1">
        <joint name="j1" axis="0 0 1" range="-1 1"/>
        <geom type="capsule" size=".02 .1" pos="0 0 .1"/>
      </body>
    </body>
  </worldbody>
  <actuator><position name="a1" joint="j1" kp="10"/></actuator>
  <keyframe><key name="home" qpos="0.5" qvel="0.1" ctrl="0.5"/></keyframe>
</mujoco>
"""
# a part whose body, joint and actuator names are the arm's too, with a material the arm has
# alike and one of its own
NAMED_GRIPPER = """<mujoco model="gripper"><compiler angle="radian"/>
  <default><geom rgba=".2 .2 .2 1"/><joint damping="1"/></default>
  <asset>
    <material name="grey" rgba=".5 .5 .5 1"/>
    <material name="rubber" rgba=".1 .1 .1 1"/>
    <material name="paint" rgba="1 0 0 1"/>
  </asset>
  <worldbody>
    <body name="base">
      <geom type="box" size="0.02 0.04 0.02" mass="0.3" material="grey"/>
      <geom name="logo" type="box" size="0.01 0.01 0.001" material="paint"/>
      <body name="left_finger" pos="0 0.02 0.04">
        <joint name="j1" type="slide" axis="0 1 0" range="0 0.03" ref="0.01"/>
        <geom type="box" size="0.005 0.005 0.025" mass="0.05" material="rubber"/>
      </body>
    </body>
  </worldbody>
  <contact><exclude body1="base" body2="left_finger"/></contact>
  <actuator><position name="a1" joint="j1" kp="5"/></actuator>
</mujoco>
"""


def test_an_mjcf_part_keeps_its_names_defaults_and_sections_prefixed_where_they_clash(
    tmp_path: Path,
) -> None:
    (tmp_path / "arm.xml").write_text(NAMED_ARM)
    (tmp_path / "gripper.xml").write_text(NAMED_GRIPPER)
    spec = tmp_path / "arm.yaml"
    spec.write_text(
        "robospec: 1\nuid: named_arm\ndescription: {mjcf: arm.xml}\n"
        "parts:\n  gripper: {description: {mjcf: gripper.xml}, at: link1}\n"
        "controllers:\n  arm: {type: pd_joint_pos, joints: [j1], lower: -1, upper: 1,"
        " stiffness: 100, damping: 10, normalize_action: false}\n"
        "  fingers: {type: pd_joint_pos, joints: [gripper_j1], lower: 0, upper: 0.03,"
        " stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes:\n  pd_joint_pos: {arm: arm, gripper: fingers}\n"
    )
    result = _compiled(spec)
    (note,) = [d for d in result.diagnostics if d.code == "RS736"]
    for renamed in ("body 'base' -> 'gripper_base'", "joint 'j1' -> 'gripper_j1'"):
        assert renamed in note.message
    assert "left_finger" not in note.message  # no clash: kept
    root = etree.fromstring(result.robot.description.generated_text)
    link1 = next(b for b in root.iter("body") if b.get("name") == "link1")
    (part,) = link1.findall("body")
    assert (part.get("name"), part.get("childclass")) == ("gripper_base", "gripper")
    # the part's defaults: a class of their own inside the robot's main default
    (main,) = root.findall("default")
    (own,) = main.findall("default")
    assert own.get("class") == "gripper" and own.find("joint").get("damping") == "1"
    assert main.find("geom").get("rgba") == ".8 .8 .8 1"  # the robot's own, kept
    # the material both define alike once, the part's own beside it, and the one both name
    # but define otherwise prefixed, with the part's geom that wears it
    materials = [m.get("name") for m in root.iter("material")]
    assert materials == ["grey", "paint", "rubber", "gripper_paint"]
    logo = next(g for g in root.iter("geom") if g.get("name") == "logo")
    assert logo.get("material") == "gripper_paint"
    # the sections' references follow the renames
    (exclude,) = root.iter("exclude")
    assert (exclude.get("body1"), exclude.get("body2")) == ("gripper_base", "left_finger")
    actuators = [(a.get("name"), a.get("joint")) for a in root.find("actuator")]
    assert actuators == [("a1", "j1"), ("gripper_a1", "gripper_j1")]
    # the robot's keyframe gets the part's joint at its reference, at rest, and its actuator
    (key,) = root.iter("key")
    assert (key.get("qpos"), key.get("qvel"), key.get("ctrl")) == ("0.5 0.01", "0.1 0", "0.5 0")


def test_build_carries_a_composed_mjcf_standalone(tmp_path: Path) -> None:
    from conftest import invoke_robospec

    out = tmp_path / "pkg"
    result = invoke_robospec("build", str(_jaco(tmp_path)), "-o", str(out))
    assert result.exit_code == 0, result.output
    xml = (out / "jaco_with_hand.xml").read_text()
    assert "<include" not in xml and "meshdir" not in xml
    files = re.findall(r'file="([^"]+)"', xml)
    assert files and all((out / f).is_file() for f in files)
    assert (
        'mjcf_path = os.path.join(HERE, "jaco_with_hand.xml")'
        in (out / "jaco_with_hand.py").read_text()
    )


def test_a_parts_named_link_link_state_and_camera_the_robot_also_names_get_its_prefix(
    tmp_path: Path,
) -> None:
    spec = _arm_and_gripper(
        tmp_path,
        "{spec: gripper.yaml, at: tool0}",
        "named_links: {finger: upper_arm}\nlink_states: {tip: {link: finger}}\n"
        "cameras: {cam: {mount: upper_arm, width: 8, height: 8, fov: 1.0}}\n",
        "named_links: {finger: left_finger}\nlink_states: {tip: {link: finger}}\n"
        "cameras: {cam: {mount: left_finger, width: 8, height: 8, fov: 1.0}}\n",
    )
    robot = _compiled(spec).robot
    assert robot.named_links == (("finger", "upper_arm"), ("gripper_finger", "left_finger"))
    # the part's link state names the part's named link, by its new name
    assert [(s.name, s.links) for s in robot.link_states] == [
        ("tip", ("finger",)),
        ("gripper_tip", ("gripper_finger",)),
    ]
    assert [(c.uid, c.mount) for c in robot.cameras] == [
        ("cam", "upper_arm"),
        ("gripper_cam", "left_finger"),
    ]


def test_a_joint_the_parts_spec_leaves_passive_needs_no_controller_in_the_robots_modes(
    tmp_path: Path,
) -> None:
    two_fingers = (
        (EXAMPLES / "gripper.urdf")
        .read_text()
        .replace(
            "</robot>",
            '<link name="right_finger"/><joint name="right" type="prismatic"><parent link='
            '"base_link"/><child link="right_finger"/><axis xyz="0 1 0"/><limit lower="0" '
            'upper="0.03" effort="10" velocity="1"/></joint></robot>',
        )
    )
    (tmp_path / "two.urdf").write_text(two_fingers)
    (tmp_path / "two.yaml").write_text(
        "robospec: 1\nuid: two_fingers\ndescription: {urdf: two.urdf}\n"
        "passive_joints: [right]\nkeyframes: {rest: {qpos: [0, 0]}}\ncontrollers:\n"
        "  left: {type: pd_joint_pos, joints: [left], lower: 0, upper: 0.03, stiffness: 100,"
        " damping: 10, normalize_action: false}\n"
        "control_modes: {pd_joint_pos: {fingers: left}}\n"
    )
    spec = _arm_and_gripper(tmp_path, "{spec: two.yaml, at: tool0}")
    result = _compiled(spec)  # no RS302 for 'right', which no controller drives
    assert result.context.part_passive_joints == {"right"}


def test_a_material_the_robot_has_alike_is_shared_and_one_it_has_unlike_is_prefixed(
    tmp_path: Path,
) -> None:
    spec = _arm_and_gripper(tmp_path, "{spec: gripper.yaml, at: tool0}")
    unlike = _compiled(spec).robot.urdf_config
    # the part's materials come first, the robot's after them
    assert list(unlike["_materials"]) == ["gripper_rubber", "rubber"]
    text = spec.read_text()
    spec.write_text(
        text.replace("friction: 2, dynamic_friction: 2", "friction: 1, dynamic_friction: 1")
    )
    alike = _compiled(spec).robot.urdf_config
    assert list(alike["_materials"]) == ["rubber"]
    assert alike["link"]["left_finger"]["material"] == "rubber"


def test_the_robots_own_tcp_replaces_the_parts_and_its_problem_is_reported_in_its_spec(
    tmp_path: Path,
) -> None:
    # the gripper's spec gives a tcp too (left_finger)
    spec = _arm_and_gripper(tmp_path, "{spec: gripper.yaml, at: tool0}", "tcp: tool0\n")
    robot = _compiled(spec).robot
    assert robot.tcp is not None and robot.tcp.link == "tool0"
    spec.write_text(spec.read_text().replace("tcp: tool0", "tcp: no_such_link"))
    (found,) = [d for d in compile_spec(spec).diagnostics if d.code == "RS202"]
    assert (found.location.file, found.location.line) == (str(spec), 12)


def test_the_srdf_pairs_beside_the_robots_urdf_stay_apart_with_a_part_mounted(
    tmp_path: Path,
) -> None:
    (tmp_path / "gripper.urdf").write_text((EXAMPLES / "gripper.urdf").read_text())
    spec = tmp_path / "panda.yaml"
    spec.write_text(
        "robospec: 1\nuid: panda_gripper\n"
        "description: {urdf: '{maniskill_assets}/robots/panda/panda_v2.urdf'}\n"
        "parts: {gripper: {description: {urdf: gripper.urdf}, at: panda_hand}}\n"
        "controllers:\n  all: {type: pd_joint_pos, joints: '*', lower: null, upper: null,"
        " stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes: {pd_joint_pos: all}\n"
    )
    robot = _compiled(spec).robot
    panda, _ = load_description(str(maniskill_assets() / "robots/panda/panda_v2.urdf"), "urdf")
    assert panda is not None and panda.loader_collision_bits  # SAPIEN reads them beside it
    kept = {frozenset(entry) for entry in robot.never_collide.entries}
    assert {frozenset(links) for _, links in panda.loader_collision_bits} <= kept


# a part's spec with every section that names something: renamed, none of its names is left
EVERY_NAME = """robospec: 1
uid: named_panda
description: {urdf: "{maniskill_assets}/robots/panda/panda_v2.urdf"}
groups: {arm: "panda_joint[1-7]", gripper: "panda_finger_joint*"}
materials: {grip: {static_friction: 2, dynamic_friction: 2, restitution: 0}}
links: {"panda_*finger": {material: grip}}
controllers:
  arm: {type: pd_joint_pos, joints: arm, lower: null, upper: null, stiffness: 1e3, damping: 1e2}
  ee: {type: pd_ee_pose, joints: arm, ee_link: panda_hand_tcp, pos_lower: -0.1, pos_upper: 0.1,
       rot_lower: -0.1, rot_upper: 0.1, stiffness: 1e3, damping: 1e2, force_limit: 100}
  gripper: {type: pd_joint_pos_mimic, joints: gripper, lower: -0.01, upper: 0.04, stiffness: 1e3,
            damping: 1e2}
control_modes:
  pd_joint_pos: {arm: arm, gripper: gripper}
  pd_ee_pose: {arm: ee, gripper: gripper}
named_links: {finger1_link: panda_leftfinger, finger2_link: panda_rightfinger,
              tip_links: [panda_leftfinger_pad, panda_rightfinger_pad]}
tcp: {link: panda_hand_tcp, midpoint: [finger1_link, finger2_link], orientation: panda_hand}
grasping:
  is_grasping: {fingers: [{link: finger1_link, opening: +y}, {link: finger2_link, opening: -y}]}
is_fallen: {contact: {links: [panda_link0], force_above: 1}}
link_states:
  tip_poses: {links: tip_links, quantity: pose, stack_dim: -2}
  hand_pose: {link: panda_hand}
proprioception: [hand_pose, tip_poses]
disable_gravity: [panda_hand]
drives: [{parent: panda_leftfinger, child: panda_rightfinger, limit: {x: [-0.1, 0.1]}}]
cameras: {hand_camera: {mount: panda_hand, width: 16, height: 16, fov: 1.0}}
collision_rules: [{links: [panda_link0], group: 2, bit: 29}]
never_collide: [[panda_link5, panda_hand]]
"""
# what names nothing (types, kinds, the description and the spec's own file, values)
NAMES_NOTHING = {
    "uid", "class_name", "spec_path", "description", "keyframes", "is_static", "is_standing",
    "hooks", "base", "declared", "download_ids", "parts", "simulation",
}  # fmt: skip


def _strings(value: object, skip: frozenset[str] = frozenset()) -> list[str]:
    """Every string in ``value`` (dataclass fields but those in ``skip``, items, keys)."""
    from robospec.resolve.resolved import FileRef

    if isinstance(value, str):
        return [value]
    if dataclasses.is_dataclass(value) and not isinstance(value, FileRef | type):
        fields = [f.name for f in dataclasses.fields(value) if f.name not in skip]
        return [s for f in fields for s in _strings(getattr(value, f))]
    if isinstance(value, dict):
        return [s for k, v in value.items() for s in (*_strings(k), *_strings(v))]
    if isinstance(value, tuple | list):
        return [s for item in value for s in _strings(item)]
    return []


def test_renaming_a_robot_renames_every_joint_link_and_name_it_refers_to(tmp_path: Path) -> None:
    from robospec.resolve.resolved import Renaming

    (tmp_path / "named.yaml").write_text(EVERY_NAME)
    result = _compiled(tmp_path / "named.yaml")
    robot, description, spec = result.robot, result.description, result.context.spec
    sections = {
        "controllers": spec.controllers, "groups": spec.groups, "named_links": spec.named_links,
        "grasping": spec.grasping, "link_states": spec.link_states, "cameras": spec.cameras,
        "materials": spec.materials, "mode_keys": ("arm", "gripper"),
    }  # fmt: skip
    names = {section: {n: "p_" + n for n in given} for section, given in sections.items()}
    joints = {j.name: "p_" + j.name for j in description.joints}
    links = {n: "p_" + n for n in description.link_names}
    combined = dataclasses.replace(robot.description, relative="combined.urdf")
    renaming = Renaming(links, joints, names, ((robot.description, combined),))
    renamed = robot.renamed(renaming)
    old = {*links, *joints, *(n for given in names.values() for n in given)}
    assert old & set(_strings(robot, frozenset(NAMES_NOTHING)))  # it names them before
    assert old.isdisjoint(_strings(renamed, frozenset(NAMES_NOTHING)))
    ee = next(c for c in renamed.controllers if c.name == "p_ee")
    assert dict(ee.kwargs)["urdf_path"] == combined  # its IK chain runs in the combined one
    assert renamed.tcp is not None and renamed.tcp.midpoint == ("p_finger1_link", "p_finger2_link")


# -- what cannot be composed ----------------------------------------------------------------------


@pytest.mark.parametrize("example", ["fail_joint", "fail_prefix"])
def test_a_clash_no_prefix_fixes_is_an_error_at_the_part(tmp_path: Path, example: str) -> None:
    extra = "joint: shoulder" if example == "fail_joint" else "prefix: 'up'"
    spec = _arm_and_gripper(tmp_path, f"{{spec: gripper.yaml, at: tool0, {extra}}}")
    if example == "fail_prefix":  # the arm has upbase_link already: 'up' + base_link is taken
        arm = tmp_path / "arm.urdf"
        frame = (
            '<link name="upbase_link"/><joint name="extra" type="fixed">'
            '<parent link="tool0"/><child link="upbase_link"/></joint>'
        )
        arm.write_text(arm.read_text().replace("</robot>", frame + "</robot>"))
    result = compile_spec(spec)
    codes = [(d.code, d.location.line) for d in result.diagnostics if d.is_error]
    assert codes == [("RS732", 5)], [d.format_text() for d in result.diagnostics]
    assert result.robot is None


# -- authoring: inspect, doc, new --attach ---------------------------------------------------------


def test_inspect_names_the_arms_flange_frame_and_the_hands_root() -> None:
    import json

    from conftest import invoke_robospec

    robots = maniskill_assets() / "robots"
    arm = invoke_robospec("inspect", str(robots / "xarm7" / "xarm7.urdf"), "--format", "json")
    frames = json.loads(arm.stdout)["mounting_frames"]
    assert [(f["at"], f["role"]) for f in frames] == [
        ("link_eef", "flange"),
        ("link7", "flange"),
        ("link_base", "root"),
    ]
    assert "named as a tool flange" in frames[0]["why"]
    hand = invoke_robospec("inspect", str(robots / "ability_hand" / "ability_hand_right.urdf"))
    assert "mounted as a part by base_link: its root link" in hand.stdout
    assert "fold_frames leaves it out" in hand.stdout  # an empty frame over 'base'


def test_inspect_gives_an_mjcf_sites_pose_as_the_mounting_pose(tmp_path: Path) -> None:
    from corpus import BY_KEY, locate

    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.mounting import mounting_frames

    source, _ = read_description_file(locate(BY_KEY["dmc_jaco_arm"]))
    assert source is not None
    first = mounting_frames(source)[0]
    assert first.at == "b_6" and "site 'wristsite'" in first.why
    assert first.pose_yaml() == {"q": [0, 0.707106781, 0.707106781, 0]}


def test_the_card_shows_the_parts() -> None:
    from robospec.authoring.card import robot_card

    result = _compiled(COMPOSED)
    card = robot_card(result.robot, result.description, "xarm7_ability.yaml")
    section = card.split("## Parts", 1)[1].split("\n## ", 1)[0]
    assert "| `hand` | spec `ability_hand_right.yaml` | `link_eef` |" in section
    assert "`joint_eef`" in section and "`link_eef`, `base_link`, `base_joint`" in section


def test_new_attach_mounts_a_spec_at_the_arms_flange_without_simulating(tmp_path: Path) -> None:
    from conftest import invoke_robospec

    for name in ("arm.urdf", "gripper.urdf", "gripper.yaml"):
        (tmp_path / name).write_text((CODE_EXAMPLES / "RS730" / name).read_text())
    out = tmp_path / "arm.yaml"
    result = invoke_robospec(
        "new", str(tmp_path / "arm.urdf"), "-o", str(out), "--no-sim", "--attach",
        str(tmp_path / "gripper.yaml"),
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    text = out.read_text()
    assert "parts: # robots mounted on this one" in text
    assert "  gripper: {spec: gripper.yaml, at: tool0}\n" in text  # the first mounting frame
    assert "never_collide" not in text  # the seam is sampled in ManiSkill only
    compiled = _compiled(out)
    assert [p.name for p in compiled.robot.parts] == ["gripper"]


def test_new_attach_says_which_link_it_cannot_mount_on(tmp_path: Path) -> None:
    from conftest import invoke_robospec

    for name in ("arm.urdf", "gripper.urdf", "gripper.yaml"):
        (tmp_path / name).write_text((CODE_EXAMPLES / "RS730" / name).read_text())
    out = tmp_path / "arm.yaml"
    attach = f"{tmp_path / 'gripper.yaml'}@tool1"
    result = invoke_robospec(
        "new", str(tmp_path / "arm.urdf"), "-o", str(out), "--no-sim", "--attach", attach
    )
    assert result.exit_code == 1
    assert "error[RS742]" in result.output and "did you mean 'tool0'?" in result.output


def test_a_parts_mends_apply_to_its_description_before_it_is_mounted(tmp_path: Path) -> None:
    hand = HAND.read_text().replace(
        '/ability_hand_right.urdf"', '/ability_hand_right.urdf"\n  mend: {mimic: controller}'
    )
    (tmp_path / "ability_hand_right.yaml").write_text(hand)
    (tmp_path / "xarm7_ability.yaml").write_text(COMPOSED.read_text())
    result = _compiled(tmp_path / "xarm7_ability.yaml")
    assert "<mimic" not in result.robot.description.generated_text
    assert not any(d.code == "RS309" for d in result.diagnostics)
    assert all(j.mimic is None for j in result.description.joints)


def test_optimize_stops_at_a_robot_with_parts_at_its_parts_line(tmp_path: Path) -> None:
    from robospec.optimize.command import run_optimize
    from robospec.optimize.options import OptimizeOptions

    spec = SPECS / "composed" / "xarm7_ability.yaml"
    report, diagnostics = run_optimize(spec, tmp_path / "out.yaml", OptimizeOptions())
    assert report is None and not (tmp_path / "out.yaml").exists()
    (stop,) = [d for d in diagnostics if d.is_error]
    parts_line = spec.read_text().splitlines().index("parts:") + 1
    assert (stop.code, stop.location.line) == ("RS743", parts_line)
