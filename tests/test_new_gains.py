"""The gains ``robospec new`` writes come from the robot: each joint's effective inertia at rest
(natural frequency 20 rad/s, critically damped), the gravity load it holds where gravity is
not cancelled, force limits from the description's ratings (a shortfall is RS609, naming the
rating), the MJCF actuators' own servo gains (gear squared); joints that cannot move get no
drive. All without simulation (``--no-sim``)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.authoring.description_file import read_description_file
from robospec.authoring.new.analysis import analyse
from robospec.authoring.new.joint_gains import loads
from robospec.diagnostics import has_errors
from robospec.pipeline import compile_spec

ROOT = Path(__file__).resolve().parent.parent

# one arm link: a 2 kg point-like mass 0.5 m out along x, turning about y at the origin, and a
# 1 kg slider on it; the inertias are small boxes about their centres
ARM = """<?xml version="1.0"?>
<robot name="lever">
  <link name="base"/>
  <link name="upper">
    <inertial><origin xyz="0.5 0 0"/><mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial>
  </link>
  <link name="slider">
    <inertial><origin xyz="0 0 0"/><mass value="1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="stuck">
    <inertial><origin xyz="0 0 0"/><mass value="0.1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="{effort}" velocity="2"/>
  </joint>
  <joint name="slide" type="prismatic">
    <parent link="upper"/><child link="slider"/><origin xyz="1 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" effort="0" velocity="1"/>
  </joint>
  <joint name="locked" type="revolute">
    <parent link="slider"/><child link="stuck"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0" effort="0" velocity="0"/>
  </joint>
</robot>
"""


def _scaffold(tmp_path: Path, text: str, suffix: str = ".urdf") -> tuple[dict, list]:
    description = tmp_path / f"robot{suffix}"
    description.write_text(text)
    out = tmp_path / "robot.yaml"
    result = run_new(description, out, None, force=False, simulate=False).write()
    assert not result.failed, result.diagnostics
    compiled = compile_spec(out)
    assert not has_errors(compiled.diagnostics), [d.format_text() for d in compiled.diagnostics]
    return YAML(typ="safe").load(out.read_text()), list(result.diagnostics)


def test_effective_inertia_is_everything_beyond_the_joint_about_its_axis(tmp_path: Path) -> None:
    path = tmp_path / "lever.urdf"
    path.write_text(ARM.format(effort=100))
    source, _ = read_description_file(path)
    assert source is not None
    found = loads(analyse(source), {"shoulder": 0.0, "slide": 0.0, "locked": 0.0}, gravity=True)
    # the arm (iyy 0.02 + 2 kg at 0.5 m) and the slider and the stuck link (1.1 kg at 1 m, their
    # own iyy 0.001 each)
    assert found["shoulder"].inertia == pytest.approx(0.02 + 2 * 0.25 + 0.002 + 1.1 * 1.0)
    assert found["slide"].inertia == pytest.approx(1.1)  # the mass it pushes
    # with the root held, the shoulder holds the weight of everything beyond it; the slider
    # slides horizontally: gravity does not push it along its axis
    assert abs(found["shoulder"].held) == pytest.approx(9.81 * (2 * 0.5 + 1.1 * 1.0))
    assert found["slide"].held == pytest.approx(0.0, abs=1e-9)


def test_gains_are_critically_damped_at_20_rad_s_with_the_rating_as_force_limit(
    tmp_path: Path,
) -> None:
    data, diagnostics = _scaffold(tmp_path, ARM.format(effort=100))
    # the slider's effort="0": the description's own sanity warning (RS091), no gain warning
    assert [d.code for d in diagnostics] == ["RS091"], [d.format_text() for d in diagnostics]
    assert "'slide'" in diagnostics[0].message
    arm = data["controllers"]["arm_pos"]
    inertia = 0.02 + 2 * 0.25 + 0.002 + 1.1
    # a fixed robot under ManiSkill's gravity compensation holds no load: stiffness I w²
    assert arm["stiffness"]["shoulder"] == pytest.approx(inertia * 400, rel=1e-3)
    assert arm["damping"]["shoulder"] == pytest.approx(
        2 * math.sqrt(arm["stiffness"]["shoulder"] * inertia), rel=2e-3
    )
    assert arm["force_limit"]["shoulder"] == 100  # its <limit effort>
    # effort="0" is "not rated" (so100 writes it): the limit lets the drive span the range
    assert arm["stiffness"]["slide"] == pytest.approx(1.1 * 400, rel=1e-3)
    assert arm["force_limit"]["slide"] == pytest.approx(1.1 * 400 * 0.2, rel=2e-3)


def test_a_rating_too_low_for_the_gains_is_a_warning_that_names_it(tmp_path: Path) -> None:
    data, diagnostics = _scaffold(tmp_path, ARM.format(effort=5))
    (warning,) = [d for d in diagnostics if d.code == "RS609"]
    assert not warning.is_error
    # at the joint's element in the description, naming the rating and what is needed
    assert warning.location.file.endswith("robot.urdf")
    lines = ARM.splitlines()
    assert warning.location.line == lines.index('  <joint name="shoulder" type="revolute">') + 1
    assert "joint 'shoulder'" in warning.message and "<limit effort> of 5 N m" in warning.message
    inertia = 0.02 + 2 * 0.25 + 0.002 + 1.1
    needs = float(warning.message.split(" would need ")[1].split(" ")[0])
    assert needs == pytest.approx(0.1 * inertia * 400, 0.01)
    # never a silent raise: the rating stays the force limit, and the joint is softened to what
    # the rating can drive through check's 0.1 rad step
    arm = data["controllers"]["arm_pos"]
    assert arm["force_limit"]["shoulder"] == 5
    assert arm["stiffness"]["shoulder"] == pytest.approx(5 / 0.1)
    assert "softens it to stiffness 50" in warning.message


def test_joints_that_cannot_move_get_a_passive_controller_and_a_comment(tmp_path: Path) -> None:
    description = tmp_path / "robot.urdf"
    description.write_text(ARM.format(effort=100))
    out = tmp_path / "robot.yaml"
    assert not run_new(description, out, None, force=False, simulate=False).write().failed
    data = YAML(typ="safe").load(out.read_text())
    assert data["groups"]["immobile"] == ["locked"]
    assert data["controllers"]["immobile"] == {
        "type": "passive",
        "joints": "immobile",
        "damping": 0.0,
    }
    assert "locked" not in data["controllers"]["arm_pos"]["stiffness"]
    text = out.read_text()
    assert "Joints that cannot move" in text and "locked (its limits are equal ([0, 0])" in text
    # they cannot fall: gravity compensation stays on
    assert all("balance_passive_force" not in mode for mode in data["control_modes"].values())


SERVO = """<mujoco model="servo">
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.1"/>
      <body name="link" pos="0 0 0.2">
        <joint name="hinge" axis="0 1 0" range="-1 1" limited="true"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position joint="hinge" kp="10" kv="2" gear="3" forcerange="-4 4"/>
  </actuator>
</mujoco>
"""


def test_an_mjcf_position_servo_is_geared_squared(tmp_path: Path) -> None:
    data, _ = _scaffold(tmp_path, SERVO, ".xml")
    (controller,) = [c for c in data["controllers"].values() if c.get("type") == "pd_joint_pos"]
    # the joint feels gear times the force and moves gear times slower: kp g², kv g², |g| f
    assert (controller["stiffness"], controller["damping"], controller["force_limit"]) == (
        90,
        18,
        12,
    )
    # the joint's own damping damps it beside the servo's kv g² in MuJoCo: the drive takes both
    (tmp_path / "damped").mkdir()
    damped = SERVO.replace('limited="true"/>', 'limited="true" damping="0.5"/>')
    data, _ = _scaffold(tmp_path / "damped", damped, ".xml")
    (controller,) = [c for c in data["controllers"].values() if c.get("type") == "pd_joint_pos"]
    assert (controller["stiffness"], controller["damping"]) == (90, 18.5)
    # the model's own gains are what it was tuned with: robospec claims nothing about their
    # force, however small its forcerange (0.3 N m)
    (tmp_path / "weak").mkdir()
    _, diagnostics = _scaffold(tmp_path / "weak", SERVO.replace('"-4 4"', '"-0.1 0.1"'), ".xml")
    assert "RS609" not in {d.code for d in diagnostics}


def test_an_mjcf_joints_actuatorfrcrange_rates_its_motor(tmp_path: Path) -> None:
    # a motor (no servo gains of its own) on a joint whose actuatorfrcrange is 0.5 N m: far
    # less than the natural-frequency gains need for check's step
    text = SERVO.replace('limited="true"/>', 'limited="true" actuatorfrcrange="-0.5 0.5"/>')
    text = text.replace(
        '<position joint="hinge" kp="10" kv="2" gear="3" forcerange="-4 4"/>',
        '<motor name="drive" joint="hinge"/>',
    )
    data, diagnostics = _scaffold(tmp_path, text, ".xml")
    (controller,) = [c for c in data["controllers"].values() if c.get("type") == "pd_joint_pos"]
    assert controller["force_limit"] == 0.5
    (warning,) = [d for d in diagnostics if d.code == "RS609"]
    assert "more than its actuatorfrcrange of 0.5 N m" in warning.message
    assert (
        warning.location.line
        == text.splitlines().index('    <motor name="drive" joint="hinge"/>') + 1
    )


def test_joint_gains_span_each_unrated_joints_range_and_skip_the_immobile(tmp_path: Path) -> None:
    from robospec.authoring.new.joint_gains import joint_gains

    path = tmp_path / "lever.urdf"
    path.write_text(
        ARM.format(effort=100).replace(
            '<limit lower="0" upper="0.2" effort="0"', '<limit lower="-0.1" upper="0.2" effort="0"'
        )
    )
    source, _ = read_description_file(path)
    assert source is not None
    qpos = {"shoulder": 0.0, "slide": 0.0, "locked": 0.0}
    gains = joint_gains(analyse(source), qpos, gravity=False)
    assert set(gains) == {"shoulder", "slide"}  # the locked joint gets no drive
    # unrated: the drive spans the slide's 0.3 m range
    assert gains["slide"].force_limit == pytest.approx(1.1 * 400 * 0.3, rel=2e-3)
    # gravity off: no load held; on, the shoulder holds the arm's weight
    assert gains["shoulder"].load == 0.0
    assert joint_gains(analyse(source), qpos, gravity=True)["shoulder"].load == pytest.approx(
        9.81 * (2 * 0.5 + 1.1 * 1.0)
    )


# a stick on a foot: a 10 kg body whose centre of mass is 1 m above the ankle (pitch, about y),
# a yaw joint between them (about z), and a 1 kg foot below the ankle
STICK = """<?xml version="1.0"?>
<robot name="stick">
  <link name="body">
    <inertial><origin xyz="0 0 0"/><mass value="10"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <link name="shin">
    <inertial><origin xyz="0 0 0"/><mass value="0.001"/>
      <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial>
  </link>
  <link name="foot">
    <inertial><origin xyz="0 0 -0.05"/><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="yaw" type="revolute">
    <parent link="body"/><child link="shin"/><origin xyz="0 0 -0.5"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="100" velocity="2"/>
  </joint>
  <joint name="ankle" type="revolute">
    <parent link="shin"/><child link="foot"/><origin xyz="0 0 -0.5"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="{effort}" velocity="2"/>
  </joint>
</robot>
"""


def _stick_loads(tmp_path: Path, feet: tuple[tuple[str, ...], ...]) -> dict:
    from robospec.authoring.new.joint_loads import joint_loads

    path = tmp_path / "stick.urdf"
    path.write_text(STICK.format(effort=1000))
    source, _ = read_description_file(path)
    assert source is not None
    analysis = analyse(source)
    assert analysis.kinematics is not None
    qpos = {"yaw": 0.0, "ankle": 0.0}
    return joint_loads(analysis.kinematics, analysis.inertials, qpos, feet=feet)


def test_a_standing_joint_carries_the_robot_above_it_as_an_inverted_pendulum(
    tmp_path: Path,
) -> None:
    standing = _stick_loads(tmp_path, (("foot",),))
    # the ankle tips the 10 kg body (and the gram of shin) whose centre of mass is 1 m above it:
    # gravity's torque grows by m g h per radian it gives
    assert standing["ankle"].topple == pytest.approx(9.81 * 10.001 * 1.0, rel=1e-3)
    # turning about a vertical axis lifts nothing
    assert standing["yaw"].topple == pytest.approx(0.0, abs=1e-9)
    # not standing (on a test stand, a fixed robot), nothing topples
    assert _stick_loads(tmp_path, ())["ankle"].topple == 0.0


def test_gains_add_the_toppling_stiffness_and_never_soften_below_it() -> None:
    from robospec.authoring.new.gains import STANCE_MARGIN, analytic_gains
    from robospec.description.ratings import Rating

    free = analytic_gains("revolute", 0.01, 0.0, 2.0, None)
    standing = analytic_gains("revolute", 0.01, 0.0, 2.0, None, topple=100.0)
    # gravity takes the toppling stiffness away: what is left is what the joint needed alone
    assert standing.stiffness == pytest.approx(free.stiffness + 100.0)
    # a rating of 5 N m would soften the joint to 50 (5 N m for a 0.1 rad step): never below
    # the stance's own need
    rated = analytic_gains("revolute", 0.01, 0.0, 2.0, Rating(5.0, "<limit effort>", 1), 100.0)
    assert rated.stiffness == pytest.approx(STANCE_MARGIN * 100.0)
    assert rated.force_limit == 5.0


def test_a_rated_joint_holding_a_load_is_softened_to_what_the_rating_leaves_beyond_it() -> None:
    from robospec.authoring.new.gains import HOLD_DRIFT, STEP, analytic_gains
    from robospec.description.ratings import Rating

    rating = Rating(5.0, "<limit effort>", 1)
    # 2 N m of load held within 0.01 rad asks for 200 N m/rad, 22 N m with a 0.1 rad step: the
    # rating's 5 N m less the load's 2 leave 3 N m for the step, 30 N m/rad
    assert HOLD_DRIFT["revolute"] == pytest.approx(0.01) and STEP["revolute"] == 0.1
    rated = analytic_gains("revolute", 0.01, 2.0, 2.0, rating)
    assert rated.needs == pytest.approx(22.0)
    assert rated.stiffness == pytest.approx(30.0)
    assert rated.force_limit == 5.0 and rated.load == 2.0 and rated.over_rating
    # the load's sign (which way gravity turns the joint) changes nothing
    assert analytic_gains("revolute", 0.01, -2.0, 2.0, rating).stiffness == pytest.approx(30.0)
    # a slide: 20 N held within a millimetre (20 000 N/m) and a 1 cm step; its 50 N rating
    # leaves 30 N for the step: 3000 N/m
    slide = analytic_gains("prismatic", 1.0, 20.0, 0.2, Rating(50.0, "<limit effort>", 1))
    assert slide.stiffness == pytest.approx(3000.0)
    # a load the rating cannot hold at all: nothing to soften to, the joint keeps the stiffness
    # that holds the load (RS609 says it cannot hold the rest pose)
    beyond = analytic_gains("revolute", 0.01, 6.0, 2.0, rating)
    assert beyond.stiffness == pytest.approx(600.0)
    # within its rating, a joint keeps its natural frequency: I w²
    free = analytic_gains("revolute", 0.01, 0.0, 2.0, Rating(50.0, "<limit effort>", 1))
    assert free.stiffness == pytest.approx(4.0) and not free.over_rating
    # a rating of just what the step needs (4 N m/rad x 0.1 rad) is enough
    just = analytic_gains("revolute", 0.01, 0.0, 2.0, Rating(0.4, "<limit effort>", 1))
    assert just.stiffness == pytest.approx(4.0) and not just.over_rating


def test_an_unrated_joints_force_limit_spans_its_range_on_top_of_its_load() -> None:
    from robospec.authoring.new.gains import UNBOUNDED_SPAN, analytic_gains

    # 2 N m of load, 200 N m/rad across a 1.5 rad range: the limit never clips the drive
    assert analytic_gains("revolute", 0.01, 2.0, 1.5, None).force_limit == pytest.approx(302.0)
    # unbounded (continuous): half a turn either way
    unbounded = analytic_gains("revolute", 0.01, 2.0, None, None).force_limit
    assert unbounded == pytest.approx(2.0 + 200.0 * UNBOUNDED_SPAN, rel=1e-3)
    infinite = analytic_gains("revolute", 0.01, 2.0, math.inf, None).force_limit
    assert infinite == pytest.approx(unbounded)
    # a range shorter than check's step: the step's reach
    assert analytic_gains("revolute", 0.01, 0.0, 0.01, None).force_limit == pytest.approx(0.4)


# two joints in a chain, one with a placeholder range of ±10 rad (more than a turn)
WIDE = """<?xml version="1.0"?>
<robot name="wide">
  <link name="base"/>
  <link name="a"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="b"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
    <limit lower="-10" upper="10" effort="100" velocity="2"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="a"/><child link="b"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1.5" effort="100" velocity="2"/>
  </joint>
</robot>
"""


def test_a_joint_whose_range_spans_more_than_a_turn_takes_targets_one_turn_about_rest(
    tmp_path: Path,
) -> None:
    data, _ = _scaffold(tmp_path, WIDE)
    (name,) = [n for n, c in data["controllers"].items() if c.get("type") == "pd_joint_pos"]
    controller = data["controllers"][name]
    # one turn about its rest (0) for the wide joint; the other keeps its own limits
    assert controller["lower"] == {"j1": pytest.approx(-math.pi, abs=1e-5), "j2": -1}
    assert controller["upper"] == {"j1": pytest.approx(math.pi, abs=1e-5), "j2": 1.5}
    # and an ordinary robot's targets are its joints' limits (null)
    (tmp_path / "arm").mkdir()
    arm, _ = _scaffold(tmp_path / "arm", ARM.format(effort=100))
    assert arm["controllers"]["arm_pos"]["lower"] is None
    assert arm["controllers"]["arm_pos"]["upper"] is None


def test_a_robot_written_y_up_is_stood_upright_and_its_loads_computed_so(tmp_path: Path) -> None:
    from robospec.authoring.new.joint_loads import joint_loads
    from robospec.geometry import matrix_from_quaternion

    text = (ROOT / "tests" / "data" / "new" / "quadruped.urdf").read_text()
    # the same robot under a root link whose frame is y-up (graphics' and motion capture's
    # convention): its legs point along -y of the root
    turned = text.replace(
        '<robot name="quad">',
        '<robot name="quad"><link name="yup"/><joint name="yup_to_body" type="fixed">'
        '<parent link="yup"/><child link="body"/><origin rpy="-1.5707963267948966 0 0"/>'
        "</joint>",
    )
    found = {}
    for name, body in (("zup", text), ("yup", turned)):
        path = tmp_path / f"{name}.urdf"
        path.write_text(body)
        source, _ = read_description_file(path)
        assert source is not None
        analysis = analyse(source)
        assert analysis.body.floating and analysis.kinematics is not None
        qpos = analysis.start_qpos()
        upright = analysis.upright(qpos)
        loads = joint_loads(
            analysis.kinematics,
            analysis.inertials,
            qpos,
            feet=analysis.feet(),
            upright=matrix_from_quaternion(upright),
        )
        found[name] = (upright, loads)
    assert found["zup"][0] == (1.0, 0.0, 0.0, 0.0)
    # a quarter turn about x takes its y to z
    assert found["yup"][0] == pytest.approx((math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0))
    # stood upright, each joint carries what it carries written z-up
    for joint, load in found["zup"][1].items():
        turned_load = found["yup"][1][joint]
        assert turned_load.held == pytest.approx(load.held, abs=1e-9), joint
        assert turned_load.standing == pytest.approx(load.standing, abs=1e-9), joint
        assert turned_load.topple == pytest.approx(load.topple, abs=1e-9), joint


MOCAP = """<mujoco model="mocap_arm">
  <worldbody>
    <body name="target" mocap="true" pos="0.3 0 0.5"/>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.1"/>
      <body name="upper" pos="0 0 0.2">
        <joint name="shoulder" axis="0 1 0" range="-1 1" limited="true"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="hand" pos="0.3 0 0">
          <joint name="wrist" axis="0 1 0" range="-1 1" limited="true"/>
          <geom type="box" size="0.03 0.03 0.03"/>
          <body name="jaw" pos="0.05 0 0">
            <joint name="jaw_joint" axis="0 1 0" range="0 0.5" limited="true"/>
            <geom type="box" size="0.03 0.01 0.01"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <equality>
    <weld body1="target" body2="hand"/>
  </equality>
  <actuator>
    <motor joint="jaw_joint" ctrlrange="-1 1" gear="2"/>
  </actuator>
</mujoco>
"""


def test_joints_a_weld_to_a_mocap_body_moves_are_driven_not_passive(tmp_path: Path) -> None:
    # no actuator drives the arm: MuJoCo moves it by its mocap body, welded to the hand
    # (gym-xarm's xArm7); the joints between the root and the hand get drives, the jaw's its
    # actuator's, and nothing is passive
    description = tmp_path / "robot.xml"
    description.write_text(MOCAP)
    source, _ = read_description_file(description)
    assert source is not None
    assert source.description.mocap_welds == ("hand",)
    data, _ = _scaffold(tmp_path, MOCAP, ".xml")
    kinds = {c.get("type") for c in data["controllers"].values()}
    assert "passive" not in kinds
    driven = {
        joint
        for c in data["controllers"].values()
        if c.get("type") == "pd_joint_pos"
        for joint in data["groups"][c["joints"]]
    }
    assert {"shoulder", "wrist"} <= driven
    # without the weld the arm is passive, as in MuJoCo
    (tmp_path / "free").mkdir()
    loose, _ = _scaffold(
        tmp_path / "free", MOCAP.replace('<weld body1="target" body2="hand"/>', ""), ".xml"
    )
    assert "passive" in {c.get("type") for c in loose["controllers"].values()}
