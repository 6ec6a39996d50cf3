"""robospec's MJCF reports on descriptions nobody here wrote, each confirmed with ManiSkill.

Needs the ``corpus`` extra (``pip install -e '.[corpus]'``: dm-control, gymnasium-robotics),
whose files are found through the distributions that install them, and ManiSkill.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mjcf_scene import parse, scene_fixture  # noqa: F401  (the scene fixture)

from robospec.description import load_description
from robospec.diagnostics import Diagnostic

pytestmark = pytest.mark.maniskill

INSTALL_CORPUS = "the corpus extra is not installed: pip install -e '.[corpus]'"


def corpus_file(dist: str, path: str) -> Path:
    try:
        folder = Path(str(distribution(dist).locate_file("")))
    except PackageNotFoundError:
        pytest.fail(f"{INSTALL_CORPUS} ({dist})")
    found = folder / path
    if not found.is_file():
        pytest.fail(f"{dist} ships no {path}")
    return found


def dm_control(path: str) -> Path:
    return corpus_file("dm-control", f"dm_control/{path}")


def gymnasium_robotics(path: str) -> Path:
    return corpus_file("gymnasium-robotics", f"gymnasium_robotics/envs/assets/{path}")


def reported(path: Path, code: str, severity: str | None = None) -> Diagnostic:
    found = [
        d
        for d in load_description(str(path), "mjcf")[1]
        if d.code == code and severity in (None, d.severity.value)
    ]
    assert found, f"{path.name}: no {code}"
    return found[0]


def test_walker_floor_zaxis_fails_the_load(scene: Any) -> None:
    walker = dm_control("suite/walker.xml")
    error = reported(walker, "RS080")
    assert error.is_error and 'quat="1 0 0 0"' in (error.hint or "")
    with pytest.raises(np.linalg.LinAlgError):
        parse(scene, walker)


def test_quadruped_terrain_height_field_fails_the_load(scene: Any) -> None:
    quadruped = dm_control("suite/quadruped.xml")
    assert reported(quadruped, "RS079").is_error
    with pytest.raises(NotImplementedError):
        parse(scene, quadruped)


def test_dog_has_too_many_bodies_for_the_collision_bits(scene: Any) -> None:
    import sapien

    dog = dm_control("suite/dog.xml")
    assert "the robot has 61 bodies" in reported(dog, "RS081").message
    builder = parse(scene, dog)
    builder.initial_pose = sapien.Pose([5.0, 5.0, 1.0])
    with pytest.raises(TypeError, match="set_collision_groups"):
        builder.build()


def test_cheetah_head_is_turned_the_other_way(scene: Any) -> None:
    cheetah = dm_control("suite/cheetah.xml")
    assert "head" in reported(cheetah, "RS080").message
    import sapien

    builder = parse(scene, cheetah)
    builder.initial_pose = sapien.Pose([8.0, 8.0, 1.0])
    torso = {link.name: link for link in builder.build().links}["torso"]
    head = torso._objs[0].collision_shapes[1]  # <geom name="head" euler="0 50 0">
    # MuJoCo tilts the capsule's axis to (sin 50, 0, cos 50); SAPIEN's capsule lies along x
    q = head.local_pose.q
    from robospec.geometry import rotate

    axis = rotate(tuple(q), (1.0, 0.0, 0.0))
    meant = (np.sin(np.radians(50)), 0.0, np.cos(np.radians(50)))
    assert abs(float(np.dot(axis, meant))) < 0.5


def test_adroit_hand_included_in_its_forearm_is_not_loaded_and_the_pen_is(scene: Any) -> None:
    adroit = gymnasium_robotics("adroit_hand/adroit_pen.xml")
    error = reported(adroit, "RS082")
    assert "the robot ManiSkill loads is body 'Object'" in error.message
    builder = parse(scene, adroit)
    names = [link.name for link in builder.link_builders]
    assert names[1:3] == ["Object_dummy_0", "Object_dummy_1"]
    assert not any("FF" in name or "forearm" in name for name in names)


def test_shadow_hand_included_in_the_worldbody_leaves_no_robot() -> None:
    reach = gymnasium_robotics("hand/reach.xml")
    error = reported(reach, "RS082", "error")
    assert "no body with a joint is left" in error.message


def test_manipulator_finger_coupling_hint_is_the_mimic_map() -> None:
    manipulator = dm_control("suite/manipulator.xml")
    assert "mimic: {finger: thumb}" in (reported(manipulator, "RS070").hint or "")
