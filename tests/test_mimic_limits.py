"""RS545: a mimic joint whose <mimic> holds it outside its own <limit> over the whole range of the
joint it mimics (example-robot-data's PR2: each gripper's r_parallel_root_joint mimics the finger
with multiplier -1 yet is limited to [0, 0.548]) is a defect of the description, named at the
joint in the description — no gains or keyframe make it follow. Found from the compiled spec
alone: no simulation."""

from __future__ import annotations

from pathlib import Path

import pytest

from robospec.pipeline import compile_spec

GRIPPER = """<?xml version="1.0"?>
<robot name="jaw">
  <link name="palm">
    <inertial><mass value="0.5"/>
      <inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial>
    <collision><geometry><box size="0.1 0.04 0.02"/></geometry></collision>
  </link>
  <link name="left"><inertial><mass value="0.05"/>
    <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial></link>
  <link name="right"><inertial><mass value="0.05"/>
    <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial></link>
  <joint name="left_joint" type="prismatic">
    <parent link="palm"/><child link="left"/><origin xyz="0 0.01 0.02"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="20" velocity="0.1"/>
  </joint>
  <joint name="right_joint" type="prismatic">
    <parent link="palm"/><child link="right"/><origin xyz="0 -0.01 0.02"/><axis xyz="0 -1 0"/>
    <limit lower="LOWER" upper="UPPER" effort="20" velocity="0.1"/>
    <mimic joint="left_joint" multiplier="MULTIPLIER" offset="0"/>
  </joint>
</robot>
"""
SPEC = """robospec: 1
uid: UID
description: {urdf: jaw.urdf}
keyframes:
  rest: {qpos: {left_joint: 0.0, right_joint: 0.0}}
controllers:
  jaw: {type: pd_joint_pos_mimic, joints: [left_joint, right_joint], lower: 0, upper: 0.04,
        stiffness: 100, damping: 10, force_limit: 20, normalize_action: false,
        mimic: {right_joint: {joint: left_joint, multiplier: MULTIPLIER}}}
control_modes:
  pd_joint_pos: {jaw: jaw}
"""


def _findings(tmp_path: Path, multiplier: str, lower: str, upper: str) -> list:
    from robospec.physics import mimic_limits
    from robospec.physics.batch import _settings
    from robospec.physics.check_run import CheckRun
    from robospec.physics.results import DEFAULT_OPTIONS

    urdf = GRIPPER.replace("MULTIPLIER", multiplier).replace("LOWER", lower)
    (tmp_path / "jaw.urdf").write_text(urdf.replace("UPPER", upper), encoding="utf-8")
    spec = tmp_path / "jaw.yaml"
    uid = f"jaw_{multiplier}_{lower}".replace("-", "m").replace(".", "_")
    text = SPEC.replace("MULTIPLIER", multiplier).replace("UID", uid)
    spec.write_text(text, encoding="utf-8")
    compiled = compile_spec(spec)
    assert compiled.ok and compiled.context is not None, compiled.diagnostics
    run = CheckRun(uid, compiled.context, _settings(compiled, DEFAULT_OPTIONS))
    return mimic_limits.check(run)


def test_a_mimic_that_holds_its_joint_past_its_limits_is_rs545_at_the_joint(
    tmp_path: Path,
) -> None:
    (finding,) = _findings(tmp_path, "-1", "0", "0.04")
    assert finding.subject == "right_joint" and finding.status.name == "FAIL"
    (diagnostic,) = finding.diagnostics
    assert diagnostic.code == "RS545"
    # at the joint's line in the description, naming both sides of the disagreement
    assert Path(diagnostic.location.file).name == "jaw.urdf"
    line = (tmp_path / "jaw.urdf").read_text().splitlines()[diagnostic.location.line - 1]
    assert '<joint name="right_joint"' in line
    assert "'right_joint' mimics 'left_joint' (multiplier -1, offset 0)" in diagnostic.message
    assert "holds it in [-0.04, 0], outside its own limits [0, 0.04]" in diagnostic.message
    assert "<mimic> and <limit>" in (diagnostic.hint or "")


@pytest.mark.parametrize(
    ("multiplier", "lower", "upper"),
    [("1", "0", "0.04"), ("-1", "-0.04", "0"), ("-1", "-0.02", "0.04")],
)
def test_a_mimic_its_limits_let_follow_is_no_finding(
    tmp_path: Path, multiplier: str, lower: str, upper: str
) -> None:
    # the relation agrees with the limits, or with part of them: the joint can follow
    assert _findings(tmp_path, multiplier, lower, upper) == []
