"""Keyframe joint velocities (``qvel``): checked like ``qpos`` (one value per active joint, by
joint, group or as an ordered list, RS303 otherwise) and handed to ManiSkill's ``Keyframe``.

tests/specs/positive/keyframe_qvel.yaml writes qvel both ways on ManiSkill's Panda."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest
from conftest import POSITIVE_SPECS

from robospec.pipeline import compile_spec

SPEC = POSITIVE_SPECS / "keyframe_qvel.yaml"
ACTIVE = [*(f"panda_joint{i}" for i in range(1, 8)), "panda_finger_joint1", "panda_finger_joint2"]
# the spec's qvel, one value per active joint in the description's order
SWINGING = (0.1, -0.2, 0.3, -0.4, 0.5, -0.6, 0.7, 0.01, -0.01)
CLOSING = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.7853981633974483, -0.02, -0.02)
CLOSING_QVEL = "qvel: [0, 0, 0, 0, 0, 0, -pi/4, -0.02, -0.02]"
SWINGING_ARM = "arm: [0.1, -0.2, 0.3, -0.4, 0.5, -0.6, 0.7]"


def position(text: str, needle: str, offset: int = 0) -> tuple[int, int]:
    """1-based (line, column) of ``needle``'s character ``offset`` in ``text``."""
    for number, line in enumerate(text.splitlines(), start=1):
        if needle in line:
            return number, line.index(needle) + offset + 1
    raise AssertionError(f"{needle!r} is not in the spec")


def errors_of(text: str, tmp_path: Path) -> list[tuple[str, int, int, str]]:
    path = tmp_path / "spec.yaml"
    path.write_text(text, encoding="utf-8")
    result = compile_spec(path)
    return [
        (d.code, d.location.line, d.location.column, d.message)
        for d in result.diagnostics
        if d.is_error
    ]


def test_qvel_by_group_and_joint_name_or_as_a_list_gives_one_value_per_active_joint() -> None:
    result = compile_spec(SPEC)
    assert [d.format_text() for d in result.diagnostics] == []
    assert result.robot is not None
    keyframes = {frame.name: frame for frame in result.robot.keyframes}
    assert keyframes["swinging"].qvel == SWINGING
    assert keyframes["closing"].qvel == CLOSING


@pytest.mark.parametrize(
    ("written", "count"),
    [("[0, 0, 0, 0, 0, 0, -pi/4, -0.02]", 8), ("[0, 0, 0, 0, 0, 0, -pi/4, -0.02, -0.02, 0]", 10)],
    ids=["one value short", "one value too many"],
)
def test_a_qvel_list_of_the_wrong_length_is_rs303_at_the_list(
    tmp_path: Path, written: str, count: int
) -> None:
    text = SPEC.read_text(encoding="utf-8").replace(CLOSING_QVEL, f"qvel: {written}")
    line, column = position(text, f"qvel: {written}", offset=len("qvel: "))
    expected = f"expected 9 values, one per active joint ({', '.join(ACTIVE)}), got {count}"
    assert errors_of(text, tmp_path) == [("RS303", line, column, expected)]


def test_a_qvel_group_one_value_short_is_rs303_at_the_group(tmp_path: Path) -> None:
    short = "arm: [0.1, -0.2, 0.3, -0.4, 0.5, -0.6]"
    text = SPEC.read_text(encoding="utf-8").replace(SWINGING_ARM, short)
    line, column = position(text, short, offset=len("arm: "))
    found = errors_of(text, tmp_path)
    assert ("RS303", line, column, "'arm' has 7 joints but 6 values") in found
    assert {code for code, *_ in found} == {"RS303"}


def test_a_qvel_that_leaves_out_joints_is_rs303_naming_them(tmp_path: Path) -> None:
    fingers = ", panda_finger_joint1: 0.01, panda_finger_joint2: -0.01"
    text = SPEC.read_text(encoding="utf-8").replace(fingers, "")
    line, column = position(text, "qvel: {arm", offset=len("qvel: "))
    message = "no value for active joint(s) panda_finger_joint1, panda_finger_joint2"
    assert errors_of(text, tmp_path) == [("RS303", line, column, message)]


# -- the generated agent ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def agent_class(maniskill: ModuleType, tmp_path_factory: pytest.TempPathFactory) -> Iterator[type]:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    import robospec

    ((uid, cls),) = robospec.register(SPEC, cache_dir=tmp_path_factory.mktemp("cache")).items()
    try:
        yield cls
    finally:
        REGISTERED_AGENTS.pop(uid, None)
        sys.modules.pop(cls.__module__, None)


def test_qvel_reaches_maniskills_keyframe_and_sets_the_robots_joint_velocities(
    agent_class: type,
) -> None:
    import numpy as np
    import torch
    from mani_skill.agents.base_agent import Keyframe

    from robospec.maniskill.headless import make_empty_env

    keyframes = agent_class.keyframes
    assert list(keyframes) == ["swinging", "closing"]
    for name, qvel in (("swinging", SWINGING), ("closing", CLOSING)):
        assert type(keyframes[name]) is Keyframe
        np.testing.assert_array_equal(keyframes[name].qvel, np.array(qvel))
    env = make_empty_env(agent_class.uid)
    try:
        env.reset(seed=0)
        robot = env.unwrapped.agent.robot
        for name in keyframes:  # as a task resets to a keyframe: SAPIEN takes it as it is
            robot.set_qvel(keyframes[name].qvel)
            expected = torch.tensor(keyframes[name].qvel, dtype=robot.get_qvel().dtype)
            assert torch.equal(robot.get_qvel()[0], expected), name
    finally:
        env.close()
