"""How ``robospec check`` runs a robot, on real SAPIEN physics with tiny robots: a step that a
self-contact blocks one way goes the other way; a floating robot's test stand holds it clear of
the ground; a runaway is the robot's centre of mass moving, not a far-off root link swinging
round. Each would have failed a corpus robot for the check's procedure, not for a defect. And
which links ``robospec new`` finds adjacent through shapeless links or a universal joint
(robospec.authoring.new.exemptions, over what its probe's LoadedRobot says)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pytest

from robospec.pipeline import compile_spec

if TYPE_CHECKING:
    from robospec.authoring.new.joint_space import JointSpace
    from robospec.authoring.new.probe import LoadedRobot

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]

BOX = '<geometry><box size="{}"/></geometry>'
LIMIT = '<limit lower="-1" upper="1" effort="10" velocity="5"/>'
INERTIAL = (
    '<inertial><mass value="1"/>'
    '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
)

# a fixed post with an arm turning about z; a wall fixed to the base lies 2 mm beside the arm on
# the side a step towards the farther limit (upper, 2 rad away; lower 1 rad) turns it into
WALLED = f"""<?xml version="1.0"?>
<robot name="walled">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="wall">
    <inertial><origin xyz="0.3 0.052 0.5"/><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><origin xyz="0.3 0.052 0.5"/>{BOX.format("0.2 0.02 0.1")}</collision>
  </link>
  <link name="arm">
    <inertial><origin xyz="0.2 0 0.5"/><mass value="1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><origin xyz="0.2 0 0.5"/>{BOX.format("0.4 0.08 0.05")}</collision>
  </link>
  <joint name="wall_mount" type="fixed"><parent link="base"/><child link="wall"/></joint>
  <joint name="turn" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="2" effort="100" velocity="5"/>
  </joint>
</robot>
"""

# a floating stick: a massless root link 1.5 m below a 10 kg body (as ManiSkill's MJCF loader
# roots a free joint at the world body's frame), and a foot hanging 0.7 m below the body: with
# the root 0.8 m below the ground, the foot stands on it
STICK = f"""<?xml version="1.0"?>
<robot name="stick">
  <link name="root"><inertial><mass value="0.001"/>
    <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <link name="body">
    <inertial><mass value="10"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision>{BOX.format("0.2 0.2 0.2")}</collision>
  </link>
  <link name="foot">
    <inertial><origin xyz="0 0 -0.3"/><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><origin xyz="0 0 -0.3"/>{BOX.format("0.1 0.1 0.6")}</collision>
  </link>
  <joint name="mount" type="fixed">
    <parent link="root"/><child link="body"/><origin xyz="0 0 1.5"/>
  </joint>
  <joint name="hip" type="revolute">
    <parent link="body"/><child link="foot"/><origin xyz="0 0 -0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="100" velocity="5"/>
  </joint>
</robot>
"""


# a foot two hinges below its base through a link without shapes (as a spherical joint becomes
# three hinges): adjacent; a thigh below a hip whose housing (welded to it) has shapes, on a hinge
# whose axis misses the hip's: not. Two universal joints (a cross with shapes between hinges whose
# axes meet, iCub's shoulder): the yoke nesting 3 mm beside the base is declared, the far one not;
# nor one 3 mm beside it whose second hinge is 5 cm off the first's axis. A flange welded under
# the base, a plate welded to the flange 5 mm beside the base, and a bar hinged to the base
# 2.5 cm below the flange: PhysX collides the bar with the flange and the plate with the base
CHAINED = f"""<?xml version="1.0"?>
<robot name="chained">
  <link name="base">{INERTIAL}<collision>{BOX.format("0.1 0.1 0.1")}</collision></link>
  <link name="between">{INERTIAL}</link>
  <link name="foot">{INERTIAL}
    <collision><origin xyz="0 0 -0.2"/>{BOX.format("0.1 0.1 0.1")}</collision></link>
  <link name="hip">{INERTIAL}</link>
  <link name="housing">{INERTIAL}<collision>{BOX.format("0.05 0.05 0.05")}</collision></link>
  <link name="thigh">{INERTIAL}
    <collision><origin xyz="0 0 -0.2"/>{BOX.format("0.05 0.05 0.1")}</collision></link>
  <joint name="a" type="revolute"><parent link="base"/><child link="between"/>
    <origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>{LIMIT}</joint>
  <joint name="b" type="revolute"><parent link="between"/><child link="foot"/>
    <axis xyz="0 1 0"/>{LIMIT}</joint>
  <joint name="c" type="revolute"><parent link="base"/><child link="hip"/>
    <origin xyz="-0.3 0 0"/><axis xyz="1 0 0"/>{LIMIT}</joint>
  <joint name="weld" type="fixed"><parent link="hip"/><child link="housing"/></joint>
  <joint name="d" type="revolute"><parent link="hip"/><child link="thigh"/>
    <origin xyz="0 0 -0.05"/><axis xyz="0 1 0"/>{LIMIT}</joint>
  <link name="cross">{INERTIAL}<collision>{BOX.format("0.02 0.02 0.02")}</collision></link>
  <link name="yoke">{INERTIAL}<collision>{BOX.format("0.05 0.05 0.05")}</collision></link>
  <joint name="e" type="revolute"><parent link="base"/><child link="cross"/>
    <origin xyz="0 0.078 0"/><axis xyz="1 0 0"/>{LIMIT}</joint>
  <joint name="f" type="revolute"><parent link="cross"/><child link="yoke"/>
    <axis xyz="0 1 0"/>{LIMIT}</joint>
  <link name="far_cross">{INERTIAL}<collision>{BOX.format("0.02 0.02 0.02")}</collision></link>
  <link name="far_yoke">{INERTIAL}
    <collision><origin xyz="0 0 -0.2"/>{BOX.format("0.05 0.05 0.1")}</collision></link>
  <joint name="g" type="revolute"><parent link="base"/><child link="far_cross"/>
    <origin xyz="0 -0.3 0"/><axis xyz="1 0 0"/>{LIMIT}</joint>
  <joint name="h" type="revolute"><parent link="far_cross"/><child link="far_yoke"/>
    <axis xyz="0 1 0"/>{LIMIT}</joint>
  <link name="offset_cross">{INERTIAL}<collision>{BOX.format("0.02 0.02 0.02")}</collision></link>
  <link name="offset_yoke">{INERTIAL}<collision>{BOX.format("0.05 0.05 0.05")}</collision></link>
  <joint name="i" type="revolute"><parent link="base"/><child link="offset_cross"/>
    <origin xyz="0 -0.078 0"/><axis xyz="1 0 0"/>{LIMIT}</joint>
  <joint name="j" type="revolute"><parent link="offset_cross"/><child link="offset_yoke"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/>{LIMIT}</joint>
  <link name="flange">{INERTIAL}<collision>{BOX.format("0.03 0.03 0.03")}</collision></link>
  <joint name="bolt" type="fixed"><parent link="base"/><child link="flange"/>
    <origin xyz="0 0 -0.075"/></joint>
  <link name="plate">{INERTIAL}
    <collision><origin xyz="0.065 0 0.075"/>{BOX.format("0.02 0.02 0.02")}</collision></link>
  <joint name="rivet" type="fixed"><parent link="flange"/><child link="plate"/></joint>
  <link name="bar">{INERTIAL}<collision>{BOX.format("0.05 0.05 0.05")}</collision></link>
  <joint name="k" type="revolute"><parent link="base"/><child link="bar"/>
    <origin xyz="0 0 -0.14"/><axis xyz="0 0 1"/>{LIMIT}</joint>
</robot>
"""
# two pincers, each a jaw sliding open along y and its mirror (a mimic follower, multiplier -1):
# closed, the first pincer's jaws are 5 mm apart (the mechanism keeps them so), the second's
# meet 2 mm deep (they touch closed, as fingers closing on nothing do)
JAW = BOX.format("0.02 0.02 0.02")
PINCERS = (
    f"""<?xml version="1.0"?>
<robot name="pincers">
  <link name="base">{INERTIAL}<collision>{BOX.format("0.1 0.1 0.1")}</collision></link>
"""
    + "".join(
        f"""  <link name="{jaw}{k}">{INERTIAL}<collision>{JAW}</collision></link>
  <joint name="{jaw}{k}" type="prismatic"><parent link="base"/><child link="{jaw}{k}"/>
    <origin xyz="{x} {side * centre} 0"/><axis xyz="0 {side} 0"/>
    <limit lower="0" upper="0.05" effort="10" velocity="1"/></joint>
"""
        for k, x, centre in [(1, 0.3, 0.0125), (2, -0.3, 0.009)]
        for jaw, side in [("left", 1), ("right", -1)]
    )
    + "</robot>\n"
)
JOINTS = {
    "walled": ["turn"],
    "stick": ["hip"],
    "chained": [*"abcdefghijk"],
    "pincers": ["left1", "right1", "left2", "right2"],
}


def _spec(folder: Path, name: str, urdf: str, floating: bool) -> Path:
    (folder / f"{name}.urdf").write_text(urdf)
    joints = JOINTS[name]
    qpos = [0.0] * len(joints)
    height = -0.8 if floating else 0.0
    fixed = str(not floating).lower()
    spec = folder / f"{name}.yaml"
    spec.write_text(
        f"""robospec: 1
uid: rs_test_{name}
description: {{urdf: {name}.urdf}}
loader: {{fix_root_link: {fixed}}}
keyframes:
  rest: {{qpos: {qpos}, pose: {{p: [0, 0, {height}]}}}}
controllers:
  drive: {{type: pd_joint_pos, joints: {joints}, lower: null, upper: null, stiffness: 100,
          damping: 10, force_limit: 100, normalize_action: false}}
control_modes:
  pd_joint_pos: {{drive: drive, balance_passive_force: {fixed}}}
"""
    )
    return spec


@pytest.fixture(scope="module")
def robots(tmp_path_factory: pytest.TempPathFactory, maniskill: object) -> dict[str, Path]:
    from robospec.output.register import register

    folder = tmp_path_factory.mktemp("procedure")
    specs = {
        "walled": _spec(folder, "walled", WALLED, floating=False),
        "stick": _spec(folder, "stick", STICK, floating=True),
        "chained": _spec(folder, "chained", CHAINED, floating=False),
        "pincers": _spec(folder, "pincers", PINCERS, floating=False),
    }
    for spec in specs.values():
        compiled = compile_spec(spec)
        assert not [d.format_text() for d in compiled.diagnostics if d.is_error]
        register(spec)
    return specs


def test_a_step_blocked_by_a_self_contact_is_taken_the_other_way(robots: dict[str, Path]) -> None:
    from robospec.physics.sim import Sim
    from robospec.physics.step_response import step_trace

    compiled = compile_spec(robots["walled"])
    assert compiled.context is not None and compiled.robot is not None
    settings = compiled.context.spec.checks.step_response.for_controller("drive")
    with Sim("rs_test_walled", "pd_joint_pos") as sim:
        trace = step_trace(sim, "drive", compiled.robot.keyframes[0], settings)
    # away from the nearer limit (+) the arm meets the wall; the other way it has room
    assert trace.reversed == ("turn",)
    assert trace.size[0] < 0
    (response,) = trace.responses
    assert response.reached >= 0.9 and response.rise_time is not None


def test_a_test_stand_holds_a_floating_robot_clear_of_the_ground(robots: dict[str, Path]) -> None:
    from robospec.physics.sim import TEST_STAND_HEIGHT, Sim

    compiled = compile_spec(robots["stick"])
    assert compiled.robot is not None
    with Sim("rs_test_stick", "pd_joint_pos") as sim:
        sim.start(compiled.robot.keyframes[0])
        # at its keyframe the foot stands on the ground
        sim.hold_drive_targets()
        sim.sim_step(sim.robot.pose)
        assert {link for link, _, _ in sim.ground_contacts()} == {"foot"}
        before = sim.root_position()[0, 2]
        pin = sim.test_stand()
        assert pin is not None
        assert sim.root_position()[0, 2] == pytest.approx(before + TEST_STAND_HEIGHT, abs=1e-4)
        for _ in range(20):
            sim.sim_step(pin)
        assert sim.ground_contacts() == []
        assert min(sim.lowest_points().values()) > 1.0


def test_a_runaway_is_the_centre_of_mass_moving_not_a_far_root_link_swinging(
    robots: dict[str, Path],
) -> None:
    import torch

    from robospec.physics.sim import Sim

    compiled = compile_spec(robots["stick"])
    assert compiled.robot is not None
    with Sim("rs_test_stick", "pd_joint_pos") as sim:
        sim.start(compiled.robot.keyframes[0])
        sim.test_stand()
        # spin the robot about its centre of mass at 10 rad/s: the root link, 1.5 m from it,
        # swings round at about 15 m/s while the robot goes nowhere
        spin = np.array([10.0, 0.0, 0.0])
        arm = sim.root_position()[0] - sim.centre_of_mass()
        sim.robot.set_root_angular_velocity(torch.tensor([spin], dtype=torch.float32))
        sim.robot.set_root_linear_velocity(torch.tensor([np.cross(spin, arm)], dtype=torch.float32))
        sim.sim_step()  # (the links' velocities follow the root's in a step; 10 ms of gravity)
        swing = float(np.linalg.norm(sim.robot.root_linear_velocity.numpy()[0]))
        assert swing > 10.0
        assert sim.root_speed()[0] < 0.5
        # moving as a whole, it is the speed of the whole
        sim.robot.set_root_angular_velocity(torch.zeros((1, 3)))
        sim.robot.set_root_linear_velocity(torch.tensor([[0.0, 3.0, 0.0]]))
        sim.sim_step()
        assert sim.root_speed()[0] == pytest.approx(3.0, rel=0.02)


@contextmanager
def _loaded(
    robots: dict[str, Path],
    name: str,
    limits: tuple[float, float],
    mimic: tuple[tuple[int, int, float, float], ...] = (),
) -> Iterator[tuple[LoadedRobot, JointSpace]]:
    """Robot ``name`` loaded as ``new``'s probe loads it, and its joints, each within
    ``limits``, in its description's kinematic tree."""
    from robospec.authoring.new.joint_space import JointSpace
    from robospec.authoring.new.probe import LoadedRobot
    from robospec.kinematics.tree import KinematicTree
    from robospec.physics.sim import Sim

    compiled = compile_spec(robots[name])
    assert compiled.description is not None
    joints = JOINTS[name]
    tree = KinematicTree(compiled.description)
    space = JointSpace(tree, joints, [limits] * len(joints), mimic)
    robot = LoadedRobot(Sim(f"rs_test_{name}", "pd_joint_pos"))
    try:
        yield robot, space
    finally:
        robot.sim.close()


def test_new_finds_links_adjacent_through_shapeless_links_welds_or_a_universal_joint(
    robots: dict[str, Path],
) -> None:
    from robospec.authoring.new.exemptions import (
        nesting_yokes,
        shapeless_neighbours,
        welded_neighbours,
    )

    with _loaded(robots, "chained", (-1.0, 1.0)) as (robot, space):
        found = robot.bodies(space.tree)
        # the foot hangs from the base through a shapeless link: PhysX, which leaves a parent
        # and its child alone, collides them; the thigh's parent is the hip with its housing,
        # its hinge 5 cm below the hip's
        # (and through it from what is welded to the base)
        assert shapeless_neighbours(found) == [
            ("base", "foot"),
            ("flange", "foot"),
            ("foot", "plate"),
        ]
        # the yoke turns about the point where its cross's hinges meet, 3 mm beside the base:
        # PhysX reports them in contact; the far yoke is 15 cm from it; the offset one is as
        # near, but its hinges' axes pass 5 cm apart
        rest = [0.0] * 11
        near = robot.posed(rest)
        assert nesting_yokes(found, robot.sim.hinge_axes(), near) == [("base", "yoke")]
        # welded to the base, the flange and the plate are the bar's parent as much as the
        # base is, and the plate is the base: PhysX leaves out only the base and the bar
        welded = welded_neighbours(found, space, rest, near, robot.sweep())
        assert welded == [("bar", "flange"), ("base", "plate")]


def test_new_leaves_out_the_parts_of_a_mechanism_its_coupling_keeps_apart(
    robots: dict[str, Path],
) -> None:
    from robospec.authoring.new.exemptions import mechanism_pairs
    from robospec.authoring.new.joint_space import JointSpace

    mimic = ((1, 0, -1.0, 0.0), (3, 2, -1.0, 0.0))
    with _loaded(robots, "pincers", (0.0, 0.05), mimic) as (robot, space):
        # within PhysX's contact offsets closed, apart as the pincer opens: left out; the
        # jaws that meet closed keep colliding
        assert mechanism_pairs(space, [0.0] * 4, robot.sweep()) == [("left1", "right1")]
        # without the coupling, nothing says the jaws stay apart
        loose = JointSpace(space.tree, space.joints, space.limits)
        assert mechanism_pairs(loose, [0.0] * 4, robot.sweep()) == []
