"""scripts/demo's verdicts, without simulating: a robot is judged as ``robospec check`` judges
random actions, by its spec's ``checks.random_actions`` (a runaway is no "finite"), said with
units; a robot that misbehaves as ManiSkill's own agent does is told apart from a real failure;
the commands it suggests run from where the user stands."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

from robospec.demo.tour import AS_MANISKILL, FAILS, OK, Run, command, judge
from robospec.model.check_settings import RandomActions


def _run(speed: float = 1.0, past: float = 0.0, nan: bool = False, **settings: float) -> Run:
    return Run(
        modes=1,
        mode="pd_joint_pos",
        action_shape=(2,),
        joints=("hinge", "slide"),
        prismatic=(False, True),
        settings=RandomActions(**settings),
        past_limit=np.array([past, 0.0]),
        top_speed=np.array([speed, 0.5]),
        nan_step=4 if nan else None,
        nan_joints=("hinge",) if nan else (),
    )


def test_a_joint_faster_than_checks_bound_runs_away_with_its_unit() -> None:
    assert _run(speed=150.0).outcome() == "fastest hinge at 150 rad/s"
    fast = _run(speed=3.48e4)
    assert fast.outcome() == "runs away: hinge at 3.48e+04 rad/s"
    (runaway,) = fast.runaways()
    assert runaway.said(fast.joints, fast.prismatic) == (
        "hinge at 3.48e+04 rad/s (max_joint_speed 200 rad/s)"
    )
    # the bound is the spec's own checks.random_actions, not a copy of check's default
    assert not _run(speed=3.48e4, max_joint_speed=5e4).runaways()


def test_a_joint_past_its_limit_beyond_the_tolerance_runs_away() -> None:
    # past_limit is measured beyond the tolerance, as check measures it: 0.1 rad more is said
    assert _run(past=1.52).outcome() == "runs away: hinge 1.62 rad past its limit"
    assert _run(past=0.0).runaways() == []
    slide = Run(**{**_run().__dict__, "past_limit": np.array([0.0, 0.02])})
    assert slide.outcome() == "runs away: slide 0.12 m past its limit"


def test_a_robot_that_misbehaves_as_maniskills_own_is_told_apart_from_a_failure() -> None:
    assert judge("rs_a", _run(), None, None).verdict == OK
    nan = _run(nan=True)
    assert judge("rs_a", nan, "a", _run(nan=True)).verdict == AS_MANISKILL
    assert judge("rs_a", nan, "a", _run()).verdict == FAILS  # ManiSkill's agent stays finite
    assert judge("rs_a", nan, "a", _run(speed=1e4)).verdict == FAILS  # another failure
    assert judge("rs_a", nan, None, None).verdict == FAILS  # no agent of ManiSkill's to compare
    assert judge("rs_a", _run(speed=1e4), "a", _run(speed=2e4)).verdict == AS_MANISKILL


def test_a_command_is_named_as_it_runs_from_here(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``.venv/bin/robospec`` where the environment is not active; ``robospec`` where it is."""
    bin_dir = tmp_path / ".venv" / "bin"
    bin_dir.mkdir(parents=True)
    for name in ("python", "robospec"):
        (bin_dir / name).write_text("#!/bin/sh\n")
        (bin_dir / name).chmod(0o755)
    monkeypatch.setattr(sys, "executable", str(bin_dir / "python"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PATH", os.defpath)
    assert command("robospec") == os.path.join(".venv", "bin", "robospec")
    monkeypatch.setenv("PATH", f"{bin_dir}{os.pathsep}{os.defpath}")
    assert command("robospec") == "robospec"
    assert command("mkdocs") == "mkdocs"  # not installed beside it: by name
