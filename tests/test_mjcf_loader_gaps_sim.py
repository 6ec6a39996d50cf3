"""What robospec says ManiSkill's MJCF loader drops or reads differently (tests/test_mjcf_loader_
gaps.py, docs/loaders.md) is what ManiSkill 3.0.1 and SAPIEN do: each fixture of
tests/data/mjcf/gaps/ loaded with ManiSkill's own loader (headless), and the dropped thing shown
absent, the size, mass or frame shown as said, the failure shown to happen."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mjcf_scene import parse, scene_fixture  # noqa: F401  (the scene fixture)

from robospec.description import load_description
from robospec.description.mjcf_frames import maniskill_rotation, mujoco_rotation, same_rotation
from robospec.geometry import about_axis, rotate

pytestmark = pytest.mark.maniskill

GAPS = Path(__file__).parent / "data" / "mjcf" / "gaps"


def build(scene: Any, path: Path, x: float = 3.0) -> Any:
    """The robot built in ``scene`` away from the panda (at ``x``): ManiSkill's Articulation."""
    import sapien

    builder = parse(scene, path)
    builder.initial_pose = sapien.Pose([x, 3.0 + x, 0.0])
    return builder.build()


def load(scene: Any, path: Path, x: float = 3.0) -> Any:
    """:func:`build`'s SAPIEN articulation, all joints at 0."""
    robot = build(scene, path, x)._objs[0]
    robot.qpos = np.zeros(robot.dof)
    return robot


def by_name(robot: Any) -> dict[str, Any]:
    return {_short(link.name): link for link in robot.links}


def _short(name: str) -> str:
    """A link's name without the ``scene-0-{uid}_`` prefix SAPIEN's entity names carry."""
    return name.split("_", 1)[1] if name.startswith("scene-") else name


def step(scene: Any, steps: int) -> None:
    for _ in range(steps):
        scene.px.step()


def diagnostics(path: Path) -> set[str]:
    return {d.code for d in load_description(str(path), "mjcf")[1]}


def test_equality_couplings_and_tendons_are_not_loaded_the_fingers_move_apart(scene: Any) -> None:
    assert {"RS070", "RS071", "RS077"} <= diagnostics(GAPS / "coupling.xml")
    robot = load(scene, GAPS / "coupling.xml", x=3.0)
    # MuJoCo holds right = -left; in ManiSkill nothing ties them: move left, right stays
    robot.qpos = np.array([0.015, 0.0])
    step(scene, 20)
    left, right = robot.qpos
    assert left == pytest.approx(0.015, abs=1e-3) and right == pytest.approx(0.0, abs=1e-3)
    # and no actuator gain reaches the joints (the tendon's position actuator included)
    assert [joint.stiffness for joint in robot.active_joints] == [0.0, 0.0]


def test_excluded_and_filtered_pairs_collide_and_a_contype_0_geom_has_no_shape(
    scene: Any,
) -> None:
    assert "RS072" in diagnostics(GAPS / "contacts.xml")
    robot = load(scene, GAPS / "contacts.xml", x=6.0)
    step(scene, 1)
    touching = {
        tuple(sorted(_short(body.entity.name) for body in contact.bodies))
        for contact in scene.px.get_contacts()
    }
    assert ("a", "b") in touching  # <contact><exclude body1="a" body2="b"/>
    assert ("c", "d") in touching  # contype 2 / conaffinity 2 and 4 / 4: never in MuJoCo
    assert len(by_name(robot)["e"].collision_shapes) == 1  # its contype=0 foot has none


def test_mesh_scale_from_default_is_not_applied_and_a_missing_mesh_loads_nothing(
    scene: Any,
) -> None:
    robot = load(scene, GAPS / "mesh_scale.xml", x=9.0)
    mass = {name: link.mass for name, link in by_name(robot).items()}
    # cube_mm.stl is a 100 mm cube written in millimetres: meant 0.1 m and 1 kg at 1000 kg/m³
    assert mass["tip"] == pytest.approx(1.0, rel=1e-3)  # scale= on the <mesh>: applied
    assert mass["base"] == pytest.approx(1e9, rel=1e-3)  # scale in <default>: 1000x, 1e9 kg
    # cube_m.stl is 0.1 m; its class means 1.5x (3.375 kg): loaded as it is, and gone.stl is
    # loaded as nothing at all
    assert mass["link"] == pytest.approx(1.0, rel=1e-3)
    assert len(by_name(robot)["link"].collision_shapes) == 1


def test_an_unnamed_mesh_in_a_folder_is_a_key_error(scene: Any) -> None:
    with pytest.raises(KeyError, match="cube_m"):
        parse(scene, GAPS / "mesh_name.xml")


def test_a_mesh_the_root_class_main_names_is_a_key_error_of_no_name(scene: Any) -> None:
    with pytest.raises(KeyError) as raised:
        parse(scene, GAPS / "main_class_mesh.xml")
    assert raised.value.args == (None,)


def test_inertials_are_not_read_and_an_ellipsoid_only_link_weighs_1e_6_kg(scene: Any) -> None:
    links = by_name(load(scene, GAPS / "masses.xml", x=12.0))
    capsule = math.pi * 0.05**2 * 0.4 + 4 / 3 * math.pi * 0.05**3  # r 0.05, half-length 0.2
    assert links["upper_arm"].mass == pytest.approx(1000 * capsule, rel=1e-4)  # not 8.393
    assert links["hand"].mass == pytest.approx(1e-6)
    assert links["hand"].collision_shapes == []


def test_euler_is_read_with_its_second_angle_negated(scene: Any) -> None:
    links = by_name(load(scene, GAPS / "orientation.xml", x=15.0))
    tilted = tuple(links["tilted"].entity_pose.q)
    meant = mujoco_rotation({"euler": "0 30 0"}, True, "xyz")
    assert same_rotation(tilted, about_axis((0.0, 1.0, 0.0), -math.pi / 6), 1e-6)
    assert not same_rotation(tilted, meant, 1e-3)
    # the snout capsule (euler 0 50 0) points along SAPIEN's capsule axis, x of its shape
    snout = links["head"].collision_shapes[0]
    axis = rotate(tuple(snout.local_pose.q), (1.0, 0.0, 0.0))
    theirs = maniskill_rotation({"euler": "0 50 0"}, True)
    meant = mujoco_rotation({"euler": "0 50 0"}, True, "xyz")
    assert theirs is not None
    # a capsule's axis either way round
    assert abs(np.dot(axis, rotate(theirs, (0.0, 0.0, 1.0)))) == pytest.approx(1.0, abs=1e-5)
    assert abs(np.dot(axis, rotate(meant, (0.0, 0.0, 1.0)))) < 0.5


def test_zaxis_along_z_fails_the_whole_load(scene: Any) -> None:
    with pytest.raises(np.linalg.LinAlgError):
        parse(scene, GAPS / "zaxis_floor.xml")


def test_a_height_field_anywhere_fails_the_whole_load(scene: Any) -> None:
    with pytest.raises(NotImplementedError, match="Height fields"):
        parse(scene, GAPS / "hfield.xml")


def test_an_include_inside_a_body_is_not_read_and_the_robot_is_the_next_body(scene: Any) -> None:
    robot = load(scene, GAPS / "include.xml", x=18.0)
    assert list(by_name(robot)) == ["dummy_root_1", "object"]


def test_a_skipped_wrapper_takes_its_pose_along(scene: Any) -> None:
    import sapien

    builder = parse(scene, GAPS / "wrapper.xml")
    builder.initial_pose = sapien.Pose()
    robot = builder.build()._objs[0]
    robot.qpos = np.zeros(robot.dof)
    base = by_name(robot)["base"]
    assert base.entity_pose.p[2] == pytest.approx(0.5)  # the file: 1 + 0.5
    description, _ = load_description(str(GAPS / "wrapper.xml"), "mjcf")
    assert description is not None and description.root_body_pose is not None
    assert description.root_body_pose[0] == (0.0, 0.0, 1.0)  # what the keyframe pose restores


def test_ref_stiffness_and_armature_are_not_loaded(scene: Any) -> None:
    robot = load(scene, GAPS / "joint_attributes.xml", x=21.0)
    (joint,) = robot.active_joints
    # range -30..30 degrees about the file's pose, not about ref=10
    assert np.allclose(joint.limits, [[-math.pi / 6, math.pi / 6]])
    assert list(joint.armature) == [0.0]
    robot.qpos = np.array([0.3])  # a spring of stiffness 50 would pull it back
    step(scene, 50)
    assert robot.qpos[0] == pytest.approx(0.3, abs=1e-3)


def test_group_1_geoms_get_no_visual_body(scene: Any) -> None:
    import xml.etree.ElementTree as ET

    from mani_skill.utils.building._mjcf_loader import MJCFLoader

    from robospec.maniskill.headless import headless_loading

    def visuals(group: int) -> int:
        loader = MJCFLoader()  # its visual groups: 0 and 2
        loader._use_degrees, loader._euler_seq, loader._materials = True, [1, 2, 3], {}
        builder = scene.create_actor_builder()
        geom = ET.Element("geom", {"type": "box", "size": ".1 .1 .1", "group": str(group)})
        loader._build_geom(geom, builder, {})
        return len(builder.visual_records)

    with headless_loading():  # SAPIEN makes no render material without a render device
        assert (visuals(0), visuals(1), visuals(2)) == (1, 0, 1)


def _chain(path: Path, bodies: int) -> Path:
    text = '<mujoco>\n<worldbody>\n<body name="b0" pos="0 0 .1"><freejoint/><geom size=".02"/>\n'
    for i in range(1, bodies):
        # hinges about y: a tail the floor does not hold droops below it
        joint = f'<joint name="j{i}" axis="0 1 0"/>'
        text += f'<body name="b{i}" pos=".05 0 0">{joint}<geom size=".02"/>\n'
    text += "</body>" * bodies + "\n</worldbody>\n</mujoco>\n"
    path.write_text(text)
    return path


def test_the_33rd_body_fails_and_the_31st_falls_through_the_floor(
    scene: Any, tmp_path: Path
) -> None:
    with pytest.raises(TypeError, match="set_collision_groups"):
        load(scene, _chain(tmp_path / "c33.xml", 33))
    robot = load(scene, _chain(tmp_path / "c31.xml", 31), x=24.0)
    step(scene, 150)
    height = {name: link.entity_pose.p[2] for name, link in by_name(robot).items()}
    assert height["b10"] > 0.0  # resting on the floor
    assert height["b30"] < -0.05  # bit 30, the ground's: no contact with it


def test_link_rules_fail_on_the_mjcf_loader_and_ee_controllers_without_a_urdf(
    scene: Any,
) -> None:
    from mani_skill.agents.controllers.utils.kinematics import Kinematics
    from mani_skill.utils import sapien_utils
    from sapien.physx import PhysxMaterial

    loader = scene.create_mjcf_loader()
    config = {"link": {"lower": {"material": PhysxMaterial(2.0, 2.0, 0.0)}}}
    with pytest.raises(AttributeError, match="set_link_material"):  # RS324
        sapien_utils.apply_urdf_config(loader, config)
    robot = build(scene, GAPS / "masses.xml", x=27.0)
    with pytest.raises(TypeError):  # RS325: no urdf_path at all
        Kinematics(None, "hand", robot, [0, 1])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="URDF"):  # nor the MJCF in its place
        Kinematics(str(GAPS / "masses.xml"), "hand", robot, [0, 1])


def _hand_from_root(robot: Any, link: str) -> np.ndarray:
    """Link ``link``'s pose in the robot's root link's frame, as a 4x4 matrix."""
    links = by_name(robot)
    root = robot.get_links()[0].entity_pose.to_transformation_matrix()
    pose = links[link].entity_pose.to_transformation_matrix()
    return np.linalg.inv(root) @ pose


def test_a_joint_without_an_axis_turns_about_x_and_the_axes_mend_puts_the_link_where_mujoco_does(
    scene: Any, tmp_path: Path
) -> None:
    from conftest import CODE_EXAMPLES

    from robospec.derive import Source, derive
    from robospec.kinematics.mjcf_poses import mjcf_poser

    unaxed = CODE_EXAMPLES / "RS095" / "unaxed.xml"
    assert "RS095" in diagnostics(unaxed)
    description = load_description(str(unaxed), "mjcf")[0]
    assert description is not None
    poser = mjcf_poser(description, unaxed.read_bytes(), str(unaxed))
    assert poser is not None
    shoulder = {"shoulder": 0.5}
    mujoco_hand = poser(shoulder).links["hand"]

    def hand(path: Path, x: float) -> np.ndarray:
        robot = load(scene, path, x=x)
        names = [joint.name for joint in robot.active_joints]
        robot.qpos = np.array([0.5 if name.endswith("shoulder") else 0.0 for name in names])
        return _hand_from_root(robot, "hand")

    # as written: the shoulder turns about x, and the hand stands elsewhere than in MuJoCo
    as_written = hand(unaxed, x=9.0)
    assert np.linalg.norm(as_written[:3, 3] - mujoco_hand[:3, 3]) > 0.05
    # mended: the shoulder's axis written as MuJoCo reads it, the hand where MuJoCo puts it
    derived = derive(
        Source(str(unaxed), unaxed.name, "mjcf", unaxed.read_bytes()), {"axes": "mujoco"}
    )
    mended = tmp_path / "unaxed.xml"
    mended.write_text(derived.text)
    assert "RS095" not in diagnostics(mended)
    np.testing.assert_allclose(hand(mended, x=12.0), mujoco_hand, atol=1e-5)


@pytest.mark.parametrize(
    ("extra", "written"),
    [
        pytest.param("", "loader: mujoco", id="mujoco-compiles-it"),
        # an attribute MuJoCo refuses (ManiSkill's loader ignores it): new keeps that loader
        pytest.param(' bogus="1"', "axes: mujoco", id="maniskill-loader"),
    ],
)
def test_new_writes_a_spec_that_validates_for_a_joint_without_an_axis(
    tmp_path: Path, extra: str, written: str
) -> None:
    from conftest import CODE_EXAMPLES, invoke_robospec

    text = (CODE_EXAMPLES / "RS095" / "unaxed.xml").read_text()
    (tmp_path / "unaxed.xml").write_text(
        text.replace(
            '<geom type="box" size=".1 .1 .02"/>', f'<geom type="box" size=".1 .1 .02"{extra}/>'
        )
    )
    spec = tmp_path / "arm.yaml"
    result = invoke_robospec("new", str(tmp_path / "unaxed.xml"), "-o", str(spec))
    assert result.exit_code == 0, result.output
    assert written in spec.read_text()
    checked = invoke_robospec("validate", str(spec))
    assert checked.exit_code == 0, checked.output
    assert "RS095" not in checked.output
