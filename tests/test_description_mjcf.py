"""MJCF facts as ManiSkill's MJCF loader makes them: dummy links, order, degrees, defaults."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from conftest import maniskill_assets
from mjcf_scene import parse, scene_fixture  # noqa: F401  (the scene fixture)

from robospec.description import load_description
from robospec.description.facts import RobotDescription
from robospec.description.mjcf import parse_mjcf
from robospec.diagnostics import Diagnostic

DATA = Path(__file__).parent / "data" / "mjcf"

# [j.name for j in agent.robot.active_joints] for ManiSkill's humanoid (measured with SAPIEN).
HUMANOID_ACTIVE_JOINTS = (
    "abdomen_z",
    "right_shoulder1",
    "left_shoulder1",
    "abdomen_y",
    "right_shoulder2",
    "left_shoulder2",
    "abdomen_x",
    "right_elbow",
    "left_elbow",
    "right_hip_x",
    "left_hip_x",
    "right_hip_z",
    "left_hip_z",
    "right_hip_y",
    "left_hip_y",
    "right_knee",
    "left_knee",
    "right_ankle_y",
    "left_ankle_y",
    "right_ankle_x",
    "left_ankle_x",
)


def humanoid_path() -> Path:
    """The humanoid.xml shipped inside mani_skill, found without importing mani_skill."""
    path = maniskill_assets() / "robots" / "humanoid" / "humanoid.xml"
    if not path.exists():
        pytest.fail(f"mani_skill ships no {path}")
    return path


def parse_file(path: Path) -> tuple[RobotDescription | None, list[Diagnostic]]:
    return parse_mjcf(path.read_bytes(), str(path))


def errors(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    return [d for d in diagnostics if d.is_error]


def mjcf(worldbody: str, head: str = "") -> str:
    """A one-file model; line 1 is <mujoco>, ``head`` starts on line 2."""
    return f"<mujoco>\n{head}<worldbody>\n{worldbody}</worldbody>\n</mujoco>\n"


# -- humanoid -------------------------------------------------------------------------------------


def test_humanoid_has_21_active_joints_in_maniskill_order() -> None:
    description, diagnostics = parse_file(humanoid_path())
    # its joint springs and armature are all ManiSkill's loader leaves out (RS084); its angles
    # are MJCF's default degrees, said as a note (RS086)
    assert [(d.code, d.is_error) for d in diagnostics] == [
        ("RS086", False),
        ("RS084", False),
        ("RS084", False),
    ]
    assert description is not None
    assert description.active_joint_names == HUMANOID_ACTIVE_JOINTS


def test_humanoid_root_is_a_free_dummy_root_because_of_its_freejoint() -> None:
    description, _ = parse_file(humanoid_path())
    assert description is not None
    assert description.floating_root
    assert description.root_link == "dummy_root_0"
    assert description.link_names[:3] == ("dummy_root_0", "torso", "head")


def test_humanoid_bodies_with_several_joints_become_dummy_links_named_after_the_body() -> None:
    description, _ = parse_file(humanoid_path())
    assert description is not None
    names = set(description.link_names)
    # lower_waist has 2 joints, right_thigh 3: the last joint moves the real body's link.
    assert {"lower_waist_dummy_0", "lower_waist"} <= names
    assert {"right_thigh_dummy_0", "right_thigh_dummy_1", "right_thigh"} <= names
    assert "lower_waist_dummy_1" not in names
    assert len(description.links) == 26
    abdomen_z = description.joint("abdomen_z")
    abdomen_y = description.joint("abdomen_y")
    assert abdomen_z is not None and abdomen_y is not None
    assert (abdomen_z.parent, abdomen_z.child) == ("torso", "lower_waist_dummy_0")
    assert (abdomen_y.parent, abdomen_y.child) == ("lower_waist_dummy_0", "lower_waist")


def test_humanoid_ranges_are_read_in_degrees_and_given_in_radians() -> None:
    description, _ = parse_file(humanoid_path())
    assert description is not None
    abdomen_y = description.joint("abdomen_y")  # range="-75 30"
    assert abdomen_y is not None and abdomen_y.type == "revolute"
    assert abdomen_y.lower == pytest.approx(math.radians(-75))
    assert abdomen_y.upper == pytest.approx(math.radians(30))
    assert all(j.lower is not None for j in description.active_joints)  # class 'body': limited


def test_humanoid_includes_are_read_relative_to_the_file() -> None:
    # humanoid.xml includes ./common/*.xml; a reader that fails shows they are needed.
    path = humanoid_path()

    def no_files(file: str) -> bytes:
        raise FileNotFoundError(2, "No such file or directory", file)

    _, diagnostics = parse_mjcf(path.read_bytes(), str(path), read_file=no_files)
    assert [d.code for d in diagnostics] == ["RS050"] * 3
    assert diagnostics[0].location.line == 2


# -- fixtures ------------------------------------------------------------------------------------


def test_tree_fixture_links_follow_maniskill_naming_and_breadth_first_order() -> None:
    description, diagnostics = parse_file(DATA / "tree.xml")
    assert diagnostics == []
    assert description is not None
    # 'table' (index 0) is a static actor, so the robot's root is dummy_root_1; 'wrapper' holds
    # only 'base' and is skipped; 'actuator' (childclass 'motorized') is dropped.
    assert description.link_names == (
        "dummy_root_1",
        "base",
        "upper",
        "forearm_dummy_0",
        "mount",
        "forearm_dummy_1",
        "sensor",
        "forearm",
        "hand",
    )
    assert description.active_joint_names == (
        "shoulder",
        "elbow_pitch",
        "elbow_slide",
        "tilt",
        "elbow_roll",
        "wrist",
    )
    assert not description.floating_root
    assert "ignored" not in description.joint_names


def test_tree_fixture_limits_follow_defaults_classes_and_compiler() -> None:
    description, _ = parse_file(DATA / "tree.xml")
    assert description is not None
    limits = {j.name: (j.type, j.lower, j.upper) for j in description.active_joints}
    assert limits["shoulder"] == ("revolute", -1.0, 1.0)  # top-level default, radians
    assert limits["elbow_pitch"] == ("revolute", -2.0, 2.0)  # childclass 'arm'
    assert limits["elbow_slide"] == ("prismatic", -0.1, 0.2)  # class from the included file
    assert limits["elbow_roll"] == ("continuous", None, None)  # limited="false"
    assert limits["tilt"] == ("revolute", -0.5, 0.25)


def test_free_root_fixture_defaults_to_degrees() -> None:
    description, _ = parse_file(DATA / "free_root.xml")
    assert description is not None
    assert description.floating_root
    hip = description.joint("hip")
    assert hip is not None
    assert (hip.lower, hip.upper) == pytest.approx((math.radians(-90), math.radians(45)))


def test_compiler_angle_radian_keeps_ranges_as_written() -> None:
    body = '<body name="a"><body name="b"><joint name="j" range="-1 2"/></body></body>\n'
    radians, _ = parse_mjcf(mjcf(body, '<compiler angle="radian"/>\n'), "r.xml")
    degrees, _ = parse_mjcf(mjcf(body, '<compiler angle="degree"/>\n'), "d.xml")
    assert radians is not None and degrees is not None
    assert (radians.joints[0].lower, radians.joints[0].upper) == (-1.0, 2.0)
    assert degrees.joints[0].upper == pytest.approx(math.radians(2))


def test_joint_lines_point_at_joint_elements() -> None:
    description, _ = parse_file(DATA / "tree.xml")
    assert description is not None
    lines = (DATA / "tree.xml").read_text().splitlines()
    for joint in description.joints:
        assert f'<joint name="{joint.name}"' in lines[joint.line - 1]


def test_unnamed_active_joint_is_a_warning() -> None:
    body = (
        '<body name="a"><body name="b"><joint axis="0 0 1" range="-1 1"/><geom size=".1"/>'
        "</body></body>\n"
    )
    description, diagnostics = parse_mjcf(mjcf(body), "u.xml")
    assert description is not None and description.active_joint_names == ("",)
    assert [(d.code, d.severity.value, d.location.line) for d in diagnostics] == [
        ("RS086", "note", 1),  # the hinge's range is in MJCF's default degrees
        ("RS052", "warning", 3),
    ]


# -- defects -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "code", "line", "words"),
    [
        pytest.param("<mujoco>\n<worldbody>\n</mujoco>\n", "RS051", 3, "mismatch", id="malformed"),
        pytest.param("<robot>\n</robot>\n", "RS052", 1, "not <mujoco>", id="wrong_root"),
        pytest.param("<mujoco>\n</mujoco>\n", "RS052", 1, "no <worldbody>", id="no_worldbody"),
        pytest.param(
            mjcf('<body name="a"><geom size=".1"/></body>\n'),
            "RS052",
            2,
            "no <body> under <worldbody> has a joint",
            id="no_articulation",
        ),
        pytest.param(
            mjcf('<body name="a">\n<body name="b"><joint name="j" type="ball"/></body></body>\n'),
            "RS052",
            4,
            "type 'ball'",
            id="ball_joint",
        ),
        pytest.param(
            mjcf('<body name="a">\n<joint name="f" type="free"/><body name="b"/></body>\n'),
            "RS052",
            4,
            "type 'free'",
            id="free_joint_element",
        ),
        pytest.param(
            mjcf('<body name="a">\n<body><joint name="j"/></body></body>\n'),
            "RS052",
            4,
            "body without a name",
            id="body_without_name",
        ),
        pytest.param(
            mjcf(
                '<body name="a">\n<body name="b" childclass="arn"><joint name="j"/></body>'
                "</body>\n",
                '<default><default class="arm"><joint range="0 1"/></default></default>\n',
            ),
            "RS052",
            5,
            "unknown default class 'arn'",
            id="unknown_class",
        ),
        pytest.param(
            mjcf(
                '<body name="a">\n<body name="b"><joint name="j" class="look"/></body></body>\n',
                '<default><default class="look"><geom rgba="1 0 0 1"/></default></default>\n',
            ),
            "RS052",
            5,
            "sets no joint attributes",
            id="class_without_joint_defaults",
        ),
        pytest.param(
            mjcf(
                '<body name="a"><joint name="j1"/>\n<body name="a"><joint name="j2"/></body>'
                "</body>\n"
            ),
            "RS052",
            4,
            "duplicate link name 'a'",
            id="duplicate_body",
        ),
        pytest.param(
            mjcf(
                '<body name="a"><joint name="j1"/><joint name="j2"/>\n'
                '<body name="a_dummy_0"><joint name="j3"/></body></body>\n'
            ),
            "RS052",
            4,
            "duplicate link name 'a_dummy_0'",
            id="body_named_like_a_dummy_link",
        ),
        pytest.param(
            mjcf('<body name="a">\n<body name="b"><joint name="j" range="-1 x"/></body></body>\n'),
            "RS052",
            4,
            'range="-1 x" is not 2 numbers',
            id="bad_range",
        ),
        pytest.param(
            mjcf('<body name="a">\n<body name="b"><joint name="j" range="1 -1"/></body></body>\n'),
            "RS052",
            4,
            "lower bound above its upper bound",
            id="inverted_range",
        ),
        pytest.param(
            '<mujoco>\n<include file="missing.xml"/>\n</mujoco>\n',
            "RS050",
            2,
            "cannot read included file 'missing.xml'",
            id="missing_include",
        ),
    ],
)
def test_each_defect_is_an_error_with_its_code_at_the_offending_line(
    text: str, code: str, line: int, words: str, tmp_path: Path
) -> None:
    path = str(tmp_path / "model.xml")
    _, diagnostics = parse_mjcf(text, path)
    found = errors(diagnostics)
    assert found, diagnostics
    assert (found[0].code, found[0].location.line) == (code, line), found[0].format_text()
    assert found[0].location.file == path
    assert words in found[0].message


def test_second_articulation_is_a_warning_and_the_first_is_the_robot() -> None:
    bodies = (
        '<body name="a"><body name="b"><joint name="j" axis="0 0 1"/><geom size=".1"/>'
        "</body></body>\n"
        '<body name="c"><body name="d"><joint name="k" axis="0 0 1"/><geom size=".1"/>'
        "</body></body>\n"
    )
    description, diagnostics = parse_mjcf(mjcf(bodies), "two.xml")
    assert description is not None and description.active_joint_names == ("j",)
    assert [(d.severity.value, d.location.line) for d in diagnostics] == [("warning", 4)]


def test_errors_in_included_files_are_located_in_those_files(tmp_path: Path) -> None:
    (tmp_path / "part.xml").write_text(
        '<mujoco>\n<worldbody>\n<body name="a">\n<body name="b">'
        '<joint name="j" type="ball"/></body></body>\n</worldbody>\n</mujoco>\n'
    )
    main = tmp_path / "main.xml"
    main.write_text('<mujoco>\n<include file="part.xml"/>\n</mujoco>\n')
    description, diagnostics = load_description(str(main), "mjcf")
    assert description is None
    [problem] = diagnostics
    assert (problem.location.file, problem.location.line) == (str(tmp_path / "part.xml"), 4)


def test_every_truncation_of_a_valid_mjcf_yields_diagnostics_not_exceptions() -> None:
    text = (DATA / "free_root.xml").read_bytes()
    for end in range(0, len(text), 5):
        description, diagnostics = parse_mjcf(text[:end], str(DATA / "cut.xml"))
        assert description is None
        assert errors(diagnostics)


# -- against ManiSkill's MJCF loader ---------------------------------------------------------------


def _maniskill_facts(scene: Any, path: Path) -> dict[str, Any]:
    """What ManiSkill's MJCF loader makes of ``path``: links, active joints and their limits,
    whether the root is fixed."""
    import sapien

    builder = parse(scene, path)
    builder.initial_pose = sapien.Pose()
    robot = builder.build()
    return {
        "links": [link.name for link in robot.links],
        "active": [j.name for j in robot.active_joints],
        "limits": [[float(x) for x in j.limits[0]] for j in robot.active_joints],
        "fixed_root": bool(robot.fixed_root_link.all()),
        "shaped": {link.name for link in robot.links if link._objs[0].collision_shapes},
    }


@pytest.mark.usefixtures("maniskill")
def test_fixtures_and_humanoid_match_maniskill_mjcf_loader(scene: Any) -> None:
    for path in (DATA / "tree.xml", DATA / "free_root.xml", humanoid_path()):
        facts = _maniskill_facts(scene, path)
        description, _ = parse_file(path)
        assert description is not None
        assert list(description.link_names) == facts["links"], path.name
        assert list(description.active_joint_names) == facts["active"], path.name
        assert description.floating_root == (not facts["fixed_root"]), path.name
        # the links with collision shapes: a body's own, never the dummies before it
        shaped = {link.name for link in description.links if link.shaped}
        assert shaped == facts["shaped"], path.name
        for joint, (lower, upper) in zip(description.active_joints, facts["limits"], strict=True):
            assert (joint.lower if joint.lower is not None else -math.inf) == pytest.approx(
                lower, rel=1e-6
            ), joint.name
            assert (joint.upper if joint.upper is not None else math.inf) == pytest.approx(
                upper, rel=1e-6
            ), joint.name
