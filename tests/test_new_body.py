"""``robospec new`` scaffolds the body a description has, not just one that validates: legged and
wheeled URDFs and MJCF free joints float without ManiSkill's gravity compensation, legs are
named by side, a planar base gets a base controller, an MJCF's keyframes and actuator gains
are kept, joints no actuator drives stay passive. Scaffolded without ManiSkill (``--no-sim``);
tests/test_new_sim.py loads the same robots in it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import ROOT, maniskill_assets
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.authoring.new import rest_pose
from robospec.pipeline import compile_spec

DATA = ROOT / "tests" / "data" / "new"
QUADRUPED_URDF = DATA / "quadruped.urdf"
QUADRUPED_MJCF = DATA / "quadruped.xml"
INERTIAL = (
    '<inertial><mass value="1"/>'
    '<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'
)


def scaffold(description: Path, out: Path, simulate: bool = False) -> tuple[dict, str]:
    """The spec ``new`` writes (as data and as text), checked to validate with no errors."""
    result = run_new(description, out, None, force=False, simulate=simulate).write()
    assert not result.failed, result.diagnostics
    compiled = compile_spec(out)
    assert [d.format_text() for d in compiled.diagnostics if d.is_error] == []
    text = out.read_text()
    return YAML(typ="safe").load(text), text


def header(text: str) -> str:
    """The scaffold's comment lines at the top, joined into one paragraph of words."""
    lines = []
    for line in text.splitlines()[1:]:
        if not line.startswith("#"):
            break
        lines.append(line.lstrip("# "))
    return " ".join(" ".join(lines).split())


def modes_balance(data: dict) -> list[object]:
    return [mode.get("balance_passive_force") for mode in data["control_modes"].values()]


def test_a_legged_urdf_floats_and_its_legs_are_named_by_where_they_stand(tmp_path: Path) -> None:
    data, text = scaffold(QUADRUPED_URDF, tmp_path / "quad.yaml")
    assert data["loader"] == {"fix_root_link": False}
    # legs a..d stand front left, front right, rear left, rear right
    assert data["groups"] == {
        "fl": ["leg_a_hip_joint", "leg_a_thigh_joint", "leg_a_knee_joint"],
        "fr": ["leg_b_hip_joint", "leg_b_thigh_joint", "leg_b_knee_joint"],
        "rl": ["leg_c_hip_joint", "leg_c_thigh_joint", "leg_c_knee_joint"],
        "rr": ["leg_d_hip_joint", "leg_d_thigh_joint", "leg_d_knee_joint"],
    }
    assert modes_balance(data) == [False, False]
    said = header(text)
    assert "Floating base: it stands on 4 legs" in said
    assert "not contact-checked (robospec new --no-sim)" in said
    assert "set keyframes.rest.pose.p" in said  # no height was measured


def test_legs_keep_the_side_names_their_description_gives(tmp_path: Path) -> None:
    text = QUADRUPED_URDF.read_text()
    for leg, side in (("a", "LF"), ("b", "RF"), ("c", "LH"), ("d", "RH")):
        text = text.replace(f"leg_{leg}_", f"{side}_")
    anymal = tmp_path / "anymal_like.urdf"
    anymal.write_text(text)
    data, _ = scaffold(anymal, tmp_path / "anymal.yaml")
    assert list(data["groups"]) == ["lf", "rf", "lh", "rh"]
    assert data["groups"]["lh"] == ["LH_hip_joint", "LH_thigh_joint", "LH_knee_joint"]


def test_an_mjcf_free_joint_floats_and_keeps_the_files_keyframe_and_gains(tmp_path: Path) -> None:
    data, _ = scaffold(QUADRUPED_MJCF, tmp_path / "mjquad.yaml")
    assert data["loader"] == {"fix_root_link": False}
    assert list(data["groups"]) == ["fl", "fr", "rl", "rr"]  # front_left_hip... say so
    assert list(data["keyframes"]) == ["rest", "home"]
    # the key's free joint is the root body's pose, as a keyframe's pose means it for MJCF
    assert data["keyframes"]["home"]["pose"] == {"p": [0.0, 0.0, 0.33]}
    assert data["keyframes"]["home"]["qpos"]["rr"] == [0.2, -0.8]
    fl, rr = data["controllers"]["fl_pos"], data["controllers"]["rr_pos"]
    # position actuators: kp -> stiffness, kv plus the joint's own damping (0.5) -> damping,
    # force range -> force_limit; by joint where they differ
    assert fl["stiffness"] == {"front_left_hip": 200, "front_left_knee": 250}
    assert fl["damping"] == {"front_left_hip": 0.5, "front_left_knee": 4.5}
    assert fl["force_limit"] == {"front_left_hip": 40, "front_left_knee": 60}
    assert rr["stiffness"] == {"rear_right_hip": 220, "rear_right_knee": 250}
    assert modes_balance(data) == [False, False]


PLANAR_WALKER = """<mujoco model="walker">
  <worldbody>
    <body name="torso" pos="0 0 1">
      <joint name="rootx" type="slide" axis="1 0 0"/>
      <joint name="rootz" type="slide" axis="0 0 1"/>
      <joint name="rooty" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="-0.5 0 0 0.5 0 0" size="0.05"/>
      <body name="bthigh" pos="-0.5 0 0">
        <joint name="bthigh" axis="0 1 0" range="-30 60"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.04"/>
        <body name="bshin" pos="0 0 -0.3">
          <joint name="bshin" axis="0 1 0" range="-45 45"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.04"/>
        </body>
      </body>
      <body name="fthigh" pos="0.5 0 0">
        <joint name="fthigh" axis="0 1 0" range="-30 60"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.04"/>
        <body name="fshin" pos="0 0 -0.3">
          <joint name="fshin" axis="0 1 0" range="-45 45"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.04"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="bthigh" gear="120" ctrlrange="-1 1"/>
    <motor joint="bshin" gear="90" ctrlrange="-1 1"/>
    <motor joint="fthigh" gear="120" ctrlrange="-1 1"/>
    <motor joint="fshin" gear="60" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""


def test_joints_no_actuator_drives_stay_passive_and_motors_give_force_limits(
    tmp_path: Path,
) -> None:
    walker = tmp_path / "walker.xml"
    walker.write_text(PLANAR_WALKER)
    data, text = scaffold(walker, tmp_path / "walker.yaml")
    # the sliding root moves the robot: it stays fixed where ManiSkill puts it
    assert "loader" not in data
    assert data["groups"] == {
        "base": ["rootx", "rootz", "rooty"],
        "rear_leg": ["bthigh", "bshin"],  # both legs on the centre line: front and rear
        "front_leg": ["fthigh", "fshin"],
    }
    assert data["controllers"]["base"] == {"type": "passive", "joints": "base", "damping": 0.0}
    assert data["controllers"]["rear_leg_pos"]["force_limit"] == {"bthigh": 120, "bshin": 90}
    assert modes_balance(data) == [False, False]  # gravity is not cancelled on passive joints
    assert "Joints no MJCF actuator drives are passive" in header(text)


def test_an_mjcf_with_legs_and_no_free_joint_is_told_how_to_stand(tmp_path: Path) -> None:
    welded = tmp_path / "welded.xml"
    welded.write_text(QUADRUPED_MJCF.read_text().replace('<freejoint name="root"/>', ""))
    data, text = scaffold(welded, tmp_path / "welded.yaml")
    assert "loader" not in data  # ManiSkill's MJCF loader welds such a root whatever we say
    assert "add <freejoint/> to the root body" in header(text)


def _urdf(path: Path, name: str, links: list[str], joints: list[str]) -> Path:
    body = "".join(f'<link name="{link}">{INERTIAL}</link>\n' for link in links)
    path.write_text(
        f'<?xml version="1.0"?>\n<robot name="{name}">\n{body}{"".join(joints)}</robot>\n'
    )
    return path


def _joint(
    name: str, kind: str, parent: str, child: str, axis: str = "0 0 1", extra: str = ""
) -> str:
    limit = '<limit lower="-1" upper="1" effort="10" velocity="4"/>' if kind != "fixed" else ""
    if kind == "continuous":
        limit = '<limit effort="10" velocity="12"/>'
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<axis xyz="{axis}"/>{extra}{limit}</joint>\n'
    )


def test_a_robot_on_wheels_gets_a_planar_base_with_its_wheels_and_caster_off_the_floor(
    tmp_path: Path,
) -> None:
    rover = _urdf(
        tmp_path / "rover.urdf",
        "rover",
        ["chassis", "left_wheel", "right_wheel", "caster"],
        [
            _joint("left_wheel_joint", "continuous", "chassis", "left_wheel", "0 1 0"),
            _joint("right_wheel_joint", "continuous", "chassis", "right_wheel", "0 1 0"),
            _joint("caster_joint", "fixed", "chassis", "caster"),
        ],
    )
    data, text = scaffold(rover, tmp_path / "rover.yaml")
    assert "loader" not in data  # the base's slides start from a fixed root
    assert data["mobile_base"] == {
        "wheels": ["left_wheel", "right_wheel", "caster"],
        "wheel_joints": "fixed",
    }
    assert data["groups"] == {"base": ["base_x_joint", "base_y_joint", "base_yaw_joint"]}
    said = header(text)
    assert "it rolls on wheels (left_wheel_joint, right_wheel_joint)" in said
    assert "pd_base_vel" in said and "add those joints" not in said


@pytest.mark.parametrize(
    ("wheel", "controller"), [(False, "pd_base_vel"), (True, "pd_base_forward_vel")]
)
def test_planar_base_joints_get_a_base_controller(
    tmp_path: Path, wheel: bool, controller: str
) -> None:
    links = ["odom", "slide_x", "slide_y", "base_link", "upper_arm", "forearm"]
    joints = [
        _joint("virtual_joint1", "prismatic", "odom", "slide_x", "1 0 0"),
        _joint("virtual_joint2", "prismatic", "slide_x", "slide_y", "0 1 0"),
        _joint("virtual_joint3", "revolute", "slide_y", "base_link", "0 0 1"),
        _joint("shoulder", "revolute", "base_link", "upper_arm", "0 1 0"),
        _joint("elbow", "revolute", "upper_arm", "forearm", "0 1 0"),
    ]
    if wheel:
        links.append("left_wheel_link")
        joints.append(_joint("left_wheel_mount", "fixed", "base_link", "left_wheel_link"))
    data, _ = scaffold(
        _urdf(tmp_path / "mobile.urdf", "mobile", links, joints), tmp_path / "m.yaml"
    )
    assert "loader" not in data  # the planar joints move the base: the root stays fixed
    assert data["groups"]["base"] == ["virtual_joint1", "virtual_joint2", "virtual_joint3"]
    assert data["groups"]["arm"] == ["shoulder", "elbow"]
    for mode in data["control_modes"].values():
        assert data["controllers"][mode["base"]]["type"] == controller


def test_legs_fixed_to_a_world_link_do_not_float(tmp_path: Path) -> None:
    text = QUADRUPED_URDF.read_text().replace(
        '<robot name="quad">',
        '<robot name="quad">\n<link name="world"/>\n<joint name="mount" type="fixed">'
        '<parent link="world"/><child link="body"/></joint>',
    )
    mounted = tmp_path / "mounted.urdf"
    mounted.write_text(text)
    data, _ = scaffold(mounted, tmp_path / "mounted.yaml")
    assert "loader" not in data
    assert modes_balance(data) == [None, None]
    assert list(data["groups"]) == ["fl", "fr", "rl", "rr"]


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@pytest.mark.parametrize(
    ("robot", "floating", "groups"),
    [
        ("humanoid/humanoid.xml", True, {"right_leg", "left_leg", "right_arm", "left_arm"}),
        ("g1_humanoid/g1_simplified_upper_body.urdf", False, {"left_arm", "right_arm"}),
        ("allegro/allegro_hand_right.urdf", False, {"finger1", "finger2", "finger3", "finger4"}),
    ],
)
def test_maniskills_own_robots_get_the_body_they_have(
    tmp_path: Path, robot: str, floating: bool, groups: set[str]
) -> None:
    data, _ = scaffold(maniskill_assets() / "robots" / robot, tmp_path / "spec.yaml")
    assert ("loader" in data) is floating
    assert groups <= set(data["groups"])


def test_without_maniskill_the_scaffold_says_its_pose_was_not_checked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the core install: nothing to load the robot in
    monkeypatch.setattr(rest_pose, "maniskill_installed", lambda: False)
    _, text = scaffold(QUADRUPED_URDF, tmp_path / "quad.yaml", simulate=True)
    said = header(text)
    assert "rest keyframe: not contact-checked (ManiSkill is not installed)" in said
    assert re.search(r"standing height was not measured", said)


def _hand_urdf() -> str:
    """A wrist of two hinges, a palm, four fingers of three joints (the last mimicking the one
    before, as a tendon couples them) and a thumb of four: the thumb is the longest chain."""
    box = '<collision><geometry><box size="0.01 0.01 0.02"/></geometry></collision>'
    limit = '<limit lower="0" upper="1.5" effort="1" velocity="1"/>'
    links = ["forearm", "wrist", "palm"]
    joints = [
        ("wrist_yaw", "forearm", "wrist", "0 0 0.05", ""),
        ("wrist_pitch", "wrist", "palm", "0 0 0.05", ""),
    ]
    # named as the Shadow hand's are (ffj1...): no gripper words in them
    fingers = [("ff", 3), ("mf", 3), ("rf", 3), ("lf", 3), ("th", 4)]
    for k, (finger, count) in enumerate(fingers):
        parent = "palm"
        for n in range(1, count + 1):
            link = f"{finger}{n}"
            links.append(link)
            origin = f"{0.02 * k - 0.04} 0 0.05" if n == 1 else "0 0 0.02"
            mimic = f'<mimic joint="{finger}j{n - 1}"/>' if n == 3 and count == 3 else ""
            joints.append((f"{finger}j{n}", parent, link, origin, mimic))
            parent = link
    body = "".join(f'<link name="{name}">{INERTIAL}{box}</link>' for name in links)
    body += "".join(
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{origin}"/><axis xyz="1 0 0"/>{limit}{mimic}</joint>'
        for name, parent, child, origin, mimic in joints
    )
    return f'<?xml version="1.0"?><robot name="hand">{body}</robot>'


def test_a_hand_whose_thumb_is_its_longest_finger_keeps_the_thumb_out_of_the_arm(
    tmp_path: Path,
) -> None:
    description = tmp_path / "hand.urdf"
    description.write_text(_hand_urdf())
    data, _ = scaffold(description, tmp_path / "hand.yaml")
    groups = data["groups"]
    # five chains part at the palm: the arm ends at the wrist, and the coupled finger joints
    # are a hand's, not a gripper's
    assert groups["arm"] == ["wrist_yaw", "wrist_pitch"]
    assert "gripper" not in groups and {"ffj2", "ffj3"} <= set(groups["hand"])
    assert [f"thj{n}" for n in range(1, 5)] in groups.values()


def _gripper(side: str, wrist_y: float, finger_y: str) -> str:
    s = side[0]
    limit = '<limit lower="0" upper="0.04" effort="10" velocity="1"/>'
    return (
        f'<link name="{side}_hand"/><link name="{s}_finger_l"/><link name="{s}_finger_r"/>'
        f'<joint name="{side}_wrist" type="revolute"><parent link="base"/>'
        f'<child link="{side}_hand"/><origin xyz="0 {wrist_y} 0"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
        f'<joint name="{s}_finger_l_joint" type="prismatic"><parent link="{side}_hand"/>'
        f'<child link="{s}_finger_l"/><origin xyz="0 {finger_y} 0.1"/><axis xyz="0 1 0"/>'
        f"{limit}</joint>"
        f'<joint name="{s}_finger_r_joint" type="prismatic"><parent link="{side}_hand"/>'
        f'<child link="{s}_finger_r"/><origin xyz="0 -0.0015 0.1"/><axis xyz="0 -1 0"/>'
        f"{limit}</joint>"
    )


def test_of_two_grippers_equally_wide_the_first_in_the_tree_holds_the_tcp(
    tmp_path: Path,
) -> None:
    # the left gripper's fingers lie 1e-13 m farther apart: rounding noise, as Baxter's
    # mirrored grippers differ by in its forward kinematics; the right one comes first
    urdf = tmp_path / "two_grippers.urdf"
    urdf.write_text(
        '<robot name="two_grippers"><link name="base"/>'
        + _gripper("right", -0.3, "0.0015")
        + _gripper("left", 0.3, "0.0015000000001")
        + "</robot>"
    )
    data, _ = scaffold(urdf, tmp_path / "two_grippers.yaml")
    assert data["tcp"]["link"] == "right_hand"


def _chains_urdf(path: Path, chains: dict[str, list[str]], trunk: list[str]) -> Path:
    """A root link, a serial ``trunk`` of revolute joints, and at its end one chain of revolute
    joints per entry of ``chains`` (joint names; each joint's child link is named after it)."""
    links, joints, parent = ["root"], [], "root"
    for name in trunk:
        links.append(f"{name}_link")
        joints.append(_joint(name, "revolute", parent, f"{name}_link", "0 1 0"))
        parent = f"{name}_link"
    end = parent
    for chain in chains.values():
        parent = end
        for name in chain:
            links.append(f"{name}_link")
            joints.append(_joint(name, "revolute", parent, f"{name}_link", "0 1 0"))
            parent = f"{name}_link"
    return _urdf(path, path.stem, links, joints)


def test_a_torso_parting_three_ways_is_no_palm_and_its_arms_are_no_legs(tmp_path: Path) -> None:
    # two arms and a head on a waist: no leg words, so no legs (the robot stays fixed), and
    # three ways is a torso, not a palm: the arm is the longest chain, waist to wrist
    torso = _chains_urdf(
        tmp_path / "torso.urdf",
        {
            "left": ["left_shoulder", "left_elbow", "left_wrist"],
            "right": ["right_shoulder", "right_elbow"],
            "head": ["neck"],
        },
        ["waist"],
    )
    data, text = scaffold(torso, tmp_path / "torso.yaml")
    assert "loader" not in data and "Floating base" not in header(text)
    assert data["groups"]["arm"] == ["waist", "left_shoulder", "left_elbow", "left_wrist"]


def test_four_chains_parting_at_one_link_hang_from_a_palm_where_the_arm_ends(
    tmp_path: Path,
) -> None:
    # three fingers of two joints and a thumb of three, named as the Shadow hand's (no gripper
    # words): the longest chain runs into the thumb, and the arm ends at the palm
    hand = _chains_urdf(
        tmp_path / "hand.urdf",
        {
            "ff": ["ffj1", "ffj2"],
            "mf": ["mfj1", "mfj2"],
            "rf": ["rfj1", "rfj2"],
            "th": ["thj1", "thj2", "thj3"],
        },
        ["shoulder", "elbow"],
    )
    data, _ = scaffold(hand, tmp_path / "hand.yaml")
    assert data["groups"]["arm"] == ["shoulder", "elbow"]
    assert ["thj1", "thj2", "thj3"] in data["groups"].values()


def test_chains_named_both_like_fingers_and_like_feet_are_fingers(tmp_path: Path) -> None:
    # each finger's tip link is its "foot": a hand word in the chain says it is no leg
    gripper = _urdf(
        tmp_path / "gripper.urdf",
        "gripper",
        ["palm", "left_a", "left_foot", "right_a", "right_foot"],
        [
            _joint("left_finger_1", "revolute", "palm", "left_a"),
            _joint("left_finger_2", "revolute", "left_a", "left_foot"),
            _joint("right_finger_1", "revolute", "palm", "right_a"),
            _joint("right_finger_2", "revolute", "right_a", "right_foot"),
        ],
    )
    data, text = scaffold(gripper, tmp_path / "gripper.yaml")
    assert "loader" not in data and "Floating base" not in header(text)
    assert not {"left_leg", "right_leg"} & set(data["groups"])


def test_an_mjcf_arm_without_legs_or_a_free_joint_is_not_told_to_add_one(tmp_path: Path) -> None:
    arm = tmp_path / "arm.xml"
    arm.write_text(
        '<mujoco model="arm"><compiler angle="radian"/><worldbody><body name="base">'
        '<geom type="box" size=".1 .1 .02"/><body name="upper" pos="0 0 .1">'
        '<joint name="shoulder" axis="0 1 0" range="-1 1"/>'
        '<geom type="capsule" size=".02 .1" pos="0 0 .1"/><body name="lower" pos="0 0 .2">'
        '<joint name="elbow" axis="0 1 0" range="-1 1"/>'
        '<geom type="capsule" size=".02 .1" pos="0 0 .1"/></body></body></body></worldbody>'
        "</mujoco>"
    )
    data, text = scaffold(arm, tmp_path / "arm.yaml")
    assert "loader" not in data
    assert "freejoint" not in header(text)


def _gripper_arm(path: Path, tcp: bool) -> Path:
    """Two hinges, then a flange and a hand welded on (as the Panda's link8 and hand), and two
    fingers sliding along y either side of the hand; the right finger's frame is turned half a
    turn about z (mirrored, as grippers mount their second finger)."""
    links = ["base", "upper", "lower", "flange", "hand", "left_finger", "right_finger"]
    joints = [
        _joint("shoulder", "revolute", "base", "upper", "0 1 0"),
        _joint("elbow", "revolute", "upper", "lower", "0 1 0", '<origin xyz="0 0 0.3"/>'),
        _joint("flange_joint", "fixed", "lower", "flange", extra='<origin xyz="0 0 0.2"/>'),
        _joint("hand_joint", "fixed", "flange", "hand", extra='<origin xyz="0 0 0.05"/>'),
        _joint(
            "left_finger_joint",
            "prismatic",
            "hand",
            "left_finger",
            "0 1 0",
            '<origin xyz="0 0.02 0.1"/>',
        ),
        _joint(
            "right_finger_joint",
            "prismatic",
            "hand",
            "right_finger",
            "0 1 0",
            '<origin xyz="0 -0.02 0.1" rpy="0 0 3.141592653589793"/>',
        ),
    ]
    if tcp:
        links.append("tcp")
        joints.append(_joint("tcp_joint", "fixed", "hand", "tcp", extra='<origin xyz="0 0 0.12"/>'))
    return _urdf(path, "gripper_arm", links, joints)


def test_each_finger_opens_away_from_the_other_along_its_own_axis(tmp_path: Path) -> None:
    data, _ = scaffold(_gripper_arm(tmp_path / "arm.urdf", tcp=True), tmp_path / "arm.yaml")
    # left opens along +y of the hand; the right finger's frame is turned: -y of the hand is
    # its +y
    assert data["grasping"]["is_grasping"]["fingers"] == [
        {"link": "left_finger", "opening": "+y"},
        {"link": "right_finger", "opening": "+y"},
    ]
    assert data["tcp"] == "tcp"  # a link welded to the fingers' parent, named so
    assert data["is_static"] == {"joints": "arm"}


def test_without_a_tcp_link_the_tcp_is_the_fingers_midpoint_on_their_parent(
    tmp_path: Path,
) -> None:
    data, _ = scaffold(_gripper_arm(tmp_path / "arm.urdf", tcp=False), tmp_path / "arm.yaml")
    assert data["tcp"] == {
        "link": "hand",
        "midpoint": ["left_finger", "right_finger"],
        "orientation": "hand",
    }


def test_a_gripper_of_one_jaw_closes_it_against_the_link_it_hangs_from(tmp_path: Path) -> None:
    # SO-101's gripper: one moving jaw on a fixed one (the hand link itself)
    links = ["base", "upper", "hand", "jaw"]
    joints = [
        _joint("shoulder", "revolute", "base", "upper", "0 1 0"),
        _joint("elbow", "revolute", "upper", "hand", "0 1 0", '<origin xyz="0 0 0.3"/>'),
        _joint("gripper", "revolute", "hand", "jaw", "1 0 0", '<origin xyz="0 0.03 0.01"/>'),
    ]
    data, _ = scaffold(_urdf(tmp_path / "jaw.urdf", "jaw", links, joints), tmp_path / "jaw.yaml")
    assert data["grasping"]["is_grasping"]["fingers"] == [
        {"link": "jaw", "opening": "+y"},  # away from the hand's centre, along its y
        {"link": "hand", "opening": "-y"},
    ]
    assert data["tcp"]["midpoint"] == ["jaw", "hand"]


def test_a_gripper_whose_knuckles_carry_its_fingers_grasps_with_the_fingers(
    tmp_path: Path,
) -> None:
    # the xArm gripper's: a knuckle each side turns on the hand and carries a finger, which
    # turns back as far (every joint a mimic of the first) and so stays parallel; the pads that
    # close on the cube are the fingers, farther out than the knuckles that hold them
    mimic = '<mimic joint="left_knuckle_joint"/>'
    links = ["base", "upper", "hand", "left_knuckle", "left_finger", "right_knuckle"]
    links.append("right_finger")
    joints = [
        _joint("shoulder", "revolute", "base", "upper", "0 1 0"),
        _joint("elbow", "revolute", "upper", "hand", "0 1 0", '<origin xyz="0 0 0.3"/>'),
        _joint(
            "left_knuckle_joint",
            "revolute",
            "hand",
            "left_knuckle",
            "1 0 0",
            '<origin xyz="0 0.03 0.05"/>',
        ),
        _joint(
            "left_finger_joint",
            "revolute",
            "left_knuckle",
            "left_finger",
            "-1 0 0",
            f'<origin xyz="0 0.03 0.04"/>{mimic}',
        ),
        _joint(
            "right_knuckle_joint",
            "revolute",
            "hand",
            "right_knuckle",
            "-1 0 0",
            f'<origin xyz="0 -0.03 0.05"/>{mimic}',
        ),
        _joint(
            "right_finger_joint",
            "revolute",
            "right_knuckle",
            "right_finger",
            "1 0 0",
            f'<origin xyz="0 -0.03 0.04"/>{mimic}',
        ),
    ]
    urdf = _urdf(tmp_path / "knuckles.urdf", "knuckles", links, joints)
    data, _ = scaffold(urdf, tmp_path / "knuckles.yaml")
    fingers = data["grasping"]["is_grasping"]["fingers"]
    assert [finger["link"] for finger in fingers] == ["left_finger", "right_finger"]
    assert data["tcp"]["midpoint"] == ["left_finger", "right_finger"]
    assert data["tcp"]["link"] == "hand"


def test_a_hand_of_finger_chains_grasps_with_the_tips_of_the_two_farthest_apart(
    tmp_path: Path,
) -> None:
    # three fingers of two joints on a palm, named fingerN by the scaffold; the outer two are
    # 8 cm apart, the middle one 4 cm from each; each ends in a fixed tip link
    links, joints = ["palm"], []
    for k, x in enumerate(["-0.04", "0", "0.04"], start=1):
        links += [f"p{k}", f"d{k}", f"tip{k}"]
        joints += [
            _joint(f"a{k}", "revolute", "palm", f"p{k}", "1 0 0", f'<origin xyz="{x} 0 0.05"/>'),
            _joint(f"b{k}", "revolute", f"p{k}", f"d{k}", "1 0 0", '<origin xyz="0 0 0.03"/>'),
            _joint(f"t{k}", "fixed", f"d{k}", f"tip{k}", extra='<origin xyz="0 0 0.02"/>'),
        ]
    data, _ = scaffold(_urdf(tmp_path / "hand.urdf", "hand", links, joints), tmp_path / "h.yaml")
    assert data["groups"] == {f"finger{k}": [f"a{k}", f"b{k}"] for k in (1, 2, 3)}
    assert data["grasping"]["is_grasping"]["fingers"] == [
        {"link": "tip1", "opening": "-x"},
        {"link": "tip3", "opening": "+x"},
    ]
    assert data["tcp"] == {"link": "palm", "midpoint": ["tip1", "tip3"], "orientation": "palm"}
    assert "is_static" not in data  # no arm
