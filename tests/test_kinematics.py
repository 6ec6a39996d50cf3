"""Where a robot's links are (robospec.kinematics): yourdfpy places a URDF's, MuJoCo an MJCF's,
with ManiSkill's links and SAPIEN's readings — each joint at its own value (a mimic follower
too), a prismatic joint sliding along its unit axis, an MJCF body of two joints a chain of two
links, a joint counted from its ``ref``, the root where a skipped wrapper body stands, an
``<include>`` read from the model's folder. tests/test_gallery.py and tests/test_corpus.py hold the
same poses to SAPIEN's on real robots."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from robospec.description import load_description
from robospec.kinematics.forward import KinematicModel, kinematics_of

LIMIT = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'


def _urdf(tmp_path: Path, joints: str, links: str = "") -> KinematicModel:
    names = ["base", "a", "b", *links.split()]
    text = (
        '<robot name="r">'
        + "".join(f'<link name="{name}"/>' for name in names)
        + joints
        + "</robot>"
    ).encode()
    return _model(tmp_path / "r.urdf", text, "urdf")


def _model(path: Path, text: bytes, kind: str) -> KinematicModel:
    path.write_bytes(text)
    description, diagnostics = load_description(str(path), kind)  # type: ignore[arg-type]
    assert description is not None, diagnostics
    model = kinematics_of(description, text, str(path))
    assert model is not None
    return model


def test_a_mimic_follower_stands_at_its_own_value_as_sapien_sets_it(tmp_path: Path) -> None:
    model = _urdf(
        tmp_path,
        '<joint name="j1" type="revolute"><parent link="base"/><child link="a"/>'
        f'<axis xyz="0 0 1"/>{LIMIT}</joint>'
        '<joint name="j2" type="revolute"><parent link="base"/><child link="b"/>'
        f'<axis xyz="0 0 1"/>{LIMIT}<mimic joint="j1" multiplier="2"/></joint>',
    )
    links = model.at({"j1": 0.3, "j2": -0.5}).links
    assert math.atan2(links["a"][1, 0], links["a"][0, 0]) == pytest.approx(0.3)
    assert math.atan2(links["b"][1, 0], links["b"][0, 0]) == pytest.approx(-0.5)


def test_a_prismatic_joint_slides_along_its_unit_axis(tmp_path: Path) -> None:
    model = _urdf(
        tmp_path,
        '<joint name="slide" type="prismatic"><parent link="base"/><child link="a"/>'
        f'<origin xyz="1 0 0"/><axis xyz="0 0 2"/>{LIMIT}</joint>'
        '<joint name="fixed" type="fixed"><parent link="a"/><child link="b"/>'
        '<origin xyz="0 1 0" rpy="0 0 1.5707963267948966"/></joint>',
    )
    placed = model.at({"slide": 0.25})
    assert placed.links["a"][:3, 3] == pytest.approx((1.0, 0.0, 0.25))
    assert placed.links["b"][:3, 3] == pytest.approx((1.0, 1.0, 0.25))
    assert placed.axes["slide"].direction == pytest.approx((0.0, 0.0, 1.0))
    assert set(placed.axes) == {"slide"}


def test_a_geometry_yourdfpy_does_not_know_leaves_the_links_placed(tmp_path: Path) -> None:
    # pybullet's humanoid draws <capsule>s, which SAPIEN reads and yourdfpy's parser refuses
    capsule = '<collision><geometry><capsule radius="0.1" length="0.3"/></geometry></collision>'
    text = (
        f'<robot name="r"><link name="base">{capsule}</link><link name="a">{capsule}</link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="a"/>'
        f'<origin xyz="0 0 0.5"/><axis xyz="1 0 0"/>{LIMIT}</joint></robot>'
    ).encode()
    model = _model(tmp_path / "capsules.urdf", text, "urdf")
    assert model.at().links["a"][:3, 3] == pytest.approx((0.0, 0.0, 0.5))


MJCF = """<mujoco>
  <worldbody>
    <body name="wrapper" pos="0 0 1" euler="0 0 90">
      <body name="torso" pos="1 0 0">
        <joint name="slide" type="slide" axis="1 0 0"/>
        <geom type="box" size=".1 .1 .1"/>
        <body name="arm" pos="0 0 0.5">
          <joint name="turn" axis="0 0 1" ref="30"/>
          <joint name="tilt" axis="0 1 0" pos="0.2 0 0"/>
          <geom type="capsule" fromto="0 0 0 0.4 0 0" size=".05"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_an_mjcf_body_of_two_joints_is_two_links_each_moved_by_its_own(tmp_path: Path) -> None:
    model = _model(tmp_path / "arm.xml", MJCF.encode(), "mjcf")
    placed = model.at({"turn": math.pi / 2, "tilt": math.pi / 2})
    # the wrapper is skipped: the root link stands where it is; torso at its own pos in it
    assert placed.links["torso"][:3, 3] == pytest.approx((1.0, 0.0, 0.0))
    # arm_dummy_0: the arm body turned by its first joint alone (counted from its ref)
    first = placed.links["arm_dummy_0"]
    assert first[:3, 3] == pytest.approx((1.0, 0.0, 0.5))
    assert first[:3, 0] == pytest.approx((0.0, 1.0, 0.0))
    # arm: tilted too, about the axis through its pivot 0.2 m along the turned x
    arm = placed.links["arm"]
    assert arm[:3, 1] == pytest.approx((-1.0, 0.0, 0.0))
    assert arm[:3, 3] == pytest.approx((1.0, 0.2, 0.7))
    assert placed.axes["tilt"].anchor == pytest.approx((1.0, 0.2, 0.5))
    assert placed.axes["tilt"].direction == pytest.approx((-1.0, 0.0, 0.0))
    # at zero, every link is where the file writes it: a joint is counted from its ref
    rest = model.at()
    assert np.allclose(rest.links["arm"][:3, :3], np.eye(3))
    assert rest.links["arm"][:3, 3] == pytest.approx((1.0, 0.0, 0.5))


def test_an_mjcf_include_is_read_from_the_models_folder(tmp_path: Path) -> None:
    # the model is compiled from its text (a derived copy has no file of its own): its
    # <include>s are read where they stand, relative to the model's folder
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "robot.xml").write_text(
        '<mujoco><worldbody><body name="torso"><joint name="slide" type="slide"/>'
        '<geom type="box" size=".1 .1 .1"/><body name="arm" pos="0 0 0.5">'
        '<joint name="turn" axis="0 0 1"/><geom type="sphere" size=".05"/></body></body>'
        "</worldbody></mujoco>"
    )
    text = b'<mujoco><include file="parts/robot.xml"/></mujoco>'
    model = _model(tmp_path / "robot.xml", text, "mjcf")
    # the slide moves along MuJoCo's default axis, z
    assert model.at({"slide": 0.1}).links["arm"][:3, 3] == pytest.approx((0.0, 0.0, 0.6))
