"""``robospec new`` with ManiSkill: the rest keyframe it writes is free of self-contact (searched
with ``robospec check``'s own contact test), a floating robot's keyframe stands it on the ground,
and the robot, registered exactly as scaffolded, stands there for a second on its own drives —
neither sinking nor hovering (gravity compensation is off: lifted, it falls back)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.model.thresholds import MIN_CONTACT_DEPTH
from robospec.pipeline import compile_spec

pytestmark = [
    pytest.mark.minutes,
    pytest.mark.maniskill,  # the scaffold is searched, registered and stood up in ManiSkill
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]

DATA = ROOT / "tests" / "data" / "new"
STANDING = 0.03  # m: how far a standing robot's root may move in a second ("a few cm")
LIFT = 0.1  # m: dropped from this much higher, a robot that does not hover lands again


def scaffold(description: Path, out: Path) -> dict:
    result = run_new(description, out, None, force=False).write()
    assert not result.failed, result.diagnostics
    compiled = compile_spec(out)
    assert [d.format_text() for d in compiled.diagnostics if d.is_error] == []
    return YAML(typ="safe").load(out.read_text())


def root_heights(spec: Path, uid: str, lift: float) -> list[float]:
    """The root's height over one second of holding the rest keyframe with the scaffold's
    ``pd_joint_pos`` mode, started ``lift`` metres above it."""
    import dataclasses

    from robospec import register
    from robospec.physics.sim import Sim

    register(spec)
    compiled = compile_spec(spec)
    assert compiled.robot is not None
    rest = compiled.robot.keyframes[0]
    x, y, z = rest.p
    with Sim(uid, "pd_joint_pos") as sim:
        qpos = sim.start(dataclasses.replace(rest, p=(x, y, z + lift)))
        action = sim.hold_action(qpos)
        assert action is not None
        heights = []
        for _ in range(sim.control_freq):
            sim.step(action)
            heights.append(float(sim.root_position()[0][2]))
        assert np.isfinite(sim.qpos()).all()
    return heights


@pytest.mark.parametrize(
    ("description", "uid"), [("quadruped.urdf", "quad"), ("quadruped.xml", "mjquad")]
)
def test_a_scaffolded_quadruped_stands_on_the_ground_and_does_not_hover(
    tmp_path: Path, description: str, uid: str
) -> None:
    spec = tmp_path / f"{uid}.yaml"
    data = scaffold(DATA / description, spec)
    rest = data["keyframes"]["rest"]
    assert rest["pose"]["p"][2] > 0.2  # measured, not left at 0
    standing = root_heights(spec, uid, 0.0)
    start = standing[0]
    assert max(abs(z - start) for z in standing) < STANDING, standing
    dropped = root_heights(spec, uid, LIFT)
    # it falls back to where it stood: gravity is not cancelled
    assert abs(dropped[-1] - standing[-1]) < STANDING, (dropped[-1], standing[-1])


def test_housings_that_overlap_their_thighs_in_every_pose_are_declared_never_collide(
    tmp_path: Path,
) -> None:
    data = scaffold(DATA / "quadruped.urdf", tmp_path / "quad.yaml")
    overlapping = [[f"leg_{leg}_housing", f"leg_{leg}_thigh"] for leg in "abcd"]
    # and each housing, welded to its hip, lies within PhysX's contact offsets of the body the
    # hip turns on without touching it in any pose of the hip: PhysX leaves out body + hip only
    welded = [["body", f"leg_{leg}_housing"] for leg in "abcd"]
    assert data["never_collide"] == overlapping + welded
    # and the header says why, pair by pair: the search's own reason for each
    from robospec.authoring.new.exemptions import ADJACENT_WHY, OVERLAPPING_WHY

    header = (tmp_path / "quad.yaml").read_text()
    for a, b in overlapping:
        assert f"#   {a} + {b}: {OVERLAPPING_WHY}\n" in header
    for a, b in welded:
        assert f"#   {a} + {b}: {ADJACENT_WHY['welded']}\n" in header
    # the rest pose itself stayed where it started: no contact needed moving it
    assert data["keyframes"]["rest"]["qpos"]["fl"] == [0.0, 0.0, -0.5]


def test_the_rest_pose_search_moves_an_arm_out_of_its_pedestal(tmp_path: Path) -> None:
    import dataclasses

    from robospec import register
    from robospec.physics.sim import Sim

    spec = tmp_path / "arm.yaml"
    data = scaffold(DATA / "folding_arm.urdf", spec)
    shoulder, elbow = data["keyframes"]["rest"]["qpos"]["arm"]
    assert shoulder != pytest.approx(1.8)  # mid-range folds the upper arm into the pedestal
    assert 1.0 <= shoulder <= 2.6 and -1.5 <= elbow <= 1.5
    assert "never_collide" not in data
    # robospec check's contact test at the keyframe as written: nothing touches
    register(spec)
    compiled = compile_spec(spec)
    assert compiled.robot is not None
    with Sim("folding_arm", "pd_joint_pos") as sim:
        for shoulder_at, touching in ((shoulder, False), (1.8, True)):
            rest = compiled.robot.keyframes[0]
            qpos = (shoulder_at, *rest.qpos[1:]) if rest.qpos else None
            sim.start(dataclasses.replace(rest, qpos=qpos))
            sim.hold_drive_targets()
            sim.sim_step()
            deep = [
                pair for pair, depth in sim.self_contacts().items() if depth >= MIN_CONTACT_DEPTH
            ]
            assert bool(deep) is touching


def test_a_pair_touching_at_check_s_threshold_in_every_pose_is_declared_never_collide(
    tmp_path: Path,
) -> None:
    # the depth sits within float noise of min_depth: check may count it where the search did
    # not (TIAGo: 0.99999 mm in the search, 1.00003 mm in check), so the search counts it
    data = scaffold(DATA / "nub_on_box.urdf", tmp_path / "nub.yaml")
    assert data["never_collide"] == [["box", "nub"]]


def test_the_refinement_stiffens_a_fixed_arm_that_sags_where_the_description_mounts_it(
    tmp_path: Path,
) -> None:
    """The refinement holds the keyframe as check does: turned by the MJCF's wrapper body
    (upright at the origin its hinge is vertical and nothing sags), and for a fixed robot too."""
    from robospec import register
    from robospec.physics.sim import Sim

    spec = tmp_path / "tilted.yaml"
    data = scaffold(DATA / "tilted_mount.xml", spec)
    (gains,) = [c for c in data["controllers"].values() if c.get("type") == "pd_joint_pos"]
    assert gains["stiffness"] > 5  # the actuator's kp=5 sags 0.12 rad
    register(spec)
    compiled = compile_spec(spec)
    assert compiled.robot is not None
    with Sim(data["uid"], "pd_joint_pos") as sim:
        start = sim.start(compiled.robot.keyframes[0])
        sim.hold_drive_targets()
        swing = sim.joint_names.index("swing")
        drift = 0.0
        for _ in range(50 * sim.sim_freq // sim.control_freq):  # check's keyframe hold
            sim.sim_step()
            drift = max(drift, abs(float(sim.qpos()[0][swing]) - start[swing]))
    assert drift < 0.05 / 2, drift


def _box(size: str, at: str) -> str:
    return f'<collision><origin xyz="{at}"/><geometry><box size="{size}"/></geometry></collision>'


def _cut_linkage_gripper(path: Path) -> Path:
    """An arm with one side of the xArm gripper's four-bar: a knuckle turns on the hand and
    carries a finger, which turns back as far (staying parallel); an inner knuckle turns
    beside it, its far end pinned to the finger where the URDF, a tree, cannot write the pin.
    Every gripper joint is a mimic of the knuckle's; a box on each end marks the pin."""
    inertial = (
        '<inertial><mass value="0.05"/>'
        '<inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial>'
    )
    shapes = {
        "base": _box("0.1 0.1 0.05", "0 0 0.025"),
        "upper": _box("0.04 0.04 0.3", "0 0 0.15"),
        "hand": _box("0.06 0.03 0.02", "0 0 0.01"),
        "knuckle": _box("0.01 0.005 0.005", "0 0.02 0.02"),
        "finger": _box("0.01 0.008 0.04", "0 0 0.03") + _box("0.008 0.008 0.008", "0 -0.015 0.015"),
        "inner": _box("0.008 0.008 0.008", "0 0.035 0.042"),
    }
    links = "".join(f'<link name="{n}">{inertial}{s}</link>\n' for n, s in shapes.items())

    def joint(name: str, parent: str, child: str, axis: str, at: str, mimic: bool) -> str:
        follow = '<mimic joint="knuckle_joint"/>' if mimic else ""
        return (
            f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{at}"/><axis xyz="{axis}"/>'
            f'<limit lower="0" upper="0.8" effort="10" velocity="2"/>{follow}</joint>\n'
        )

    joints = (
        joint("shoulder", "base", "upper", "0 1 0", "0 0 0.05", False).replace(
            'lower="0" upper="0.8"', 'lower="-1" upper="1"'
        )
        + '<joint name="wrist" type="fixed"><parent link="upper"/><child link="hand"/>'
        '<origin xyz="0 0 0.3"/></joint>\n'
        + joint("knuckle_joint", "hand", "knuckle", "1 0 0", "0 0.03 0.02", False)
        + joint("finger_joint", "knuckle", "finger", "-1 0 0", "0 0.035 0.042", True)
        + joint("inner_joint", "hand", "inner", "1 0 0", "0 0.015 0.035", True)
    )
    path.write_text(f'<?xml version="1.0"?>\n<robot name="cut">\n{links}{joints}</robot>\n')
    return path


def test_a_parallelogram_the_urdf_cuts_open_is_closed_by_a_loop_and_its_tendons_left_out(
    tmp_path: Path,
) -> None:
    """Its <mimic> tags turn the linkage at the parallelogram's own rates, and the loop closes
    it all the same (a mimic controller left each follower's drive to hold its share of a
    grasp alone: the xArm6's fingers let the cube squeeze out)."""
    spec = tmp_path / "cut.yaml"
    data = scaffold(_cut_linkage_gripper(tmp_path / "cut.urdf"), spec)
    # the inner knuckle's end is pinned to the finger where the URDF could not write the pin
    assert data["loops"]["inner"]["links"] == ["inner", "finger"]
    # PhysX's tendons for the <mimic> tags are left out: the loop moves the followers
    assert data["description"]["mend"]["mimic"] == "controller"
    assert sorted(data["groups"]["linkage"]) == ["finger_joint", "inner_joint"]
    assert data["controllers"]["linkage"]["type"] == "passive"
    assert data["groups"]["gripper"] == ["knuckle_joint"]
