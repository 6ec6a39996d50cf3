"""`robospec check`'s random actions blame the floor, not the robot, for what a joint does while
the floor presses on a link it moves, unless the robot stands on that link.

The robot is tests/data/check/column_*.urdf: a 20 kg column with a 20 g finger, stood leaning so
that it topples. With the finger at its top, the column lands on it and the floor pushes the
finger through its limit, as random actions topple TALOS onto a 26 g fingertip: a warning, and
the robot passes. With the finger at its foot, the lowest link it leans on, the same push is a
link the robot stands on giving way: an error.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

from robospec.diagnostics import Severity
from robospec.physics.batch import RobotReport, check_paths
from robospec.physics.findings import Status
from robospec.physics.results import Options

pytestmark = pytest.mark.maniskill

DATA = ROOT / "tests" / "data" / "check"


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, RobotReport]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        found, extra = check_paths([DATA / "column_top.yaml", DATA / "column_foot.yaml"], Options())
    assert extra == []
    return {Path(r.spec).stem: r for r in found}


def _random_actions(report: RobotReport, code: str) -> list:
    return [
        d
        for f in report.findings
        if f.check == "random_actions" and f.subject == "from leaning"
        for d in f.diagnostics
        if d.code == code
    ]


def test_a_free_robot_toppled_onto_a_light_link_passes_with_the_floor_named(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["column_top"]
    assert not report.failed, [d.format_text() for d in report.all_diagnostics]
    for code, what in [("RS503", "past its limit"), ("RS504", "ran away at")]:
        (diagnostic,) = _random_actions(report, code)
        assert diagnostic.severity is Severity.WARNING
        assert "joint 'finger_joint'" in diagnostic.message and what in diagnostic.message
        assert "not one the robot stands on, pressed on the ground" in diagnostic.message
        assert "random actions toppled the free robot onto it" in diagnostic.message
        assert diagnostic.hint is not None and "nothing to fix in the robot" in diagnostic.hint
        assert "mounted" not in diagnostic.message + diagnostic.hint


def test_a_link_the_free_robot_stands_on_giving_way_is_its_failure(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["column_foot"]
    assert report.failed
    (diagnostic,) = _random_actions(report, "RS503")
    assert diagnostic.severity is Severity.ERROR
    assert "joint 'finger_joint'" in diagnostic.message
    assert "pressed on the ground" not in diagnostic.message


@pytest.fixture(scope="module")
def on_stand(tmp_path_factory: pytest.TempPathFactory) -> dict[str, list]:
    """The ground and random-actions findings of column_stand.yaml, those checks alone."""
    from robospec.output.register import register
    from robospec.physics import ground, random_actions
    from robospec.physics.check_run import CheckRun
    from robospec.pipeline import compile_spec

    spec = DATA / "column_stand.yaml"
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        compiled = compile_spec(spec)
        assert compiled.robot is not None and compiled.context is not None
        register(spec)
        run = CheckRun(compiled.robot.uid, compiled.context, compiled.context.spec.checks)
        try:
            return {"ground": ground.check(run), "random_actions": random_actions.check(run)}
        finally:
            run.close()


def test_a_joint_the_test_stand_cannot_keep_inside_fails_though_the_floor_pressed_on_it(
    on_stand: dict[str, list],
) -> None:
    (leaning,) = [f for f in on_stand["random_actions"] if f.subject == "from leaning"]
    found = {d.code: d for d in leaning.diagnostics}
    assert set(found) == {"RS503", "RS504"}
    for code, still in [("RS503", "still take it"), ("RS504", "still run it at")]:
        assert found[code].severity is Severity.ERROR, found[code].message
        assert "joint 'finger_joint'" in found[code].message
        assert f"held clear of the floor on a test stand, the same actions {still}" in (
            found[code].message
        )
        assert "pressed on the ground" not in found[code].message


def test_a_start_is_inside_the_ground_from_5_mm_below_it(on_stand: dict[str, list]) -> None:
    status = {f.subject: f.status for f in on_stand["ground"]}
    assert status["sunk_3mm"] is Status.PASS  # contacts settle by millimetres
    assert status["sunk_8mm"] is Status.FAIL
    (sunk,) = [f for f in on_stand["ground"] if f.subject == "sunk_8mm"]
    assert sunk.metrics["depth"] == pytest.approx(0.008, abs=1e-4)
