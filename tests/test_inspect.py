"""``robospec inspect``: active joints in qpos order with their limits, mimic relations and the
kinematic tree of real URDF, xacro and MJCF files; malformed descriptions get the resolver's
located diagnostics and exit 1, never a traceback (those run the command in a child process;
what it prints runs through the typer app in this one)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from conftest import TWOLINK_XACRO, fast_first, invoke_robospec, maniskill_assets, run_robospec

LIMIT = '<limit lower="-1" upper="1" effort="5" velocity="2"/>'


def robot(path: Path, body: str) -> Path:
    path.write_text(f'<?xml version="1.0"?>\n<robot name="r">\n{body}</robot>\n')
    return path


def inspect_json(path: Path) -> dict:
    result = invoke_robospec("inspect", str(path), "--format", "json")
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_panda_active_joints_come_in_qpos_order_with_limits_velocity_and_effort() -> None:
    report = inspect_json(maniskill_assets() / "robots/panda/panda_v2.urdf")
    joints = report["active_joints"]
    assert [j["name"] for j in joints] == [f"panda_joint{i}" for i in range(1, 8)] + [
        "panda_finger_joint1",
        "panda_finger_joint2",
    ]
    joint4 = joints[3]
    assert (joint4["type"], joint4["lower"], joint4["upper"]) == ("revolute", -3.0718, -0.0698)
    assert (joint4["velocity"], joint4["effort"]) == (2.175, 87.0)
    assert [j["index"] for j in joints] == list(range(9))
    assert report["robot"] == "panda" and report["root_link"] == "panda_link0"


def test_panda_mimic_relation_is_printed_as_follower_mimics_leader_times_multiplier_plus_offset():
    result = invoke_robospec("inspect", str(maniskill_assets() / "robots/panda/panda_v2.urdf"))
    assert result.exit_code == 0, result.output
    assert "panda_finger_joint2 mimics panda_finger_joint1 ×1 + 0" in result.stdout
    row = next(line for line in result.stdout.splitlines() if " panda_joint4 " in line)
    assert row.split() == ["3", "panda_joint4", "revolute", "-3.0718", "-0.0698", "2.175", "87"]


def test_inspire_hand_mimic_multipliers_and_offsets_are_reported() -> None:
    report = inspect_json(
        maniskill_assets() / "robots/inspire_hand/RH56DFX-2LR/urdf/inspire_hand_left.urdf"
    )
    by_name = {j["name"]: j for j in report["active_joints"]}
    mimic = by_name["left_hand_index_PIP_joint"]["mimic"]
    assert mimic["joint"] == "left_hand_index_MCP_joint"
    assert mimic["multiplier"] == pytest.approx(1.06399)
    assert len(report["mimic"]) == sum(j["mimic"] is not None for j in report["active_joints"])


def test_tree_indents_each_link_under_its_parent_with_the_joint_that_attaches_it() -> None:
    path = maniskill_assets() / "robots/panda/panda_v2.urdf"
    report = inspect_json(path)
    depth = {row["link"]: row["depth"] for row in report["tree"]}
    assert depth["panda_link0"] == 0 and depth["panda_link1"] == 1
    assert depth["panda_leftfinger"] == depth["panda_hand"] + 1
    text = invoke_robospec("inspect", str(path)).stdout
    line = next(li for li in text.splitlines() if li.strip().startswith("panda_leftfinger "))
    hand = next(li for li in text.splitlines() if li.strip().startswith("panda_hand "))
    assert line.strip() == "panda_leftfinger  <- panda_finger_joint1 (prismatic)"
    assert len(line) - len(line.lstrip()) == len(hand) - len(hand.lstrip()) + 2
    # every link once; every row but the root names its joint
    assert len(depth) == len(report["tree"])
    assert [row["joint"] is None for row in report["tree"]].count(True) == 1


def test_continuous_joints_are_unbounded_null_in_json_and_infinite_in_text() -> None:
    path = maniskill_assets() / "robots/fetch/fetch.urdf"
    report = inspect_json(path)
    roll = next(j for j in report["active_joints"] if j["name"] == "upperarm_roll_joint")
    assert (roll["type"], roll["lower"], roll["upper"]) == ("continuous", None, None)
    row = next(
        li
        for li in invoke_robospec("inspect", str(path)).stdout.splitlines()
        if "upperarm_roll" in li
    )
    assert row.split()[3:5] == ["-inf", "inf"]


def test_xacro_files_are_expanded_before_inspection() -> None:
    report = inspect_json(TWOLINK_XACRO)
    assert report["kind"] == "xacro" and report["robot"] == "twolink"
    assert [j["name"] for j in report["active_joints"]] == [
        "twolink_joint1",
        "twolink_joint2",
        "twolink_joint3",
        "twolink_finger_joint1",
        "twolink_finger_joint2",
    ]
    assert report["mimic"] == []


def test_mjcf_files_are_inspected() -> None:
    report = inspect_json(maniskill_assets() / "robots/humanoid/humanoid.xml")
    assert report["kind"] == "mjcf" and report["floating_root"] is True
    assert "right_knee" in [j["name"] for j in report["active_joints"]]


TWO_HINGE_BODY = """<mujoco model="wrist">
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.1" mass="2"/>
      <body name="hand" pos="0 0 0.2">
        <joint name="pitch" axis="0 1 0" range="-1 1" limited="true"/>
        <joint name="roll" axis="1 0 0" range="-1 1" limited="true"/>
        <geom type="sphere" size="0.05" mass="0.5"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_an_mjcf_is_inspected_as_the_spec_new_writes_reads_it_compiled_by_mujoco(
    tmp_path: Path,
) -> None:
    # new writes `loader: mujoco` for every MJCF MuJoCo compiles: inspect shows that robot
    # (links named as the file names its bodies) unless asked for ManiSkill's own reading
    path = tmp_path / "wrist.xml"
    path.write_text(TWO_HINGE_BODY)
    compiled = inspect_json(path)
    assert compiled["loader"] == "mujoco"
    assert [j["name"] for j in compiled["active_joints"]] == ["pitch", "roll"]
    assert compiled["active_joints"][0]["effort"] is None  # no rating in the file's joints
    assert compiled["tree"][-1]["link"] == "hand"
    result = invoke_robospec("inspect", str(path), "--format", "json", "--loader", "maniskill")
    assert result.exit_code == 0, result.output
    maniskill = json.loads(result.stdout)
    assert maniskill["loader"] == "maniskill"
    assert [row["link"] for row in maniskill["tree"]] != [row["link"] for row in compiled["tree"]]
    assert "(mjcf, loader: mujoco)" in invoke_robospec("inspect", str(path)).stdout


def test_inspect_loader_mujoco_on_a_file_mujoco_refuses_says_why_at_the_element(
    tmp_path: Path,
) -> None:
    path = tmp_path / "bad.xml"
    path.write_text(
        '<mujoco>\n<worldbody><body name="b">\n<joint type="bogus"/>\n'
        "</body></worldbody></mujoco>\n"
    )
    result = invoke_robospec("inspect", str(path), "--loader", "mujoco")
    assert result.exit_code == 1
    assert f"{path}:3:1: error[RS790]" in result.output


def test_a_file_is_named_as_given_and_a_xacros_problem_as_its_expansion(tmp_path: Path) -> None:
    # read as validate reads a spec's description: a ManiSkill folder by its placeholder, a
    # problem found in a xacro's expansion at the expansion's line, named so
    from robospec.authoring.description_file import read_description_file

    missing = Path("{maniskill_assets}/robots/nowhere.urdf")
    _, (problem,) = read_description_file(missing)
    assert (problem.code, problem.location.file) == ("RS050", str(missing))
    path = tmp_path / "bad.urdf.xacro"
    robot(path, f'<link name="a"/>\n<link name="b"/>\n<joint name="j" type="revolute">'
          f'<parent link="nowhere"/><child link="b"/>{LIMIT}</joint>\n')  # fmt: skip
    _, found = read_description_file(path)
    assert [(d.code, d.location.file) for d in found] == [("RS052", f"{path} (expanded)")]


MALFORMED = {
    "bad_xml": ('<link name="a">\n', "RS051", 4),
    "unknown_parent": (
        f'<link name="a"/>\n<link name="b"/>\n<joint name="j" type="revolute">'
        f'<parent link="nowhere"/><child link="b"/>{LIMIT}</joint>\n',
        "RS052",
        5,
    ),
    "cycle": (
        f'<link name="a"/>\n<link name="b"/>\n'
        f'<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>{LIMIT}</joint>\n'
        f'<joint name="j2" type="revolute"><parent link="b"/><child link="a"/>{LIMIT}</joint>\n',
        "RS052",
        None,
    ),
    "duplicate_link": ('<link name="a"/>\n<link name="a"/>\n', "RS052", 4),
    "unknown_mimic_target": (
        f'<link name="a"/>\n<link name="b"/>\n<joint name="j" type="prismatic"><parent link="a"/>'
        f'<child link="b"/>{LIMIT}\n<mimic joint="j9"/></joint>\n',
        "RS052",
        6,
    ),
}
# errors that leave the kinematic tree intact: inspect shows the robot beside them
TREE_INTACT = {"unknown_mimic_target"}


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
@pytest.mark.parametrize("case", fast_first(sorted(MALFORMED)))
def test_malformed_description_gets_located_diagnostics_and_exit_1(
    tmp_path: Path, case: str
) -> None:
    body, code, line = MALFORMED[case]
    path = robot(tmp_path / f"{case}.urdf", body)
    for format in ("text", "json"):
        result = run_robospec("inspect", str(path), "--format", format)
        assert result.returncode == 1
        assert "Traceback" not in result.stderr
        assert (result.stdout != "") == (case in TREE_INTACT), result.stdout
    text = run_robospec("inspect", str(path)).stderr
    match = re.search(rf"{re.escape(str(path))}:(\d+):(\d+): error\[{code}\]", text)
    assert match, text
    if line is not None:
        assert int(match.group(1)) == line


def test_unknown_file_type_is_rs600(tmp_path: Path) -> None:
    path = tmp_path / "robot.sdf"
    path.write_text("<sdf/>")
    result = run_robospec("inspect", str(path))
    assert result.returncode == 1
    assert f"{path}:1:1: error[RS600]" in result.stderr


def test_missing_file_is_rs050(tmp_path: Path) -> None:
    result = run_robospec("inspect", str(tmp_path / "missing.urdf"))
    assert result.returncode == 1
    assert "error[RS050]" in result.stderr and "Traceback" not in result.stderr
