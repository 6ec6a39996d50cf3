"""``robospec new`` gives a wheeled robot, a base on a URDF ``planar`` or ``floating`` root joint
and a platform with no joint at all a drivable planar base (the spec's ``mobile_base``), as
ManiSkill's guide builds one: in ManiSkill's Empty-v1 a forward command of the base controller
drives the robot forward and a turn command turns it, with the wheels out of the floor's
collisions (group 2, bit 30, which the scene sets on the ground)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import run_robospec
from corpus import BY_KEY, CorpusMissing, locate
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.pipeline import compile_spec

STEPS = 100  # control steps of each command
MIN_TRAVEL = 0.3  # m, forward in STEPS
MIN_TURN = 0.3  # rad, in STEPS


CASTER_CART = Path(__file__).parent / "data" / "new" / "caster_cart.xml"
CART_SPEC = """\
robospec: 1
uid: {uid}
description: {{mjcf: "{path}", loader: mujoco}}
mobile_base: {{wheels: [left_wheel, right_wheel, caster], wheel_joints: fixed, height: 0.1}}
"""
FLOOR_GROUP, FLOOR_BIT = 2, 30

# a platform with no joint: one box standing on the floor
PLATFORM = """<?xml version="1.0"?>
<robot name="platform">
  <link name="deck">
    <inertial><origin xyz="0 0 0.1"/><mass value="20"/>
      <inertia ixx="0.2" ixy="0" ixz="0" iyy="0.4" iyz="0" izz="0.5"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.6 0.4 0.2"/></geometry></collision>
  </link>
</robot>
"""

# a cart whose base moves on a root joint of KIND (planar, floating) below a world link
ROOT_JOINT = """<?xml version="1.0"?>
<robot name="cart">
  <link name="world"/>
  <joint name="world_to_cart" type="{kind}">
    <parent link="world"/><child link="cart"/><origin xyz="0 0 0.15"/>
  </joint>
  <link name="cart">
    <inertial><mass value="10"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
    <collision><geometry><box size="0.5 0.3 0.2"/></geometry></collision>
  </link>
  <joint name="mast_joint" type="prismatic">
    <parent link="cart"/><child link="mast"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.3" effort="100" velocity="0.5"/>
  </joint>
  <link name="mast">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><box size="0.05 0.05 0.4"/></geometry></collision>
  </link>
</robot>
"""


def _scaffold(description: Path, out: Path, simulate: bool = False) -> dict:
    """What new writes, validated as validate would."""
    result = run_new(description, out, None, force=False, simulate=simulate).write()
    assert not result.failed, [d.format_text() for d in result.diagnostics]
    compiled = compile_spec(out)
    assert [d.format_text() for d in compiled.diagnostics if d.is_error] == []
    return YAML(typ="safe").load(out.read_text())


def _corpus(key: str) -> Path:
    try:
        return locate(BY_KEY[key])
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)


def test_a_platform_with_no_joint_becomes_a_base_to_drive_not_an_error(tmp_path: Path) -> None:
    (tmp_path / "platform.urdf").write_text(PLATFORM)
    data = _scaffold(tmp_path / "platform.urdf", tmp_path / "platform.yaml")
    assert data["mobile_base"] == {"wheels": ["deck"]}  # the deck slides over the floor
    assert data["groups"] == {"base": ["base_x_joint", "base_y_joint", "base_yaw_joint"]}
    # its one controller is the section's: no mode of its own
    assert "controllers" not in data and "control_modes" not in data
    assert "it has no joint that moves" in (tmp_path / "platform.yaml").read_text()


@pytest.mark.parametrize("kind", ["planar", "floating"])
def test_a_planar_or_floating_root_joint_becomes_the_base_s_slides_and_hinge(
    tmp_path: Path, kind: str
) -> None:
    urdf = tmp_path / f"{kind}.urdf"
    urdf.write_text(ROOT_JOINT.format(kind=kind))
    data = _scaffold(urdf, tmp_path / f"{kind}.yaml")
    assert data["mobile_base"] == {"wheels": ["cart"]}
    assert data["groups"]["base"] == ["base_x_joint", "base_y_joint", "base_yaw_joint"]
    # the mast keeps its own controllers; the base's joins every mode
    assert {c["joints"] for c in data["controllers"].values() if "joints" in c} == {"arm"}
    said = (tmp_path / f"{kind}.yaml").read_text()
    assert f"{kind} joint" in said and "SAPIEN" in said


def test_a_wheeled_robot_drives_its_base_instead_of_its_wheels(tmp_path: Path) -> None:
    data = _scaffold(_corpus("pb_husky"), tmp_path / "husky.yaml")
    assert "loader" not in data  # the base's chain starts from a fixed root
    assert data["mobile_base"]["wheel_joints"] == "fixed"
    assert data["mobile_base"]["wheels"] == [
        f"{end}_{side}_wheel_link" for end in ("front", "rear") for side in ("left", "right")
    ]
    assert "wheels" not in data["groups"]  # welded: nothing left to drive by joint velocity
    said = (tmp_path / "husky.yaml").read_text()
    assert "add those joints" not in said and "pd_base_vel" in said


@pytest.mark.slow  # a child process: over a second
def test_a_fixed_frame_is_a_platform_to_drive_on_the_command_line(tmp_path: Path) -> None:
    body = '<link name="a"/><link name="b"/>\n<joint name="j" type="fixed">'
    urdf = tmp_path / "frame.urdf"
    urdf.write_text(
        f'<robot name="frame">{body}<parent link="a"/><child link="b"/></joint></robot>'
    )
    out = tmp_path / "frame.yaml"
    result = run_robospec("new", str(urdf), "-o", str(out), "--no-sim")
    assert result.returncode == 0, result.stderr
    assert "RS602" not in result.stderr
    assert "mobile_base" in out.read_text()


def _drive(
    spec: Path, base_link: str, commands: list[list[float]]
) -> tuple[list[tuple[float, float]], list[str]]:
    """For each command to the base controller, from the rest keyframe in Empty-v1: how far
    the base link went forward (along its starting x axis) in STEPS steps, and how far it
    turned; and the links among the section's wheels that still collide with the floor."""
    from robospec import register
    from robospec.maniskill.headless import make_empty_env

    compiled = compile_spec(spec)
    assert compiled.robot is not None and compiled.robot.mobile_base is not None
    base = compiled.robot.mobile_base
    register(spec)
    env = make_empty_env(compiled.robot.uid)
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        offset = 0
        for name, controller in agent.controller.controllers.items():
            if name == base.controller:
                break
            offset += controller.action_space.shape[0]
        link = agent.robot.links_map[base_link]
        moves = []
        for command in commands:
            env.reset(seed=0)
            action = np.zeros(env.action_space.shape, dtype=np.float32)
            action[offset : offset + 3] = command
            p0, yaw0 = _planar(link.pose)
            for _ in range(STEPS):
                env.step(action)
            assert np.isfinite(agent.robot.get_qpos().numpy()).all()
            p1, yaw1 = _planar(link.pose)
            forward = float((p1 - p0) @ np.array([math.cos(yaw0), math.sin(yaw0)]))
            moves.append((forward, math.remainder(yaw1 - yaw0, 2 * math.pi)))
        touching = [
            name
            for name in base.wheels
            for body in agent.robot.links_map[name]._bodies
            for shape in body.get_collision_shapes()
            if not shape.get_collision_groups()[FLOOR_GROUP] & (1 << FLOOR_BIT)
        ]
        return moves, touching
    finally:
        env.close()


def _planar(pose: object) -> tuple[np.ndarray, float]:
    p = pose.p[0].numpy()  # type: ignore[attr-defined]
    w, x, y, z = pose.q[0].numpy().tolist()  # type: ignore[attr-defined]
    return p[:2], math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


@pytest.mark.maniskill
@pytest.mark.minutes
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize(
    ("robot", "base_link"),
    [
        ("pb_husky", "base_footprint"),
        ("pb_r2d2", "base_link"),
        ("pb_racecar", "base_link"),
        ("platform", "deck"),
        # an MJCF on two hinge wheels and a ball caster, compiled by MuJoCo
        ("caster_cart", "chassis"),
    ],
)
def test_a_scaffolded_base_drives_forward_and_turns_with_its_wheels_off_the_floor(
    tmp_path: Path, maniskill: object, robot: str, base_link: str
) -> None:
    if robot == "platform":
        description = tmp_path / "platform.urdf"
        description.write_text(PLATFORM)
    elif robot == "caster_cart":
        description = CASTER_CART
    else:
        description = _corpus(robot)
    spec = tmp_path / f"{robot}.yaml"
    uid = _scaffold(description, spec, simulate=True)["uid"]  # as users run it
    moves, touching = _drive(spec, base_link, [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    (forward, _), (_, turned) = moves
    assert forward >= MIN_TRAVEL, f"{uid} went {forward:.3f} m forward"
    assert turned >= MIN_TURN, f"{uid} turned {turned:.3f} rad"
    assert touching == []  # the wheels (the platform's deck) are out of the floor's collisions


def test_a_base_rides_at_its_height_above_the_floor_where_the_slides_lie(tmp_path: Path) -> None:
    from lxml import etree

    from robospec.authoring.description_file import read_description_file
    from robospec.model.mechanisms import MobileBase
    from robospec.resolve.description_loading import mobile_base_settings

    (tmp_path / "platform.urdf").write_text(PLATFORM)
    settings = mobile_base_settings(MobileBase(height=0.25))
    source, _ = read_description_file(
        tmp_path / "platform.urdf", sections={"mobile_base": settings}
    )
    assert source is not None
    root = etree.fromstring(source.text)
    (slide,) = [j for j in root.iter("joint") if j.get("name") == "base_x_joint"]
    assert slide.find("origin").get("xyz") == "0 0 0.25"


def _caster_cart(tmp_path: Path, uid: str) -> Path:
    spec = tmp_path / "cart.yaml"
    spec.write_text(CART_SPEC.format(uid=uid, path=CASTER_CART.as_posix()), encoding="utf-8")
    return spec


def test_an_mjcf_bases_welded_wheels_take_their_actuators_with_them(tmp_path: Path) -> None:
    """An MJCF cart on two hinge wheels and a ball caster, compiled by MuJoCo: the base's
    slides and hinge replace its free joint, the wheels' joints go, and so do the velocity
    actuators on them (MuJoCo refuses a model that names a joint it does not have)."""
    result = compile_spec(_caster_cart(tmp_path, "caster_cart"))
    assert result.ok, [d.format_text() for d in result.diagnostics]
    assert result.robot is not None and result.description is not None
    assert result.robot.active_joints == ("base_x_joint", "base_y_joint", "base_yaw_joint")
    assert {"left_wheel", "right_wheel", "caster"} <= set(result.description.link_names)
    (note,) = [d for d in result.diagnostics if d.code == "RS780"]
    assert note.location.line == 7  # the chassis, and 5 more changes: 3 joints, 2 actuators
    assert "and 5 more" in note.message


def test_a_fixed_tendon_or_a_sensor_through_a_welded_wheel_goes_whole(tmp_path: Path) -> None:
    """A fixed tendon through both wheels goes as one change (a tendon that lost one of its
    joints would couple something else), a joint sensor on a wheel as another."""
    text = CASTER_CART.read_text(encoding="utf-8").replace(
        "  <actuator>",
        '  <tendon><fixed name="differential"><joint joint="left_wheel_joint" coef="1"/>'
        '<joint joint="right_wheel_joint" coef="-1"/></fixed></tendon>\n'
        '  <sensor><jointpos name="left_angle" joint="left_wheel_joint"/></sensor>\n'
        "  <actuator>",
    )
    cart = tmp_path / "cart.xml"
    cart.write_text(text, encoding="utf-8")
    spec = tmp_path / "cart.yaml"
    spec.write_text(CART_SPEC.format(uid="tendon_cart", path=cart.as_posix()), encoding="utf-8")
    result = compile_spec(spec)
    assert result.ok, [d.format_text() for d in result.diagnostics]
    (note,) = [d for d in result.diagnostics if d.code == "RS780"]
    assert "and 7 more" in note.message  # 3 joints, 2 actuators, the tendon, the sensor
    assert not any("tendon" in d.message for d in result.diagnostics if d.code == "RS791")


def test_an_mjcf_on_wheels_and_a_ball_caster_gets_a_base_to_drive(tmp_path: Path) -> None:
    """new writes the section for an MJCF that rolls (compiled by MuJoCo, its ball-jointed
    caster three hinges): the wheels are the MJCF's bodies, not the hinges' links."""
    data = _scaffold(CASTER_CART, tmp_path / "cart.yaml")
    assert data["description"]["loader"] == "mujoco"
    assert data["mobile_base"] == {
        "wheels": ["left_wheel", "right_wheel", "caster"],
        "wheel_joints": "fixed",
    }
    assert data["groups"] == {"base": ["base_x_joint", "base_y_joint", "base_yaw_joint"]}
