"""Text SAPIEN's URDF loader stops at is a located diagnostic, never a traceback.

Each case is a small URDF with one thing SAPIEN's parser (its copy of urchin) or its loader
cannot take, and the same URDF mended. The fast tests hold robospec to the code and the line;
the ``maniskill`` ones prove against SAPIEN that the broken text really stops the load and that
the mended one loads.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from mesh_files import STL

from robospec.description.urdf import parse_urdf

ARM = """<?xml version="1.0"?>
<robot{ROBOT}>
  <link name="base_link"/>
  <link name="upper_arm">
    <inertial>
      <mass value="1"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/>
    </inertial>{LINK}
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="upper_arm"/>{JOINT}
    <axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>{TOP}
</robot>
"""
NAMED = ' name="arm"'
BOX = '\n    <collision><geometry><box size="0.05 0.05 0.3"/></geometry></collision>'
MESH = '\n    <collision><geometry><mesh filename="part.stl"{}/></geometry></collision>'
VISUAL = '\n    <visual><geometry><box size="0.05 0.05 0.3"/></geometry>{}</visual>'
TRANSMISSION = """
  <transmission name="shoulder_transmission"{ATTR}>{TYPE}
    <joint name="shoulder"/>{ACTUATOR}
  </transmission>"""
TYPE = "\n    <type>transmission_interface/SimpleTransmission</type>"
ACTUATOR = '\n    <actuator name="motor"><mechanicalReduction>{}</mechanicalReduction></actuator>'
CAMERA = """
  <gazebo reference="upper_arm">
    <sensor type="camera" name="wrist_camera">
      <camera>
        <image>{IMAGE}</image>{FOV}
      </camera>
    </sensor>
  </gazebo>"""


def arm(robot: str = NAMED, link: str = BOX, joint: str = "", top: str = "") -> str:
    return (
        ARM.replace("{ROBOT}", robot)
        .replace("{LINK}", link)
        .replace("{JOINT}", joint)
        .replace("{TOP}", top)
    )


def transmission(attr: str = "", type_: str = TYPE, actuator: str = "1") -> str:
    actuators = ACTUATOR.format(actuator) if actuator else ""
    return (
        TRANSMISSION.replace("{ATTR}", attr)
        .replace("{TYPE}", type_)
        .replace("{ACTUATOR}", actuators)
    )


def camera(image: str = "<width>64</width><height>48</height>", fov: str = "1.2") -> str:
    fovs = f"\n        <horizontal_fov>{fov}</horizontal_fov>" if fov else ""
    return CAMERA.replace("{IMAGE}", image).replace("{FOV}", fovs)


@dataclass(frozen=True)
class Case:
    id: str
    broken: str
    mended: str
    code: str
    at: str  # the text of the line the diagnostic points at (its first occurrence)
    words: str


CASES = [
    Case("robot_without_name", arm(robot=""), arm(), "RS052", "<robot>", "<robot> has no name"),
    Case(
        "collision_without_geometry",
        arm(link='\n    <collision><origin xyz="0 0 0.1"/></collision>'),
        arm(),
        "RS052",
        "<collision>",
        "has no <geometry>",
    ),
    Case(
        "geometry_plane",
        arm(link='\n    <collision><geometry><plane normal="0 0 1"/></geometry></collision>'),
        arm(),
        "RS052",
        "<plane",
        "<geometry> has <plane>",
    ),
    Case(
        "box_of_two_numbers",
        arm(link=BOX.replace("0.05 0.05 0.3", "0.05 0.3")),
        arm(),
        "RS052",
        "<box",
        'size="0.05 0.3" is not 3 numbers',
    ),
    Case(
        "sphere_without_radius",
        arm(link="\n    <collision><geometry><sphere/></geometry></collision>"),
        arm(link='\n    <collision><geometry><sphere radius="0.05"/></geometry></collision>'),
        "RS052",
        "<sphere",
        'has no radius=""',
    ),
    Case(
        "mesh_scale_of_four_numbers",  # pybullet's racecar_differential
        arm(link=MESH.format(' scale="1 1 1 1"')),
        arm(link=MESH.format(' scale="1 1 1"')),
        "RS052",
        "<mesh",
        'scale="1 1 1 1" is not 3 numbers',
    ),
    Case(
        "collision_origin_of_two_numbers",
        arm(link=BOX.replace("<geometry>", '<origin xyz="0 0.1"/><geometry>')),
        arm(link=BOX.replace("<geometry>", '<origin xyz="0 0 0.1"/><geometry>')),
        "RS052",
        "<collision>",
        'xyz="0 0.1" is not 3 numbers',
    ),
    Case(
        "visual_material_without_name",
        arm(link=VISUAL.format('<material><color rgba="1 0 0 1"/></material>') + BOX),
        arm(link=VISUAL.format('<material name="red"><color rgba="1 0 0 1"/></material>') + BOX),
        "RS052",
        "<visual>",
        'has no name=""',
    ),
    Case(
        "color_of_three_numbers",
        arm(top='\n  <material name="red"><color rgba="1 0 0"/></material>'),
        arm(top='\n  <material name="red"><color rgba="1 0 0 1"/></material>'),
        "RS052",
        "<material",
        'rgba="1 0 0" is not 4 numbers',
    ),
    Case(
        "empty_texture",  # example-robot-data's iCub and Romeo
        arm(top='\n  <material name="skin">\n    <texture/>\n  </material>'),
        arm(top='\n  <material name="skin">\n  </material>'),
        "RS052",
        "<texture/>",
        "<texture> without filename",
    ),
    Case(
        "duplicate_material",
        arm(top='\n  <material name="red"/>\n  <material name="red"/>'),
        arm(top='\n  <material name="red"/>'),
        "RS052",
        '<material name="red"/>\n</robot>',  # the second one
        "duplicate material name 'red'",
    ),
    Case(
        "safety_controller_without_k_velocity",
        arm(joint='\n    <safety_controller k_position="10"/>'),
        arm(joint='\n    <safety_controller k_position="10" k_velocity="1"/>'),
        "RS052",
        "<safety_controller",
        'has no k_velocity=""',
    ),
    Case(
        "dynamics_damping_word",
        arm(joint='\n    <dynamics damping="high"/>'),
        arm(joint='\n    <dynamics damping="0.7"/>'),
        "RS052",
        "<dynamics",
        'damping="high" is not a number',
    ),
    Case(
        "inertial_without_mass",
        arm().replace('      <mass value="1"/>\n', ""),
        arm(),
        "RS052",
        "<inertial>",
        'has no <mass value="..."/>',
    ),
    Case(
        "inertia_without_ixy",
        arm().replace(' ixy="0"', ""),
        arm(),
        "RS052",
        "<inertia ",
        "<inertia> has no ixy",
    ),
    Case(
        "optenv_in_an_origin",  # pybullet's Husky
        arm(joint='\n    <origin xyz="$(optenv ARM_XYZ 0 0 0.1)"/>'),
        arm(joint='\n    <origin xyz="0 0 0.1"/>'),
        "RS063",
        "<origin",
        'write its value: "0 0 0.1" is its default',
    ),
    Case(
        "substitution_in_a_mass",
        arm().replace('<mass value="1"/>', '<mass value="${arm_mass}"/>'),
        arm(),
        "RS063",
        "<mass",
        "xacro/roslaunch substitution",
    ),
    Case(
        "transmission_type_as_an_attribute",  # the PR2
        arm(top=transmission(attr=' type="SimpleTransmission"', type_="")),
        arm(top=transmission()),
        "RS064",
        "<transmission",
        '(type="SimpleTransmission" is an attribute, the old URDF format)',
    ),
    Case(
        "mechanical_reduction_word",  # pybullet's xArm6
        arm(top=transmission(actuator="reduction")),
        arm(top=transmission(actuator="100")),
        "RS064",
        "<actuator",
        "'reduction' is not a number",
    ),
    Case(
        "transmission_without_actuator",
        arm(top=transmission(actuator="")),
        arm(top=transmission()),
        "RS064",
        "<transmission",
        "has no <actuator>",
    ),
    Case(
        "camera_without_field_of_view",
        arm(top=camera(fov="")),
        arm(top=camera()),
        "RS052",
        "<camera>",
        "has no horizontal_fov or vertical_fov",
    ),
    Case(
        "camera_without_height",
        arm(top=camera(image="<width>64</width>")),
        arm(top=camera()),
        "RS052",
        "<image>",
        "height is 'missing'",
    ),
]
IDS = [case.id for case in CASES]


def line_of(text: str, snippet: str) -> int:
    return text[: text.index(snippet)].count("\n") + 1


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_text_sapien_stops_at_is_one_diagnostic_at_its_element(case: Case) -> None:
    _description, diagnostics = parse_urdf(case.broken, "arm.urdf")
    [problem] = diagnostics
    assert problem.is_error
    assert (problem.code, problem.location.line) == (case.code, line_of(case.broken, case.at))
    assert case.words in f"{problem.message} {problem.hint}"


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_the_mended_text_has_no_diagnostic(case: Case) -> None:
    description, diagnostics = parse_urdf(case.mended, "arm.urdf")
    assert description is not None and diagnostics == []


def test_many_transmissions_sapien_cannot_read_are_one_error_with_their_lines() -> None:
    old_style = transmission(attr=' type="SimpleTransmission"', type_="")
    text = arm(top="".join(old_style.replace("shoulder_", f"t{i}_") for i in range(3)))
    [problem] = parse_urdf(text, "arm.urdf")[1]
    assert problem.code == "RS064"
    assert "(and 2 more transmission problems: lines 21, 25)" in problem.message


# -- against SAPIEN ---------------------------------------------------------------------------


def sapien_load(text: str, folder: Path) -> BaseException | None:
    """What SAPIEN 3.0.3 does with the URDF ``text``, as ManiSkill loads a robot: its parser
    reads the whole text (visuals included), then the articulation is built (without visuals:
    there is no render device here). The exception that stops it, or None when it loads."""
    import sapien
    from lxml import etree
    from sapien.wrapper.urchin import URDF

    from robospec.maniskill.headless import strip_urdf_visuals

    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    try:
        URDF._from_xml(etree.fromstring(text.encode()), str(folder), lazy_load_meshes=True)
        loader = scene.create_urdf_loader()
        loader.urdf_dir, loader.package_dir, loader.ignore_pairs = str(folder), None, []
        articulation_builders, _actors, _cameras = loader._parse_urdf(strip_urdf_visuals(text))
        articulation_builders[0].build()
    except Exception as stopped:  # what SAPIEN raises is what the test is about
        return stopped
    finally:
        del scene
    return None


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "part.stl").write_text(STL)
    return tmp_path


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_sapien_stops_at_the_broken_text_and_loads_the_mended_one(case: Case, folder: Path) -> None:
    stopped: Any = sapien_load(case.broken, folder)
    assert stopped is not None, "SAPIEN loaded what robospec calls an error"
    assert sapien_load(case.mended, folder) is None
