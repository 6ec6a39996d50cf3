"""Resolve binds names and reports the ones that bind to nothing; the checks judge what bound.
So independent mistakes are all reported in one run, and one mistake is reported once — not
again by every check that reads the names it broke."""

from __future__ import annotations

import shutil
from pathlib import Path

from robospec.pipeline import compile_spec

# tests/data/tree.urdf: active joints j_head, j_arm1, j_arm2, j_lift, j_finger_l, j_finger_r
# (j_cam and j_tool are fixed)
TREE = Path(__file__).parent / "data" / "tree.urdf"
SPEC = """\
robospec: 1
uid: rs_binding_tree
description: {urdf: tree.urdf}
groups:
  arm: [j_arm1, j_arm2,
        j_lift]
  gripper: [j_finger_l, j_finger_r]
keyframes:
  rest: {qpos: {arm: [0, 0, 0.1], gripper: 0, j_head: 0}}
controllers:
  arm: {type: pd_joint_pos, joints: [j_head, arm], lower: null, upper: null, stiffness: 1e3,
        damping: 1e2}
  gripper: {type: pd_joint_pos, joints: gripper, lower: null, upper: null, stiffness: 1e3,
            damping: 1e2}
control_modes:
  pd_joint_pos: {arm: arm, gripper: gripper}
"""


def _codes(tmp_path: Path, text: str) -> list[tuple[str, int]]:
    shutil.copy(TREE, tmp_path / "tree.urdf")
    spec = tmp_path / "spec.yaml"
    spec.write_text(text, encoding="utf-8")
    result = compile_spec(spec)
    return [(d.code, d.location.line) for d in result.diagnostics if d.is_error]


def test_the_spec_these_tests_change_compiles_clean(tmp_path: Path) -> None:
    assert _codes(tmp_path, SPEC) == []


def test_a_misspelled_joint_in_a_group_is_one_error_not_one_per_user_of_the_group(
    tmp_path: Path,
) -> None:
    text = SPEC.replace("        j_lift]", "        j_liftt]")
    # the keyframe and the controller use the group: neither reports its joints as missing
    assert _codes(tmp_path, text) == [("RS201", 6)]


def test_a_keyframe_group_one_value_short_is_one_error(tmp_path: Path) -> None:
    text = SPEC.replace("[0, 0, 0.1]", "[0, 0]")
    assert _codes(tmp_path, text) == [("RS303", 9)]


def test_a_misspelled_passive_joint_is_an_unknown_joint_not_an_undriven_one(
    tmp_path: Path,
) -> None:
    text = SPEC.replace(
        "  pd_joint_pos: {arm: arm, gripper: gripper}\n", "  pd_joint_pos: {arm: arm}\n"
    )
    text += "passive_joints: grippr\n"
    assert _codes(tmp_path, text) == [("RS201", 17)]


def test_binding_checks_report_alongside_unknown_names(tmp_path: Path) -> None:
    text = SPEC.replace("joints: [j_head, arm]", "joints: [j_head, arm, j_cam]")
    text += "cameras:\n  cam: {mount: cameraa, width: 8, height: 8}\n"
    # RS202 (an unknown mount) from resolve; RS311 (a fixed joint) and RS314 (no fov or
    # intrinsic) from the checks, in the same run
    assert sorted(_codes(tmp_path, text)) == [("RS202", 18), ("RS311", 11), ("RS314", 18)]


def test_whole_robot_checks_wait_for_a_robot_without_errors(tmp_path: Path) -> None:
    # the gripper is left undriven (RS302) and a camera is incomplete (RS314): the mode
    # coverage check runs once the binding error is mended, not before
    text = SPEC.replace(
        "  pd_joint_pos: {arm: arm, gripper: gripper}\n", "  pd_joint_pos: {arm: arm}\n"
    )
    broken = text + "cameras:\n  cam: {mount: camera, width: 8, height: 8}\n"
    assert _codes(tmp_path, broken) == [("RS314", 18)]
    mended = text + "cameras:\n  cam: {mount: camera, width: 8, height: 8, fov: 1}\n"
    assert _codes(tmp_path, mended) == [("RS302", 16)]


def test_a_keyframe_qvel_one_value_short_is_reported_like_qpos(tmp_path: Path) -> None:
    text = SPEC.replace(
        "  rest: {qpos: {arm: [0, 0, 0.1], gripper: 0, j_head: 0}}",
        "  rest: {qpos: {arm: [0, 0, 0.1], gripper: 0, j_head: 0},\n"
        "         qvel: [0, 0, 0, 0, 0]}",
    )
    assert _codes(tmp_path, text) == [("RS303", 10)]


def test_a_mistake_in_a_controller_others_extend_is_reported_once_where_it_was_written(
    tmp_path: Path,
) -> None:
    text = SPEC.replace(
        "  gripper: {type: pd_joint_pos, joints: gripper,",
        "  arm_delta: {extends: arm, lower: -0.1, upper: 0.1, use_delta: true}\n"
        "  arm_target: {extends: arm_delta, use_target: true}\n"
        "  gripper: {type: pd_joint_pos, joints: gripper,",
    ).replace("joints: [j_head, arm]", "joints: [j_headd, arm]")
    # three controllers carry the misspelled joint; it is written once
    assert _codes(tmp_path, text) == [("RS201", 11)]


def test_values_by_joint_are_not_blamed_for_a_joint_the_controller_failed_to_name(
    tmp_path: Path,
) -> None:
    text = SPEC.replace("joints: [j_head, arm]", "joints: [j_headd, arm]").replace(
        "stiffness: 1e3,\n        damping: 1e2}",
        "stiffness: {j_head: 1, arm: 1e3},\n        damping: 1e2}",
    )
    # j_head is not among the joints the controller names only because j_headd did not bind
    assert _codes(tmp_path, text) == [("RS201", 11)]
