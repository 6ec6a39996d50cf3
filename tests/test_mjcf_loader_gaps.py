"""What ManiSkill's MJCF loader drops or reads differently is reported at the MJCF element, once
per kind, with the mend where it is mechanical (robospec.description.mjcf_gaps). The fixtures
are tests/data/mjcf/gaps/; tests/test_mjcf_loader_gaps_sim.py loads each with ManiSkill and shows
the report true. Also here: MuJoCo's orientations, the facts ``robospec new`` takes from an MJCF
(keys, actuators), and the tree ``inspect`` shows."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CODE_EXAMPLES

from robospec.description import load_description
from robospec.description.facts import Mimic, RobotDescription
from robospec.description.mjcf_frames import (
    maniskill_rotation,
    mujoco_rotation,
    same_rotation,
)
from robospec.diagnostics import Diagnostic
from robospec.kinematics.tree import KinematicTree

DATA = Path(__file__).parent / "data" / "mjcf"
GAPS = DATA / "gaps"


def parse(path: Path) -> tuple[RobotDescription | None, list[Diagnostic]]:
    return load_description(str(path), "mjcf")


def found(path: Path) -> list[tuple[str, str, int]]:
    return [(d.code, d.severity.value, d.location.line) for d in parse(path)[1]]


def only(path: Path, code: str) -> Diagnostic:
    matches = [d for d in parse(path)[1] if d.code == code]
    assert len(matches) == 1, [d.format_text() for d in parse(path)[1]]
    return matches[0]


def chain(path: Path, bodies: int, axis: str | None = "0 0 1") -> Path:
    """A snake of ``bodies`` bodies on a free root, each a sphere on a hinge about ``axis``
    (None: the hinges write none)."""
    text = '<mujoco>\n<worldbody>\n<body name="b0" pos="0 0 .5"><freejoint/><geom size=".02"/>\n'
    axis_attribute = f' axis="{axis}"' if axis is not None else ""
    for i in range(1, bodies):
        text += (
            f'<body name="b{i}" pos=".05 0 0"><joint name="j{i}"{axis_attribute}/>'
            '<geom size=".02"/>\n'
        )
    text += "</body>" * bodies + "\n</worldbody>\n</mujoco>\n"
    path.write_text(text)
    return path


# -- each kind at its element ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("fixture", "expected"),
    [
        pytest.param(
            "coupling.xml",
            [
                ("RS070", "warning", 17),  # the joint coupling
                ("RS070", "warning", 18),  # the closed loop
                ("RS071", "warning", 21),
                ("RS077", "warning", 27),
            ],
            id="coupling",
        ),
        pytest.param(
            "contacts.xml",
            [("RS072", "warning", 30), ("RS073", "warning", 25), ("RS073", "warning", 8)],
            id="contacts",
        ),
        pytest.param(
            "mesh_scale.xml",
            [("RS074", "error", 5), ("RS074", "warning", 7), ("RS056", "error", 22)],
            id="mesh_scale",
        ),
        pytest.param("mesh_name.xml", [("RS085", "error", 11)], id="mesh_name"),
        pytest.param("main_class_mesh.xml", [("RS085", "error", 13)], id="main_class_mesh"),
        pytest.param("masses.xml", [("RS075", "warning", 8), ("RS076", "error", 10)], id="masses"),
        pytest.param(
            "orientation.xml",
            [("RS086", "note", 1), ("RS080", "error", 6)],  # its euler= is in degrees
            id="orientation",
        ),
        pytest.param("zaxis_floor.xml", [("RS080", "error", 4)], id="zaxis_floor"),
        pytest.param("hfield.xml", [("RS079", "error", 7)], id="hfield"),
        pytest.param("include.xml", [("RS082", "error", 6)], id="include"),
        pytest.param("wrapper.xml", [("RS083", "warning", 4)], id="wrapper"),
        pytest.param(
            "joint_attributes.xml",
            [("RS086", "note", 1), *[("RS084", "warning", 7)] * 3],  # its range is in degrees
            id="joint_attributes",
        ),
        pytest.param("groups.xml", [("RS078", "warning", 5)], id="groups"),
    ],
)
def test_each_thing_the_loader_drops_is_reported_once_at_its_element(
    fixture: str, expected: list[tuple[str, str, int]]
) -> None:
    assert found(GAPS / fixture) == expected


def test_a_mesh_the_root_class_main_names_is_predicted_at_the_geom_with_the_mend() -> None:
    diagnostic = only(GAPS / "main_class_mesh.xml", "RS085")
    assert "takes mesh 'cube_m' from default class 'main'" in diagnostic.message
    assert "KeyError: None" in diagnostic.message
    assert diagnostic.hint is not None and "{geom_meshes: defaults}" in diagnostic.hint


def test_a_joint_coupling_hint_writes_the_mimic_map_it_implies() -> None:
    # <joint joint1="right" joint2="left" polycoef="0 -1 0 0 0">: right = -left
    hint = parse(GAPS / "coupling.xml")[1][0].hint
    assert hint is not None
    assert "pd_joint_pos_mimic" in hint
    assert "mimic: {right: {joint: left, multiplier: -1}}" in hint


def test_a_tendon_equality_between_two_joints_is_a_mimic_map_too(tmp_path: Path) -> None:
    text = (GAPS / "coupling.xml").read_text()
    text = text.replace(
        '<joint joint1="right" joint2="left" polycoef="0 -1 0 0 0"/>',
        '<tendon tendon1="grip" polycoef=".01 0 0 0 0"/>',
    )
    (tmp_path / "tendon.xml").write_text(text)
    coupling = next(d for d in parse(tmp_path / "tendon.xml")[1] if d.code == "RS070")
    # left - right = 0.01  ->  right = left - 0.01
    assert coupling.hint is not None
    assert "mimic: {right: {joint: left, offset: -0.01}}" in coupling.hint
    # the tendon an equality uses is told there, not again as a lost tendon
    assert "RS071" not in {d.code for d in parse(tmp_path / "tendon.xml")[1]}


def test_a_narrow_fixed_tendon_of_two_joints_couples_them_led_by_the_actuated_one() -> None:
    # 0.007 j0 - 0.008 j1 in [-0.001, 0.001]: j0 = 8/7 j1 within 0.29 rad of its 1.6;
    # the wide tendon (0.007 j0 + 0.008 j1 in [-0.007, 0.03]) only bounds their sum
    description, _ = parse(DATA.parent / "new" / "tendon_finger.xml")
    assert description is not None
    (coupling,) = description.couplings
    assert (coupling.follower, coupling.mimic.joint) == ("j0", "j1")  # an actuator drives j1
    assert coupling.mimic.multiplier == pytest.approx(8 / 7)
    assert coupling.mimic.offset == 0
    assert coupling.what == "tendon 'couple'"


def test_equality_couplings_of_two_joints_are_couplings_of_the_description(
    tmp_path: Path,
) -> None:
    description, _ = parse(GAPS / "coupling.xml")  # right = -left
    assert description is not None
    assert [(c.follower, c.mimic) for c in description.couplings] == [
        ("right", Mimic("left", -1.0, 0.0))
    ]
    text = (GAPS / "coupling.xml").read_text()
    text = text.replace(
        '<joint joint1="right" joint2="left" polycoef="0 -1 0 0 0"/>',
        '<tendon tendon1="grip" polycoef=".01 0 0 0 0"/>',
    )
    (tmp_path / "tendon.xml").write_text(text)
    description, _ = parse(tmp_path / "tendon.xml")  # left - right = 0.01
    assert description is not None
    assert [(c.follower, c.mimic) for c in description.couplings] == [
        ("right", Mimic("left", 1.0, -0.01))
    ]


def test_excluded_contacts_and_filtered_pairs_hint_never_collide() -> None:
    diagnostics = parse(GAPS / "contacts.xml")[1]
    assert diagnostics[0].hint == "never_collide: [[a, b]]"
    pairs = diagnostics[2]
    assert "c + d" in pairs.message
    assert pairs.hint is not None and "[c, d]" in pairs.hint


def test_a_robot_mujoco_never_self_collides_is_hinted_disable_self_collisions(
    tmp_path: Path,
) -> None:
    # contype 1, conaffinity 0 everywhere (dm_control's walker): the robot touches the floor
    # only, in MuJoCo
    (tmp_path / "walker.xml").write_text(
        '<mujoco>\n<default><geom contype="1" conaffinity="0"/><joint axis="0 1 0"/></default>\n'
        "<worldbody>\n"
        '<body name="torso"><geom size=".1"/>\n'
        '<body name="thigh"><joint name="hip"/><geom size=".1"/>\n'
        '<body name="shin"><joint name="knee"/><geom size=".1"/>\n'
        "</body></body></body>\n</worldbody>\n</mujoco>\n"
    )
    (pairs,) = parse(tmp_path / "walker.xml")[1]
    assert (pairs.code, pairs.location.line) == ("RS073", 4)
    assert "torso + shin" in pairs.message
    assert pairs.hint is not None
    assert pairs.hint.startswith("loader: {disable_self_collisions: true}")


def test_a_mesh_a_thousand_times_too_large_is_an_error_and_names_the_default() -> None:
    error = next(d for d in parse(GAPS / "mesh_scale.xml")[1] if d.code == "RS074")
    assert error.is_error
    assert "'base' 1000 times the size the file means" in error.message
    assert error.hint == 'write scale="0.001 0.001 0.001" on each <mesh> element'


def test_file_masses_are_compared_with_what_the_loader_computes() -> None:
    masses = only(GAPS / "masses.xml", "RS075")
    # a capsule of radius 0.05 and half-length 0.2 at 1000 kg/m³
    assert "upper_arm: 8.393 kg in the file, 3.665 kg loaded" in masses.message


def test_the_skipped_ellipsoid_is_said_once_by_the_error_it_causes() -> None:
    ghost = only(GAPS / "masses.xml", "RS076")
    assert "'hand'" in ghost.message and "ellipsoid geoms are skipped" in ghost.message
    assert "'wrist'" in ghost.message
    assert "RS079" not in {d.code for d in parse(GAPS / "masses.xml")[1]}


def test_orientation_errors_name_the_frames_and_write_the_quaternion() -> None:
    error = only(GAPS / "orientation.xml", "RS080")
    # the body's euler and the capsule's euler differ; the sphere's xyaxes and the capsule's
    # zaxis (round about its axis) do not matter
    assert "'body tilted', 'geom snout'" in error.message
    assert "eye" not in error.message and "ear" not in error.message
    assert error.hint is not None and 'line 6: quat="0.965926 0 0.258819 0"' in error.hint


def test_an_unreadable_include_names_the_robot_maniskill_takes_instead() -> None:
    description, diagnostics = parse(GAPS / "include.xml")
    assert "the robot ManiSkill loads is body 'object'" in diagnostics[0].message
    assert description is None  # include errors are structure errors


def test_the_33rd_body_does_not_fit_and_the_31st_misses_the_floor(tmp_path: Path) -> None:
    assert found(chain(tmp_path / "c33.xml", 33)) == [("RS081", "error", 35)]
    ground = parse(chain(tmp_path / "c31.xml", 31))[1]
    assert [(d.code, d.severity.value) for d in ground] == [("RS081", "warning")]
    assert "body 'b30' (the 31st) and its parent 'b29'" in ground[0].message
    assert parse(chain(tmp_path / "c30.xml", 30))[1] == []


def test_a_clean_model_reports_nothing(tmp_path: Path) -> None:
    assert parse(DATA / "tree.xml")[1] == []


# -- orientations as MuJoCo and as ManiSkill read them ---------------------------------------------

# body_quat of MuJoCo 4.0 for each attribute (degrees unless said otherwise)
MUJOCO_QUATERNIONS = [
    ({"euler": "10 20 30"}, "xyz", True, (0.943714, 0.127679, 0.144878, 0.268536)),
    ({"euler": "10 20 30"}, "ZYX", True, (0.943714, 0.268536, 0.144878, 0.127679)),
    ({"euler": "10 20 30"}, "xYz", True, (0.951549, 0.127679, 0.144878, 0.239298)),
    ({"euler": "0.3 0.2 0.1"}, "xyz", False, (0.981856, 0.153439, 0.091158, 0.064071)),
    ({"xyaxes": "0 1 0 -1 0 0"}, "xyz", True, (0.707107, 0.0, 0.0, 0.707107)),
    ({"xyaxes": "1 0 0 0 2 2"}, "xyz", True, (0.92388, 0.382683, 0.0, 0.0)),
    ({"zaxis": "1 0 0"}, "xyz", True, (0.707107, 0.0, 0.707107, 0.0)),
    ({"zaxis": "0 1 1"}, "xyz", True, (0.92388, -0.382683, 0.0, 0.0)),
    ({"zaxis": "0 0 -1"}, "xyz", True, (0.0, 1.0, 0.0, 0.0)),
    ({"axisangle": "0 0 1 90"}, "xyz", True, (0.707107, 0.0, 0.0, 0.707107)),
    ({"quat": "2 0 0 2"}, "xyz", True, (0.707107, 0.0, 0.0, 0.707107)),
]


@pytest.mark.parametrize(("attributes", "eulerseq", "degrees", "expected"), MUJOCO_QUATERNIONS)
def test_mujoco_rotation_matches_mujoco(
    attributes: dict[str, str], eulerseq: str, degrees: bool, expected: tuple[float, ...]
) -> None:
    # the measured values have 6 digits
    assert same_rotation(mujoco_rotation(attributes, degrees, eulerseq), expected, 1e-6)


def test_maniskill_reads_euler_xyaxes_and_zaxis_otherwise_and_quat_alike() -> None:
    def differs(attributes: dict[str, str]) -> bool:
        theirs = maniskill_rotation(attributes, True)
        assert theirs is not None
        return not same_rotation(theirs, mujoco_rotation(attributes, True, "xyz"))

    assert differs({"euler": "0 30 0"}) and differs({"euler": "10 20 30"})
    assert not differs({"euler": "30 0 0"}) and not differs({"euler": "0 0 30"})
    assert differs({"xyaxes": "1 0 0 0 1 0"}) and differs({"zaxis": "1 0 0"})
    assert not differs({"quat": "1 1 0 0"}) and not differs({"axisangle": "1 0 0 30"})
    assert maniskill_rotation({"zaxis": "0 0 1"}, True) is None  # its LinAlgError


# -- facts for robospec new and inspect ----------------------------------------------------------


def test_keys_become_joint_values_in_maniskill_zero_and_a_root_body_pose() -> None:
    description, _ = parse(DATA / "control.xml")
    assert description is not None
    crouch, unnamed, short = description.keyframes
    assert crouch.name == "crouch" and crouch.line == 29
    # hip: qpos 0.8 minus its ref of 30 degrees; the ball's free joint after the robot is skipped
    assert dict(crouch.qpos) == pytest.approx({"hip": 0.8 - 0.5235987755982988, "knee": -1.2})
    assert crouch.root_pose == ((0.0, 0.0, 0.6), (1.0, 0.0, 0.0, 0.0))
    # a key without qpos is qpos0: the file's pose; its qvel is read
    assert unnamed.name == "key1" and dict(unnamed.qpos) == {"hip": 0.0, "knee": 0.0}
    assert unnamed.root_pose == ((0.0, 0.0, 0.8), (1.0, 0.0, 0.0, 0.0))
    assert dict(unnamed.qvel) == {"hip": 1.0, "knee": 2.0}
    # a short key leaves the rest at qpos0, as MuJoCo 4 does
    assert short.root_pose == ((0.0, 0.0, 0.6), (1.0, 0.0, 0.0, 0.0))
    assert dict(short.qpos) == {"hip": 0.0, "knee": 0.0}


def test_actuators_give_gains_and_ranges_with_their_defaults() -> None:
    description, _ = parse(DATA / "control.xml")
    assert description is not None
    hip, knee, servo, motor = description.actuators
    assert (hip.joint, hip.kp, hip.kv, hip.ctrl_range, hip.force_range) == (
        "hip",
        50.0,
        0.0,
        (-1.0, 1.0),
        (-20.0, 20.0),
    )
    assert (knee.kp, knee.kv, knee.ctrl_range) == (200.0, 5.0, None)  # class strong
    assert (servo.type, servo.kp, servo.kv) == ("general", 80.0, 3.0)  # affine bias: a servo
    assert (motor.type, motor.kp, motor.gear, motor.ctrl_range) == ("motor", None, 2.0, None)


def test_root_body_pose_is_the_file_pose_and_a_skipped_wrapper_offsets_nothing() -> None:
    description, _ = parse(DATA / "control.xml")
    assert description is not None
    assert description.root_body_pose == ((0.0, 0.0, 0.8), (1.0, 0.0, 0.0, 0.0))
    assert description.root_body_offset == description.root_body_pose
    wrapped, _ = parse(GAPS / "wrapper.xml")
    assert wrapped is not None
    assert wrapped.root_body_pose == ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0))
    assert wrapped.root_body_offset == ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0))


def test_the_tree_reaches_every_link_through_the_nameless_fixed_joints() -> None:
    description, _ = parse(GAPS / "wrapper.xml")
    assert description is not None
    rows = KinematicTree(description).rows()
    assert [(row.depth, row.link) for row in rows] == [
        (0, "dummy_root_0"),
        (1, "base"),
        (2, "link"),
    ]
    assert rows[1].joint is not None and (rows[1].joint.name, rows[1].joint.type) == ("", "fixed")
    assert description.joint_names == ("joint",)  # the nameless joint is no spec's to name


def test_inspect_shows_maniskills_reading_of_an_mjcf_with_the_mends_it_needs() -> None:
    from robospec.authoring.commands import run_inspect

    result = run_inspect(GAPS / "orientation.xml", loader="maniskill")
    text, diagnostics = result.report, result.diagnostics
    assert text is not None
    assert "    base  <- (fixed, unnamed)\n      tilted  <- tilted (continuous)\n" in text
    # the frames are shown as `new`'s orientations mend leaves them: its note says what it
    # wrote and how the euler angles were read (the degrees note's angles went with them)
    assert [d.code for d in diagnostics] == ["RS721"]
    assert "(degrees: no <compiler angle>)" in diagnostics[0].message


CONTROL_SPEC = """robospec: 1
uid: rs_control
description: {mjcf: control.xml}
loader: {fix_root_link: false}
keyframes:
  crouch: {pose: {p: [0, 0, 0.6]}, qpos: [0.2764, -1.2]}
controllers:
  legs: {type: pd_joint_pos, joints: [hip, knee], lower: null, upper: null, stiffness: 100,
         damping: 10, normalize_action: false}
control_modes:
  pd_joint_pos: {legs: legs}
"""


def test_a_keyframe_pose_is_the_root_bodys_and_the_card_shows_it_so(tmp_path: Path) -> None:
    from robospec.authoring.card import robot_card
    from robospec.pipeline import compile_spec

    (tmp_path / "control.xml").write_text((DATA / "control.xml").read_text())
    (tmp_path / "control.yaml").write_text(CONTROL_SPEC)
    compiled = compile_spec(tmp_path / "control.yaml")
    assert compiled.robot is not None and compiled.description is not None
    (crouch,) = compiled.robot.keyframes
    # the torso at 0.6 m hangs 0.8 m below ManiSkill's root link
    assert crouch.p == pytest.approx((0.0, 0.0, -0.2)) and crouch.q == (1.0, 0.0, 0.0, 0.0)
    card = robot_card(compiled.robot, compiled.description, "control.yaml")
    assert "| pose p | [0, 0, 0.6] |" in card
    assert 'l_dummy_root_0 -->|"fixed"| l_torso' in card  # the tree reaches the torso


def test_an_articulation_with_more_joints_behind_the_one_maniskill_takes_is_pointed_out(
    tmp_path: Path,
) -> None:
    (tmp_path / "order.xml").write_text(
        "<mujoco>\n<worldbody>\n"
        '<body name="target"><joint name="tx" type="slide" axis="0 0 1"/>'
        '<geom size=".02"/></body>\n'
        '<body name="base"><geom size=".1"/>\n'
        '<body name="l1"><joint name="j1"/><geom size=".05"/>\n'
        '<body name="l2"><joint name="j2"/><geom size=".05"/></body></body></body>\n'
        "</worldbody>\n</mujoco>\n"
    )
    description, (warning,) = parse(tmp_path / "order.xml")
    assert description is not None and description.active_joint_names == ("tx",)
    assert (warning.code, warning.location.line) == ("RS052", 4)
    assert "body 'target' (1 joint(s)), and this one has 2" in warning.message
    assert warning.hint == "if this is the robot, move it before the other bodies in <worldbody>"


# -- joints without an axis ------------------------------------------------------------------------

UNAXED = CODE_EXAMPLES / "RS095" / "unaxed.xml"


def test_only_the_joint_that_writes_no_axis_nor_takes_one_from_a_class_is_reported() -> None:
    # shoulder: no axis anywhere (MuJoCo: z); elbow: class 'bent' gives y; wrist: its own x
    diagnostic = only(UNAXED, "RS095")
    assert diagnostic.severity.value == "error"
    assert diagnostic.location.line == 11  # the shoulder
    assert "'shoulder'" in diagnostic.message and "about x" in diagnostic.message
    assert "elbow" not in diagnostic.message and "wrist" not in diagnostic.message
    assert diagnostic.hint is not None
    assert "{axes: mujoco}" in diagnostic.hint and "loader: mujoco" in diagnostic.hint


def test_joints_without_axes_are_one_error_at_the_first_listing_the_others(
    tmp_path: Path,
) -> None:
    path = chain(tmp_path / "snake.xml", 4, axis=None)  # j1..j3 write no axis
    diagnostic = only(path, "RS095")
    assert "'j1'" in diagnostic.message and "2 more joint(s) ('j2', 'j3')" in diagnostic.message


def test_an_axis_only_mujocos_class_reading_gives_is_reported_with_that_axis(
    tmp_path: Path,
) -> None:
    # MuJoCo's root class spelled class="main": a class of its own in ManiSkill's reading,
    # applied to no joint that does not name it, so the loader reads no axis there
    path = tmp_path / "main.xml"
    path.write_text(
        '<mujoco><compiler angle="radian"/><default class="main"><joint axis="0 1 0"/>'
        '</default><worldbody><body name="base"><geom size=".05"/><body name="arm">'
        '<joint name="j"/><geom size=".05"/></body></body></worldbody></mujoco>'
    )
    diagnostic = only(path, "RS095")
    assert "\"0 1 0\" (from class 'main')" in diagnostic.message


def test_a_joint_mujoco_turns_about_x_is_not_reported(tmp_path: Path) -> None:
    path = tmp_path / "x.xml"
    path.write_text(
        '<mujoco><compiler angle="radian"/><default class="main"><joint axis="1 0 0"/>'
        '</default><worldbody><body name="base"><geom size=".05"/><body name="arm">'
        '<joint name="j"/><geom size=".05"/></body></body></worldbody></mujoco>'
    )
    assert "RS095" not in {d.code for d in parse(path)[1]}


def test_the_axes_mend_writes_mujocos_axis_on_the_unaxed_joint_only() -> None:
    from lxml import etree

    from robospec.derive import Source, derive

    derived = derive(
        Source(str(UNAXED), UNAXED.name, "mjcf", UNAXED.read_bytes()), {"axes": "mujoco"}
    )
    root = etree.fromstring(derived.text.encode())
    axes = {joint.get("name"): joint.get("axis") for joint in root.find("worldbody").iter("joint")}
    assert axes == {"shoulder": "0 0 1", "elbow": None, "wrist": "1 0 0"}
