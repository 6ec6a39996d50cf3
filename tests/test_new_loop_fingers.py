"""A linkage gripper's fingers as ``robospec new`` picks them: of each loop's finger chain, the
last link with collision shapes (the grasp check closes them on the cube: ``robospec solve``
refuses a shapeless finger, RS682), while the tcp stays the midpoint of the chains' ends
(fingertip frames). tests/data/new/fourbar_gripper.xml states its gripper as gym-xarm's xArm
gripper does: fingertip frames without geoms welded below the fingers."""

from __future__ import annotations

from pathlib import Path

from conftest import ROOT
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new

GRIPPER = ROOT / "tests" / "data" / "new" / "fourbar_gripper.xml"


def test_a_loop_finger_is_its_chains_last_link_with_collision_shapes(tmp_path: Path) -> None:
    out = tmp_path / "gripper.yaml"
    result = run_new(GRIPPER, out, None, force=False, simulate=False).write()
    assert not result.failed, result.diagnostics
    data = YAML(typ="safe").load(out.read_text())
    assert set(data["loops"]) == {"inner_l", "inner_r"}
    fingers = {f["link"] for f in data["grasping"]["is_grasping"]["fingers"]}
    assert fingers == {"finger_l", "finger_r"}  # not tip_l, tip_r: they have no geoms
    assert set(data["tcp"]["midpoint"]) == {"tip_l", "tip_r"}


def test_a_welded_pad_with_shapes_is_still_the_finger(tmp_path: Path) -> None:
    # a fingertip with a geom of its own is what closes on the cube (robosuite's Robotiq pads)
    text = GRIPPER.read_text()
    for side in ("l", "r"):
        text = text.replace(
            f'<site name="tip_{side}_site" size="0.002"/>',
            f'<site name="tip_{side}_site" size="0.002"/><geom size="0.004 0.01 0.004"/>',
        )
    description = tmp_path / "gripper.xml"
    description.write_text(text)
    out = tmp_path / "gripper.yaml"
    result = run_new(description, out, None, force=False, simulate=False).write()
    assert not result.failed, result.diagnostics
    data = YAML(typ="safe").load(out.read_text())
    fingers = {f["link"] for f in data["grasping"]["is_grasping"]["fingers"]}
    assert fingers == {"tip_l", "tip_r"}
    assert set(data["tcp"]["midpoint"]) == {"tip_l", "tip_r"}
