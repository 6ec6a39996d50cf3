"""Joint armature (rotor inertia), which a URDF has no element for: the description's (an MJCF
compiled by MuJoCo, robospec.derive.mujoco_urdf) and the spec's ``simulation.armature``, by
joint name, glob or group, each over what comes before it, set by the generated agent through
SAPIEN after loading. (That SAPIEN then turns the joint as MuJoCo does:
tests/test_mujoco_urdf_sim.py's turntable.)"""

from __future__ import annotations

import shutil
from pathlib import Path

from conftest import PANDA_SPEC

from robospec.emit.generate import emit_module
from robospec.pipeline import compile_spec

ARM3 = Path(__file__).parent / "specs" / "reference"


def _panda(tmp_path: Path, armature: str) -> Path:
    text = PANDA_SPEC.read_text(encoding="utf-8")
    assert "\nsimulation:" not in text
    spec = tmp_path / "panda.yaml"
    spec.write_text(text + f"\nsimulation:\n  armature: {armature}\n", encoding="utf-8")
    return spec


def test_a_urdf_robots_armature_comes_from_the_spec_by_glob_and_name(tmp_path: Path) -> None:
    spec = _panda(tmp_path, '{"panda_joint[1-4]": 0.2, panda_joint2: 0.3}')
    result = compile_spec(spec)
    assert result.ok, [d.format_text() for d in result.diagnostics]
    assert result.robot is not None
    assert result.robot.armature == (
        ("panda_joint1", 0.2),
        ("panda_joint2", 0.3),
        ("panda_joint3", 0.2),
        ("panda_joint4", 0.2),
    )
    code = emit_module(result.robot, tmp_path)
    assert "joint.set_armature([armature])" in code
    assert '"panda_joint2": 0.3' in code


def test_a_pattern_that_matches_no_joint_is_rs207_at_its_entry(tmp_path: Path) -> None:
    spec = _panda(tmp_path, '{"elbow*": 0.2}')
    errors = [d for d in compile_spec(spec).diagnostics if d.is_error]
    assert [d.code for d in errors] == ["RS207"]
    assert (
        errors[0].location.line
        == spec.read_text().splitlines().index('  armature: {"elbow*": 0.2}') + 1
    )


def test_the_spec_replaces_the_mjcfs_own_armature_and_zero_takes_it_away(tmp_path: Path) -> None:
    shutil.copy(ARM3 / "arm3.xml", tmp_path / "arm3.xml")
    text = (ARM3 / "arm3.yaml").read_text(encoding="utf-8")
    named = "  mjcf: arm3.xml\n"
    text = text.replace(named, named + "  loader: mujoco\n")
    spec = tmp_path / "arm3.yaml"
    spec.write_text(text, encoding="utf-8")
    robot = compile_spec(spec).robot
    assert robot is not None
    assert robot.armature == (("shoulder_yaw", 0.01), ("elbow", 0.01), ("wrist", 0.01))
    spec.write_text(text + "\nsimulation:\n  armature: {elbow: 0.05, wrist: 0}\n", encoding="utf-8")
    robot = compile_spec(spec).robot
    assert robot is not None
    assert robot.armature == (("shoulder_yaw", 0.01), ("elbow", 0.05))
