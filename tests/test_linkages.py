"""How ``robospec new`` finds a parallelogram linkage its description cut into a tree (no
simulation): the missing pin where the follower's pivot, moved by the crank's bar, lies inside
both the follower's and the coupler's collision boxes; the followers' rules from the shape
(the follower turns as the crank does, the coupler back); the loop where the description
already couples the joints alike (a ``<mimic>`` family with those rates: the xArm6's and TALOS's
grippers, whose followers' drives each held their share of a grasp alone) as where it couples
them otherwise (robosuite's 2F-140's tendons)."""

from __future__ import annotations

from pathlib import Path

import pytest

from robospec.authoring.description_file import read_description_file
from robospec.authoring.new.analysis import analyse

URDF = """\
<robot name="parallelogram">
  <link name="base">
    <collision><origin xyz="0.01 0 -0.01"/><geometry><box size="0.05 0.02 0.01"/></geometry>
    </collision>
  </link>
  <link name="crank">
    <collision><origin xyz="0 0 0.025"/><geometry><box size="0.01 0.01 0.06"/></geometry>
    </collision>
  </link>
  <link name="coupler">
    <collision><origin xyz="0.015 0 0"/><geometry><box size="0.04 0.01 0.01"/></geometry>
    </collision>
  </link>
  <link name="follower">
    <collision><origin xyz="0 0 0.025"/><geometry><box size="0.01 0.01 0.06"/></geometry>
    </collision>
  </link>
  <joint name="crank_joint" type="revolute">
    <parent link="base"/><child link="crank"/><axis xyz="0 1 0"/>
    <limit lower="-0.5" upper="0.5" effort="10" velocity="1"/>
  </joint>
  <joint name="coupler_joint" type="revolute">
    <parent link="crank"/><child link="coupler"/><origin xyz="0 0 0.05"/><axis xyz="0 1 0"/>
    <limit lower="-0.5" upper="0.5" effort="10" velocity="1"/>COUPLER_MIMIC
  </joint>
  <joint name="follower_joint" type="revolute">
    <parent link="base"/><child link="follower"/><origin xyz="0.02 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-0.5" upper="0.5" effort="10" velocity="1"/>FOLLOWER_MIMIC
  </joint>
</robot>
"""


def _loops(tmp_path: Path, coupler: str = "", follower: str = ""):
    path = tmp_path / "parallelogram.urdf"
    text = URDF.replace("COUPLER_MIMIC", coupler).replace("FOLLOWER_MIMIC", follower)
    path.write_text(text, encoding="utf-8")
    source, diagnostics = read_description_file(path)
    assert source is not None, [d.format_text() for d in diagnostics]
    return analyse(source)


def test_a_parallelogram_cut_into_a_tree_is_closed_at_its_missing_pin(tmp_path: Path) -> None:
    analysis = _loops(tmp_path)
    (loop,) = analysis.loops
    assert loop.links == ("follower", "coupler")
    # the follower's pivot moved by the crank's bar, (0.02, 0, 0.05), in each link's frame
    assert loop.at[0] == pytest.approx((0.0, 0.0, 0.05))
    assert loop.at[1] == pytest.approx((0.02, 0.0, 0.0))
    assert loop.driver == "crank_joint"  # nothing actuated: the top joint of the longer branch
    # the follower turns as the crank does (about its own axis, written the other way), the
    # coupler back by as much
    assert dict((j, m) for j, m, _ in loop.follows) == {
        "follower_joint": -1.0,
        "coupler_joint": -1.0,
    }
    assert {(m.follower, m.leader, m.multiplier) for m in analysis.linkage_mimic} == {
        ("follower_joint", "crank_joint", -1.0),
        ("coupler_joint", "crank_joint", -1.0),
    }
    assert analysis.groups.groups["linkage"] == ["coupler_joint", "follower_joint"]


def test_a_parallelogram_its_mimic_tags_already_move_alike_is_closed_too(tmp_path: Path) -> None:
    mimic = '\n    <mimic joint="crank_joint" multiplier="-1"/>'
    analysis = _loops(tmp_path, coupler=mimic, follower=mimic)
    (loop,) = analysis.loops
    assert loop.links == ("follower", "coupler")
    # the loop stands in for the <mimic> tags: its followers are passive, the crank drives
    assert sorted(analysis.groups.groups["linkage"]) == ["coupler_joint", "follower_joint"]


def test_a_parallelogram_coupled_at_other_rates_is_closed_with_the_shapes_rules(
    tmp_path: Path,
) -> None:
    analysis = _loops(
        tmp_path,
        coupler='\n    <mimic joint="crank_joint" multiplier="-0.5"/>',
        follower='\n    <mimic joint="crank_joint" multiplier="-1"/>',
    )
    (loop,) = analysis.loops
    assert dict((j, m) for j, m, _ in loop.follows)["coupler_joint"] == -1.0


def test_links_that_do_not_overlap_at_the_missing_pin_are_no_loop(tmp_path: Path) -> None:
    # the follower a stub that ends well short of where the pin would be
    path_text = URDF.replace(
        '<link name="follower">\n    <collision><origin xyz="0 0 0.025"/><geometry><box '
        'size="0.01 0.01 0.06"/>',
        '<link name="follower">\n    <collision><origin xyz="0 0 0.01"/><geometry><box '
        'size="0.01 0.01 0.02"/>',
    )
    assert path_text != URDF
    path = tmp_path / "stub.urdf"
    path.write_text(path_text.replace("COUPLER_MIMIC", "").replace("FOLLOWER_MIMIC", ""))
    source, _ = read_description_file(path)
    assert source is not None
    assert analyse(source).loops == ()
