"""robospec.optimize.condense: fixed links merged into their parents, the robot unchanged.

A hand-written robot (two boxes on a fixed joint with an offset and a rotation) against mass,
centre of mass and inertia worked out by hand; then ManiSkill's own URDFs, original and
condensed, loaded in SAPIEN and compared: the same active joints in the same order, every
shared link at the same pose at random configurations, the same total mass, centre of mass and
inertia. The same comparison runs again in float64 outside SAPIEN (SAPIEN keeps poses in
float32), so the tolerances there can be tight.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import maniskill_assets
from lxml import etree

from robospec.optimize.condense import SAPIEN_EMPTY_LINK as STAND_IN
from robospec.optimize.condense import Condensed, MergedLink, condense

# -- a hand-written robot for exact arithmetic
#
# Link a: a box 0.2 × 0.1 × 0.1, 2 kg, centre at a's origin.
# Link b: a box 0.1 × 0.2 × 0.3, 1 kg, centre at (0, 0, 0.1) in b; its inertia is written in
#   axes turned a quarter turn about z (so the file lists the x and y moments swapped).
# Fixed joint a_to_b: b at (0.3, 0, 0.1) in a, turned a quarter turn about z.
# b carries a visual (offset and rolled), a collision without an origin, and a revolute joint
# to c; a fixed joint to a massless frame e comes first in the document (merged first, into b,
# then with b into a).

Q = math.pi / 2
BOX_A = {
    "ixx": 2 * (0.01 + 0.01) / 12,
    "iyy": 2 * (0.04 + 0.01) / 12,
    "izz": 2 * (0.04 + 0.01) / 12,
}
# b's moments in its own axes are (0.13, 0.1, 0.05)/12; the file's axes are turned by Q about z
BOX_B_TURNED = {"ixx": 0.1 / 12, "iyy": 0.13 / 12, "izz": 0.05 / 12}


def _inertia(moments: Mapping[str, float]) -> str:
    return " ".join(f'{key}="{value!r}"' for key, value in moments.items())


TWO_BOXES = f"""<robot name="two_boxes">
  <material name="blue">
    <color rgba="0 0 1 1"/>
  </material>
  <link name="a">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="2"/>
      <inertia {_inertia(BOX_A)} ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <collision>
      <geometry>
        <box size="0.2 0.1 0.1"/>
      </geometry>
    </collision>
  </link>
  <link name="b">
    <inertial>
      <origin xyz="0 0 0.1" rpy="0 0 {Q!r}"/>
      <mass value="1"/>
      <inertia {_inertia(BOX_B_TURNED)} ixy="0" ixz="0" iyz="0"/>
    </inertial>
    <visual name="b_look">
      <origin xyz="0 0 0.1" rpy="0.1 0 0"/>
      <geometry>
        <mesh filename="meshes/b.obj" scale="1 1 1"/>
      </geometry>
      <material name="blue"/>
    </visual>
    <collision name="b_shape">
      <geometry>
        <box size="0.1 0.2 0.3"/>
      </geometry>
    </collision>
  </link>
  <link name="c"/>
  <link name="d"/>
  <link name="e"/>
  <joint name="b_to_e" type="fixed">
    <parent link="b"/>
    <child link="e"/>
    <origin xyz="0 0 0.5"/>
  </joint>
  <joint name="a_to_b" type="fixed">
    <origin xyz="0.3 0 0.1" rpy="0 0 {Q!r}"/>
    <parent link="a"/>
    <child link="b"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="a"/>
    <child link="d"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="wrist" type="revolute">
    <origin xyz="0 0.1 0"/>
    <parent link="b"/>
    <child link="c"/>
    <axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <transmission name="wrist_trans">
    <joint name="wrist"/>
  </transmission>
  <transmission name="fixed_trans">
    <joint name="a_to_b"/>
  </transmission>
  <gazebo reference="b">
    <material>Gazebo/Blue</material>
  </gazebo>
  <gazebo reference="a">
    <material>Gazebo/Red</material>
  </gazebo>
  <gazebo>
    <static>false</static>
  </gazebo>
</robot>
"""


def _parse(text: str) -> etree._Element:
    return etree.fromstring(text.encode())


def _floats(element: etree._Element, attribute: str) -> list[float]:
    return [float(part) for part in element.get(attribute, "").split()]


def _only(root: etree._Element, path: str) -> etree._Element:
    found = root.findall(path)
    assert len(found) == 1, f"{path}: {len(found)} found"
    return found[0]


def test_two_boxes_merge_into_one_body_worked_out_by_hand() -> None:
    # e kept: empty, it would add SAPIEN's 1e-6 kg stand-in (the next tests but one)
    condensed = condense(_parse(TWO_BOXES), keep={"e"})
    robot = condensed.robot
    assert [link.get("name") for link in robot.iterfind("link")] == ["a", "c", "d", "e"]
    inertial = _only(robot, "link[@name='a']/inertial")
    assert float(_only(inertial, "mass").get("value")) == 3.0
    origin = _only(inertial, "origin")
    # centre of mass: (2 kg at (0, 0, 0) + 1 kg at (0.3, 0, 0.2)) / 3 kg
    assert _floats(origin, "xyz") == pytest.approx([0.1, 0.0, 0.2 / 3], abs=1e-15)
    assert _floats(origin, "rpy") == [0.0, 0.0, 0.0]
    # about that centre: each box's own inertia (b's axes turned twice by Q: the file's
    # (0.1, 0.13, 0.05)/12 turn into b's (0.13, 0.1, 0.05)/12, then into a's (0.1, 0.13,
    # 0.05)/12) plus m (|d|² E - d dᵀ), d = (-0.1, 0, -0.2/3) for a, (0.2, 0, 0.4/3) for b
    expected = {
        "ixx": (0.04 + 0.1) / 12 + 2 * (0.2 / 3) ** 2 + 1 * (0.4 / 3) ** 2,
        "iyy": (0.1 + 0.13) / 12 + 2 * (0.01 + (0.2 / 3) ** 2) + 1 * (0.04 + (0.4 / 3) ** 2),
        "izz": (0.1 + 0.05) / 12 + 2 * 0.01 + 1 * 0.04,
        "ixy": 0.0,
        "ixz": -2 * (-0.1) * (-0.2 / 3) - 1 * 0.2 * (0.4 / 3),
        "iyz": 0.0,
    }
    tensor = _only(inertial, "inertia")
    for key, value in expected.items():
        assert float(tensor.get(key)) == pytest.approx(value, rel=1e-12, abs=1e-15), key


def test_visuals_and_collisions_move_with_composed_origins() -> None:
    robot = condense(_parse(TWO_BOXES), keep=()).robot
    link = _only(robot, "link[@name='a']")
    assert [(e.tag, e.get("name")) for e in link if e.tag in ("visual", "collision")] == [
        ("collision", None),
        ("visual", "b_look"),
        ("collision", "b_shape"),
    ]
    visual = _only(link, "visual/origin")
    # (0, 0, 0.1) rolled by 0.1, seen from a: b's origin + Rz(Q) (0, 0, 0.1); roll then yaw
    assert _floats(visual, "xyz") == pytest.approx([0.3, 0.0, 0.2], abs=1e-15)
    assert _floats(visual, "rpy") == pytest.approx([0.1, 0.0, Q], abs=1e-15)
    # no origin of its own: the joint's, exactly
    shape = _only(link, "collision[@name='b_shape']/origin")
    assert _floats(shape, "xyz") == [0.3, 0.0, 0.1]
    assert _floats(shape, "rpy") == [0.0, 0.0, Q]
    # the mesh, its material and everything else about the element as written
    assert _only(link, "visual/geometry/mesh").attrib == {
        "filename": "meshes/b.obj",
        "scale": "1 1 1",
    }
    assert _only(link, "visual/material").get("name") == "blue"


def test_a_merged_links_child_joints_hang_from_the_survivor_where_the_fixed_joint_stood() -> None:
    robot = condense(_parse(TWO_BOXES), keep=()).robot
    # wrist was last in the file; it takes a_to_b's place, before elbow, as SAPIEN's walk
    # would have reached it
    assert [joint.get("name") for joint in robot.iterfind("joint")] == ["wrist", "elbow"]
    wrist = _only(robot, "joint[@name='wrist']")
    assert _only(wrist, "parent").get("link") == "a"
    origin = _only(wrist, "origin")
    # (0.3, 0, 0.1) + Rz(Q) (0, 0.1, 0) = (0.2, 0, 0.1), turned by Q
    assert _floats(origin, "xyz") == pytest.approx([0.2, 0.0, 0.1], abs=1e-15)
    assert _floats(origin, "rpy") == [0.0, 0.0, Q]
    # the axis is in the joint's own frame: as written
    assert _only(wrist, "axis").get("xyz") == "1 0 0"
    assert _only(robot, "joint[@name='elbow']").find("origin") is None


def test_what_names_a_removed_link_or_joint_goes_and_the_rest_stays() -> None:
    robot = condense(_parse(TWO_BOXES), keep=()).robot
    assert [(e.tag, dict(e.attrib)) for e in robot if e.tag not in ("link", "joint")] == [
        ("material", {"name": "blue"}),
        ("transmission", {"name": "wrist_trans"}),
        ("gazebo", {"reference": "a"}),
        ("gazebo", {}),
    ]


def test_merges_are_reported_in_order_with_the_final_survivor() -> None:
    merged = condense(_parse(TWO_BOXES), keep=()).merged
    # b_to_e comes first in the file: e goes into b, then b (with e) into a
    assert merged == (
        MergedLink(link="e", into="a", joint="b_to_e"),
        MergedLink(link="b", into="a", joint="a_to_b"),
    )


def test_a_kept_link_is_never_merged() -> None:
    original = _parse(TWO_BOXES)
    kept = condense(original, keep={"b"})
    # e still goes into b; b and its fixed joint stay
    assert kept.merged == (MergedLink(link="e", into="b", joint="b_to_e"),)
    assert _only(kept.robot, "joint[@name='a_to_b']/child").get("link") == "b"
    assert _only(kept.robot, "link[@name='a']/inertial/mass").get("value") == "2"
    # keeping everything changes nothing, byte for byte
    untouched = condense(original, keep={"b", "e"})
    assert untouched.merged == ()
    assert etree.tostring(untouched.robot) == etree.tostring(original)


def test_the_input_is_not_mutated_and_the_output_is_deterministic() -> None:
    original = _parse(TWO_BOXES)
    before = etree.tostring(original)
    first, second = condense(original, keep=()), condense(_parse(TWO_BOXES), keep=())
    assert etree.tostring(original) == before
    assert etree.tostring(first.robot) == etree.tostring(second.robot)
    assert first == Condensed(robot=first.robot, merged=second.merged)


MASSLESS = """<robot name="frames">
  <link name="base"/>
  <link name="frame">
    <inertial>
      <mass value="0"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>
    </inertial>
  </link>
  <link name="marker"/>
  <link name="arm">
    <inertial>
      <origin xyz="0 0 0.5" rpy="0.3 0 0"/>
      <mass value="1.5"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/>
    </inertial>
  </link>
  <joint name="base_to_frame" type="fixed">
    <parent link="base"/>
    <child link="frame"/>
  </joint>
  <joint name="base_to_marker" type="fixed">
    <parent link="base"/>
    <child link="marker"/>
  </joint>
  <joint name="base_to_arm" type="fixed">
    <origin xyz="1 0 0"/>
    <parent link="base"/>
    <child link="arm"/>
  </joint>
</robot>
"""


def test_links_without_a_usable_inertial_merge_as_the_body_sapien_gives_them() -> None:
    robot = _parse(MASSLESS)
    # an empty link and one whose inertial has no mass: SAPIEN simulates each as its stand-in
    # body (1e-6 kg, 1e-6 kg·m² about each axis), so three of them merge into three times that
    stand_ins = _only(condense(robot, keep={"arm"}).robot, "link[@name='base']/inertial")
    assert float(_only(stand_ins, "mass").get("value")) == pytest.approx(3e-6, rel=1e-12)
    assert _floats(_only(stand_ins, "origin"), "xyz") == [0.0, 0.0, 0.0]
    stand_in_tensor = _only(stand_ins, "inertia")
    assert float(stand_in_tensor.get("ixx")) == pytest.approx(3e-6, rel=1e-12)
    assert float(stand_in_tensor.get("ixy")) == 0.0
    # a real body into them: the body, moved, plus the stand-ins at the survivor's origin
    inertial = _only(condense(robot, keep=()).robot, "link[@name='base']/inertial")
    mass = 1.5 + 3e-6
    assert float(_only(inertial, "mass").get("value")) == pytest.approx(mass, rel=1e-15)
    centre = _floats(_only(inertial, "origin"), "xyz")
    assert centre == pytest.approx([1.5 / mass, 0.0, 0.75 / mass], rel=1e-14)
    tensor = _only(inertial, "inertia")
    c, s = math.cos(0.3), math.sin(0.3)  # the rolled axes: yy and zz mix
    # the parallel-axis terms of two bodies, 1.5 kg and 3e-6 kg, r = (1, 0, 0.5) apart: the
    # reduced mass times |r|² E - r rᵀ
    reduced = 1.5 * 3e-6 / mass
    expected = {
        "ixx": 0.1 + 3e-6 + reduced * 0.25,
        "iyy": 0.2 * c * c + 0.3 * s * s + 3e-6 + reduced * 1.25,
        "izz": 0.2 * s * s + 0.3 * c * c + 3e-6 + reduced * 1.0,
        "ixz": -reduced * 0.5,
        "iyz": (0.2 - 0.3) * c * s,
        "ixy": 0.0,
    }
    for key, value in expected.items():
        assert float(tensor.get(key)) == pytest.approx(value, rel=1e-12, abs=1e-18), key


def test_a_link_whose_mass_sapien_takes_from_its_shapes_is_never_merged() -> None:
    # no inertial but a collision box: SAPIEN computes its mass from the box, a number a merge
    # would overwrite with the inertial it writes; so neither it nor its children merge
    box = "<collision><geometry><box size='1 1 1'/></geometry></collision>"
    text = MASSLESS.replace('<link name="base"/>', f'<link name="base">{box}</link>').replace(
        '<link name="marker"/>', f'<link name="marker">{box}</link>'
    )
    condensed = condense(_parse(text), keep=())
    assert condensed.merged == ()
    assert condensed.robot.find("link[@name='base']/inertial") is None


def test_a_fixed_joint_a_mimic_names_stays() -> None:
    text = TWO_BOXES.replace(
        '<axis xyz="1 0 0"/>', '<axis xyz="1 0 0"/>\n    <mimic joint="a_to_b"/>'
    )
    condensed = condense(_parse(text), keep=())
    assert [step.joint for step in condensed.merged] == ["b_to_e"]


@pytest.mark.parametrize(
    ("joint_rpy", "visual_rpy"),
    [
        ((0.3, -1.2, 2.5), (-0.7, 0.4, 1.1)),
        ((0.0, Q, 0.0), (0.3, 0.0, 0.0)),  # gimbal lock: pitch π/2
        ((0.2, Q - 0.4, 0.1), (0.0, 0.4, 0.0)),  # pitch at π/2 by a sum
        ((0.0, -Q + 1e-9, 0.5), (0.25, 0.0, 0.0)),  # a hair from it
        ((math.pi, 0.0, 0.0), (0.0, 0.0, math.pi)),  # turned half about two axes
    ],
)
def test_rotations_compose_as_matrices_do(
    joint_rpy: tuple[float, float, float], visual_rpy: tuple[float, float, float]
) -> None:
    def rpy(values: tuple[float, float, float]) -> str:
        return " ".join(repr(value) for value in values)

    text = f"""<robot name="turned">
      <link name="a"/>
      <link name="b"><visual><origin xyz="0.1 0.2 0.3" rpy="{rpy(visual_rpy)}"/>
        <geometry><sphere radius="0.1"/></geometry></visual></link>
      <joint name="a_to_b" type="fixed"><origin xyz="1 2 3" rpy="{rpy(joint_rpy)}"/>
        <parent link="a"/><child link="b"/></joint>
    </robot>"""
    visual = _only(condense(_parse(text), keep=()).robot, "link[@name='a']/visual")
    joint = _origin(_only(_parse(text), "joint"))
    expected = joint @ _origin(_only(_parse(text), "link[@name='b']/visual"))
    np.testing.assert_allclose(_origin(visual), expected, atol=1e-14)


# -- ManiSkill's robots, in SAPIEN and in float64


# (file, links to keep, links in the file before, after): the keep sets are the links ManiSkill's
# agent classes name (tcp, camera mounts, finger tips, collision-bit links) or none at all
CASES = [
    ("panda/panda_v2.urdf", {"panda_hand_tcp"}, 15, 11),
    (
        "panda/panda_v2.urdf",
        {"panda_hand_tcp", "panda_leftfinger_pad", "panda_rightfinger_pad"},
        15,
        13,
    ),
    ("fetch/fetch.urdf", set(), 29, 16),
    (
        "fetch/fetch.urdf",
        {"gripper_link", "head_camera_link", "l_wheel_link", "r_wheel_link", "base_link"},
        29,
        20,
    ),
    ("g1_humanoid/g1.urdf", set(), 44, 38),
    (
        "g1_humanoid/g1_simplified_upper_body.urdf",
        {"head_link", "left_tcp_link", "right_tcp_link"},
        46,
        29,
    ),
    (
        "allegro/allegro_hand_right_glb.urdf",
        {"palm", "link_3.0_tip", "link_7.0_tip", "link_11.0_tip", "link_15.0_tip"},
        23,
        22,
    ),
    ("allegro/allegro_hand_right_glb.urdf", set(), 23, 17),
    # empty fingertip links: SAPIEN's stand-in body outweighs the fingertip's own inertia
    ("inspire_hand/RH56DFX-2LR/urdf/inspire_hand_left.urdf", set(), 20, 15),
]


def _case_id(case: tuple[str, set[str], int, int]) -> str:
    path, keep, before, after = case
    return f"{Path(path).stem}-keep{len(keep)}-{before}to{after}links"


@pytest.fixture(scope="module", params=CASES, ids=[_case_id(case) for case in CASES])
def pair(request: pytest.FixtureRequest) -> tuple[Path, etree._Element, Condensed]:
    path, keep, before, after = request.param
    source = maniskill_assets() / "robots" / path
    original = etree.parse(str(source)).getroot()
    condensed = condense(original, keep)
    assert (len(original.findall("link")), len(condensed.robot.findall("link"))) == (
        before,
        after,
    )
    names = {link.get("name") for link in condensed.robot.iterfind("link")}
    assert set(keep) <= names
    assert not names & {step.link for step in condensed.merged}
    return source, original, condensed


def test_real_robots_keep_their_kinematics_in_float64(
    pair: tuple[Path, etree._Element, Condensed],
) -> None:
    _, original, condensed = pair
    before, after = _Kinematics(original), _Kinematics(condensed.robot)
    # the joints SAPIEN makes active, in the order its depth-first walk reaches them
    assert after.walk() == before.walk()
    shared = sorted(set(after.parents) & set(before.parents))
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = before.random_configuration(rng)
        poses_before, poses_after = before.poses(q), after.poses(q)
        for link in shared:
            np.testing.assert_allclose(poses_after[link], poses_before[link], atol=1e-9)
    mass_before, mass_after = before.mass_properties(), after.mass_properties()
    assert mass_after[0] == pytest.approx(mass_before[0], rel=1e-12)
    np.testing.assert_allclose(mass_after[1], mass_before[1], atol=1e-12)
    scale = np.abs(mass_before[2]).max()
    np.testing.assert_allclose(mass_after[2], mass_before[2], atol=1e-12 * scale)


def test_real_robots_load_the_same_in_sapien(
    maniskill: Any, pair: tuple[Path, etree._Element, Condensed], tmp_path: Path
) -> None:
    import sapien

    source, original, condensed = pair
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    before = _load(scene, _headless(original, source.parent), tmp_path / "original.urdf")
    after = _load(scene, _headless(condensed.robot, source.parent), tmp_path / "condensed.urdf")
    names = [joint.name for joint in before.get_active_joints()]
    assert [joint.name for joint in after.get_active_joints()] == names
    assert len(after.get_links()) < len(before.get_links())
    _same_poses(before, after)
    _same_mass_properties(before, after)
    _same_collision_shapes(before, after, {step.link: step.into for step in condensed.merged})


def _same_poses(before: Any, after: Any) -> None:
    """Every shared link at the same pose at 20 configurations within the joint limits.

    SAPIEN keeps poses in float32: two different chains of float32 products that reach a link
    a metre out differ by up to ~2e-6 (fetch), so 1e-5 here; the float64 test holds to 1e-9."""
    limits = before.get_qlimits()
    low = np.where(np.isfinite(limits[:, 0]), limits[:, 0], -np.pi)
    high = np.where(np.isfinite(limits[:, 1]), limits[:, 1], np.pi)
    links_before = {link.name: link for link in before.get_links()}
    shared = [(links_before[link.name], link) for link in after.get_links()]
    rng = np.random.default_rng(0)
    moved = 0.0
    for _ in range(20):
        q = rng.uniform(low, high)
        before.set_qpos(q)
        after.set_qpos(q)
        for one, other in shared:
            pose = one.entity_pose.to_transformation_matrix()
            np.testing.assert_allclose(
                other.entity_pose.to_transformation_matrix(), pose, atol=1e-5
            )
            moved = max(moved, float(np.abs(pose[:3, 3]).max()))
    assert moved > 0.05  # set_qpos moved the links: the comparison is not of two rest poses


def _same_collision_shapes(before: Any, after: Any, into: Mapping[str, str]) -> None:
    """Each surviving link carries its own collision shapes and those of the links merged into
    it, each where it was (in the root's frame, at a random configuration)."""
    q = np.random.default_rng(1).uniform(*np.clip(before.get_qlimits().T, -np.pi, np.pi))
    before.set_qpos(q)
    after.set_qpos(q)
    expected: dict[str, list[np.ndarray]] = {}
    for link in before.get_links():
        expected.setdefault(into.get(link.name, link.name), []).extend(_shape_poses(link))
    for link in after.get_links():
        left = expected.pop(link.name)
        for pose in _shape_poses(link):
            match = next(i for i, other in enumerate(left) if np.allclose(other, pose, atol=1e-5))
            del left[match]
        assert left == [], link.name
    assert expected == {}


def _shape_poses(link: Any) -> list[np.ndarray]:
    return [
        (link.entity_pose * shape.local_pose).to_transformation_matrix()
        for shape in link.get_collision_shapes()
    ]


def _same_mass_properties(before: Any, after: Any) -> None:
    """Total mass, centre of mass and inertia about it, in the root's frame at qpos 0, of every
    body SAPIEN simulates — the stand-in it gives a link with neither a usable inertial nor a
    collision shape included: its 1e-6 kg·m² is ten times an Inspire fingertip's inertia."""
    zero = np.zeros(len(before.get_active_joints()))
    before.set_qpos(zero)
    after.set_qpos(zero)
    mass, centre, inertia = _sapien_mass_properties(before)
    mass_after, centre_after, inertia_after = _sapien_mass_properties(after)
    assert mass_after == pytest.approx(mass, rel=1e-6)
    np.testing.assert_allclose(centre_after, centre, atol=1e-6 * max(1.0, np.abs(centre).max()))
    np.testing.assert_allclose(inertia_after, inertia, atol=1e-6 * np.abs(inertia).max())


def _sapien_mass_properties(articulation: Any) -> tuple[float, np.ndarray, np.ndarray]:
    bodies = []
    for link in articulation.get_links():
        frame = (link.entity_pose * link.cmass_local_pose).to_transformation_matrix()
        rotation = frame[:3, :3].astype(float)
        tensor = rotation @ np.diag(link.inertia.astype(float)) @ rotation.T
        bodies.append((float(link.mass), frame[:3, 3].astype(float), tensor))
    return _combine(bodies)


def _combine(bodies: list[tuple[float, np.ndarray, np.ndarray]]) -> tuple[float, Any, Any]:
    """(mass, centre, inertia about the centre) of bodies given as (mass, centre, inertia)."""
    mass = sum(body[0] for body in bodies)
    centre = sum(m * c for m, c, _ in bodies) / mass
    inertia = sum(
        tensor + m * (np.dot(c - centre, c - centre) * np.eye(3) - np.outer(c - centre, c - centre))
        for m, c, tensor in bodies
    )
    return mass, centre, inertia


def _headless(robot: etree._Element, folder: Path) -> bytes:
    """A copy SAPIEN can load here: no visuals (no rendering device), mesh paths absolute."""
    copy = etree.fromstring(etree.tostring(robot))
    for visual in list(copy.iter("visual")):
        visual.getparent().remove(visual)
    for mesh in copy.iter("mesh"):
        mesh.set("filename", str((folder / mesh.get("filename", "")).resolve()))
    return etree.tostring(copy)


def _load(scene: Any, text: bytes, path: Path) -> Any:
    path.write_bytes(text)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    return loader.load(str(path))


class _Kinematics:
    """A URDF's kinematic tree in float64 (numpy, and trimesh's rotations: not the module's
    own arithmetic)."""

    def __init__(self, robot: etree._Element) -> None:
        self.joints = {joint.get("name"): joint for joint in robot.iterfind("joint")}
        self.parents = {joint.find("child").get("link"): joint for joint in robot.iterfind("joint")}
        links = [link.get("name") for link in robot.iterfind("link")]
        self.root = next(link for link in links if link not in self.parents)
        self.parents[self.root] = None
        self.links = {link.get("name"): link for link in robot.iterfind("link")}
        self.moving = [name for name, joint in self.joints.items() if joint.get("type") != "fixed"]

    def walk(self) -> list[str]:
        """The moving joints in the order SAPIEN's URDF loader reaches them: depth first from
        the root, each link's child joints in document order."""
        order, stack = [], [self.root]
        while stack:
            link = stack.pop()
            joint = self.parents[link]
            if joint is not None and joint.get("type") != "fixed":
                order.append(joint.get("name"))
            children = [j for j in self.joints.values() if j.find("parent").get("link") == link]
            stack.extend(j.find("child").get("link") for j in reversed(children))
        return order

    def random_configuration(self, rng: np.random.Generator) -> dict[str, float]:
        q = {}
        for name in self.moving:
            limit = self.joints[name].find("limit")
            continuous = limit is None or self.joints[name].get("type") == "continuous"
            low = -np.pi if continuous else float(limit.get("lower", "0"))
            high = np.pi if continuous else float(limit.get("upper", "0"))
            q[name] = float(rng.uniform(low, high))
        return q

    def poses(self, q: Mapping[str, float]) -> dict[str, np.ndarray]:
        poses: dict[str, np.ndarray] = {}
        for link in self.parents:
            self._pose(link, q, poses)
        return poses

    def _pose(self, link: str, q: Mapping[str, float], poses: dict[str, np.ndarray]) -> Any:
        if link not in poses:
            joint = self.parents[link]
            if joint is None:
                poses[link] = np.eye(4)
            else:
                parent = self._pose(joint.find("parent").get("link"), q, poses)
                poses[link] = parent @ _origin(joint) @ _motion(joint, q.get(joint.get("name"), 0))
        return poses[link]

    def mass_properties(self) -> tuple[float, Any, Any]:
        poses = self.poses({})
        bodies = []
        for name, link in self.links.items():
            inertial = link.find("inertial")
            if inertial is None or float(inertial.find("mass").get("value")) == 0:
                if link.find("collision") is None:  # SAPIEN's stand-in, isotropic: axes moot
                    bodies.append((STAND_IN.mass, poses[name][:3, 3], np.array(STAND_IN.inertia)))
                continue
            frame = poses[name] @ _origin(inertial)
            tensor = inertial.find("inertia")
            i = {
                key: float(tensor.get(key, "0"))
                for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
            }
            local = np.array(
                [
                    [i["ixx"], i["ixy"], i["ixz"]],
                    [i["ixy"], i["iyy"], i["iyz"]],
                    [i["ixz"], i["iyz"], i["izz"]],
                ]
            )
            rotation = frame[:3, :3]
            bodies.append(
                (
                    float(inertial.find("mass").get("value")),
                    frame[:3, 3],
                    rotation @ local @ rotation.T,
                )
            )
        return _combine(bodies)


def _origin(element: etree._Element) -> np.ndarray:
    from trimesh import transformations

    origin = element.find("origin")
    xyz = _floats(origin, "xyz") if origin is not None and origin.get("xyz") else [0.0] * 3
    rpy = _floats(origin, "rpy") if origin is not None and origin.get("rpy") else [0.0] * 3
    matrix = transformations.euler_matrix(*rpy, axes="sxyz")
    matrix[:3, 3] = xyz
    return matrix


def _motion(joint: etree._Element, value: float) -> np.ndarray:
    from trimesh import transformations

    axis_element = joint.find("axis")
    axis = _floats(axis_element, "xyz") if axis_element is not None else [1.0, 0.0, 0.0]
    kind = joint.get("type")
    if kind in ("revolute", "continuous"):
        return transformations.rotation_matrix(value, axis)
    if kind == "prismatic":
        return transformations.translation_matrix(np.asarray(axis) / np.linalg.norm(axis) * value)
    return np.eye(4)


def test_sapien_gives_an_empty_link_the_stand_in_body_condense_merges(
    maniskill: Any, tmp_path: Path
) -> None:
    import sapien

    from robospec.optimize.condense import SAPIEN_EMPTY_LINK

    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    robot = _load(scene, MASSLESS.encode(), tmp_path / "massless.urdf")
    for name in ("base", "frame", "marker"):
        link = next(link for link in robot.get_links() if link.name == name)
        assert link.mass == pytest.approx(SAPIEN_EMPTY_LINK.mass, rel=1e-6)
        np.testing.assert_allclose(link.inertia, np.diag(SAPIEN_EMPTY_LINK.inertia), rtol=1e-6)
        np.testing.assert_allclose(link.cmass_local_pose.p, SAPIEN_EMPTY_LINK.centre, atol=0)
