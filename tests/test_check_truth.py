"""``robospec check`` fails only for what the simulation confirms, and says where: a joint no
drive holds (passive) is never counted as keyframe drift; a keyframe that puts the robot inside
the ground is RS521 at its pose, and the holds from there say so; ManiSkill's own Allegro touch
hand, as users load it, fails with that reason (tests/test_check_zoo.py holds the whole zoo to
it, ManiSkill's agents included)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import SPECS, TWOLINK_XACRO

from robospec.physics.batch import RobotReport, check_paths
from robospec.physics.findings import Status

pytestmark = [pytest.mark.maniskill, pytest.mark.minutes]

SPEC = """\
robospec: 1
uid: {uid}
description:
  xacro: "{xacro}"
  args: {{prefix: "twolink_", link_length: 0.35}}
groups:
  column: [twolink_joint1, twolink_joint2]
  elbow: [twolink_joint3]
  gripper: "twolink_finger_joint*"
keyframes:
  rest: {{qpos: {{column: [0, 0.5], elbow: 1.0, gripper: 0.02}}, pose: {{p: [0, 0, {z}]}}}}
controllers:
  column_pos: {{type: pd_joint_pos, joints: column, lower: null, upper: null, stiffness: 2000,
               damping: 200, force_limit: 200, normalize_action: false}}
  elbow_free: {{type: passive, joints: elbow, damping: 0.0}}
  fingers: {{type: pd_joint_pos, joints: gripper, lower: null, upper: null, stiffness: 500,
            damping: 50, force_limit: 50, normalize_action: false}}
control_modes:
  hold: {{column: column_pos, elbow: elbow_free, gripper: fingers,
         balance_passive_force: false}}
checks:
  keyframe_hold: {{mode: hold}}
"""


def _check(tmp_path: Path, uid: str, z: float, monkeypatch: pytest.MonkeyPatch) -> RobotReport:
    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = tmp_path / f"{uid}.yaml"
    spec.write_text(SPEC.format(uid=uid, xacro=TWOLINK_XACRO, z=z))
    (report,), extra = check_paths([spec], isolate=False)
    assert extra == [] and not [d for d in report.diagnostics if d.is_error]
    return report


def test_a_passive_joint_falling_under_gravity_is_no_keyframe_drift(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    report = _check(tmp_path, "passive_elbow", 0.0, monkeypatch)
    (hold,) = [f for f in report.findings if f.check == "keyframe_hold"]
    # gravity is on and nothing drives the elbow: it swings down; the drives hold the rest
    assert hold.status is Status.PASS, hold.summary
    assert hold.metrics["joint"] != "twolink_joint3"
    assert hold.metrics["max_joint_drift"] < 0.05


def test_a_keyframe_inside_the_ground_is_rs521_at_its_pose(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    report = _check(tmp_path, "sunk", -0.3, monkeypatch)
    (ground,) = [f for f in report.findings if f.check == "ground" and f.subject == "rest"]
    assert ground.status is Status.FAIL
    (diagnostic,) = ground.diagnostics
    assert diagnostic.code == "RS521" and diagnostic.is_error
    assert diagnostic.location.line == 11  # keyframes.rest's pose
    assert "below the ground of ManiSkill's scenes" in diagnostic.message
    assert "pose: {p: [0, 0, " in (diagnostic.hint or "")
    # what else fails from that start says why
    notes = [d for f in report.findings if f.check == "keyframe_hold" for d in f.diagnostics]
    assert notes and all("inside the ground (RS521)" in d.message for d in notes)


def test_maniskills_allegro_touch_hand_fails_where_users_load_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
    spec = SPECS / "maniskill" / "allegro_hand_right_touch.yaml"
    (report,), _ = check_paths([spec], isolate=False)
    assert report.failed
    (ground,) = [f for f in report.findings if f.check == "ground"]
    (diagnostic,) = ground.diagnostics
    # no keyframe: the load is its only start, at the origin, its fingers in the ground
    assert diagnostic.code == "RS521" and diagnostic.is_error
    assert diagnostic.location.line == 11  # its uid
    assert "link_15.0_tip" in diagnostic.message
    blown = [f for f in report.findings if f.check == "random_actions" and f.mode == "pd_joint_pos"]
    assert blown and blown[0].metrics["max_limit_excess"] > 100  # thousands of radians
