"""``robospec new`` on robots nobody here wrote (the corpus of tests/corpus.py; needs the
``corpus`` extra: ``pip install -e '.[corpus]'``, which scripts/setup installs): quadrupeds get
their legs by side and stand, a humanoid MJCF floats, a car drives its base, and a robot
ManiSkill cannot load still gets its scaffold, with a warning that says why it went unchecked.

tests/test_corpus.py takes every corpus robot through the whole journey; these pin what the
scaffold itself must say about a few of them.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from corpus import BY_KEY, HUMANOID, URDF, CorpusMissing, Robot, locate
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.diagnostics import Diagnostic
from robospec.pipeline import compile_spec

# new searches each rest pose in ManiSkill
pytestmark = [pytest.mark.maniskill, pytest.mark.minutes]


# TALOS as example-robot-data reduces it: robospec reads it, but ManiSkill cannot load it
# (its mimic joints make a PhysX tendon through joints that are not all revolute or prismatic)
TALOS_REDUCED = Robot(
    "erd_talos_reduced",
    "PAL TALOS (reduced)",
    "example-robot-data",
    "cmeel.prefix/share/example-robot-data/robots/talos_data/robots/talos_reduced.urdf",
    HUMANOID,
    URDF,
)


def scaffold(key: str | Robot, out: Path) -> tuple[dict, list[Diagnostic]]:
    try:
        description = locate(BY_KEY[key] if isinstance(key, str) else key)
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    result = run_new(description, out, None, force=False).write()
    assert not result.failed, result.diagnostics
    compiled = compile_spec(out)
    assert [d.format_text() for d in compiled.diagnostics if d.is_error] == []
    return YAML(typ="safe").load(out.read_text()), list(result.diagnostics)


@pytest.mark.parametrize(
    ("key", "legs"),
    [("pb_a1", ["fr", "fl", "rr", "rl"]), ("erd_go2", ["fl", "fr", "rl", "rr"])],
)
def test_quadrupeds_float_with_legs_by_side_standing_free_of_self_contact(
    tmp_path: Path, key: str, legs: list[str]
) -> None:
    data, diagnostics = scaffold(key, tmp_path / f"{key}.yaml")
    # no contact left that the scaffold could not explain, and ManiSkill loaded it
    assert [d for d in diagnostics if d.code in ("RS605", "RS606")] == []
    assert data["loader"] == {"fix_root_link": False}
    assert list(data["groups"]) == legs
    assert all(mode["balance_passive_force"] is False for mode in data["control_modes"].values())
    assert data["keyframes"]["rest"]["pose"]["p"][2] > 0.15


def test_a_humanoid_mjcf_floats_on_its_legs(tmp_path: Path) -> None:
    data, _ = scaffold("dmc_humanoid", tmp_path / "humanoid.yaml")
    assert data["loader"] == {"fix_root_link": False}
    assert {"left_leg", "right_leg"} <= set(data["groups"])
    assert data["keyframes"]["rest"]["pose"]["p"][2] > 1.0  # the torso stands above the feet


def test_a_car_drives_its_base_and_steers_its_hinges(tmp_path: Path) -> None:
    data, _ = scaffold("pb_racecar", tmp_path / "racecar.yaml")
    assert "loader" not in data  # a planar base from a fixed root
    assert data["mobile_base"]["wheel_joints"] == "fixed"  # the wheels welded, off the floor
    assert "wheels" not in data["groups"]
    assert data["groups"]["steering_hinge"] == [
        "left_steering_hinge_joint",
        "right_steering_hinge_joint",
    ]


def test_a_robot_maniskill_cannot_load_is_scaffolded_unchecked_with_a_warning(
    tmp_path: Path,
) -> None:
    out = tmp_path / "talos.yaml"
    data, diagnostics = scaffold(TALOS_REDUCED, out)
    (warning,) = [d for d in diagnostics if d.code == "RS606"]
    assert warning.code == "RS606" and not warning.is_error
    assert warning.location.file.endswith("talos_reduced.urdf")
    assert "the rest keyframe was not checked" in warning.message
    assert "not contact-checked" in out.read_text()
    assert data["loader"] == {"fix_root_link": False}  # two legs
