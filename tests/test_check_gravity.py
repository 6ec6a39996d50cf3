"""`robospec check` never passes a floating robot that ManiSkill's gravity compensation holds up
in mid-air (RS518), nor a spec whose root is not the one ManiSkill loads (RS519).

The robot is tests/data/check/crawler.xml: a box with a free joint, lying on the floor, with one
arm. Its specs differ in one line each: gravity kept in every mode (it falls), ManiSkill's
default gravity compensation (it hovers: before RS518 every check passed it, a keyframe held in
mid-air does not drift), compensation asked for on purpose in one mode (a warning), and
``fix_root_link`` left at its default, which ManiSkill's MJCF loader ignores for a free joint.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

from robospec.diagnostics import Severity
from robospec.physics.batch import RobotReport, check_paths
from robospec.physics.findings import Finding, Status
from robospec.physics.results import Options

pytestmark = pytest.mark.maniskill

DATA = ROOT / "tests" / "data" / "check"
SPECS = [
    "crawler_falls",
    "crawler_hovers",
    "crawler_in_orbit",
    "crawler_in_orbit_silenced",
    "crawler_fixed",
]


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, RobotReport]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        found, extra = check_paths([DATA / f"{name}.yaml" for name in SPECS], Options(steps=10))
    assert extra == []
    return {Path(r.spec).stem: r for r in found}


def _gravity(report: RobotReport) -> dict[str | None, Finding]:
    return {f.mode: f for f in report.findings if f.check == "gravity"}


def _line(name: str, text: str) -> int:
    lines = (DATA / f"{name}.yaml").read_text().splitlines()
    return next(i for i, line in enumerate(lines, 1) if line.startswith(text))


def test_a_floating_robot_with_gravity_falls_and_passes(reports: dict[str, RobotReport]) -> None:
    report = reports["crawler_falls"]
    assert not report.failed, [d.format_text() for d in report.all_diagnostics]
    for finding in _gravity(report).values():
        assert finding.status is Status.PASS
        assert finding.metrics["fell"] > 0.4
        assert finding.metrics["gravity_off"] is False


def test_a_floating_robot_held_up_by_gravity_compensation_fails_rs518_at_each_mode(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["crawler_hovers"]
    assert report.failed
    # every other check passes it: in mid-air a held keyframe does not drift
    others = [f for f in report.findings if f.check != "gravity"]
    assert all(not f.failed for f in others), [f.summary for f in others if f.failed]
    hold = next(f for f in report.findings if f.check == "keyframe_hold")
    assert hold.metrics["max_root_drift"] < 1e-3
    errors = [d for d in report.all_diagnostics if d.is_error]
    assert [d.code for d in errors] == ["RS518", "RS518"]
    for diagnostic, mode in zip(errors, ["pd_joint_delta_pos", "pd_joint_pos"], strict=True):
        assert diagnostic.location.line == _line("crawler_hovers", f"  {mode}:")
        assert f"mode {mode}: the floating robot hovers" in diagnostic.message
        assert "fell 0 m" in diagnostic.message
        assert "ManiSkill turned gravity off for every link" in diagnostic.message
        assert "balance_passive_force: false" in (diagnostic.hint or "")


def test_gravity_compensation_asked_for_on_purpose_is_a_warning(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["crawler_in_orbit"]
    assert not report.failed
    found = _gravity(report)
    assert found["pd_joint_delta_pos"].status is Status.PASS
    (diagnostic,) = found["pd_joint_pos"].diagnostics
    assert (diagnostic.code, diagnostic.severity) == ("RS518", Severity.WARNING)
    assert diagnostic.location.line == _line("crawler_in_orbit", "  pd_joint_pos:")


def test_a_warning_of_the_simulation_that_the_spec_silences_is_not_reported(
    reports: dict[str, RobotReport],
) -> None:
    loud, quiet = reports["crawler_in_orbit"], reports["crawler_in_orbit_silenced"]
    assert [d.code for f in loud.findings for d in f.diagnostics] == ["RS518"]
    assert [d.code for f in quiet.findings for d in f.diagnostics] == [] and not quiet.failed
    assert [f.status for f in quiet.findings] == [f.status for f in loud.findings]


def test_an_error_stays_whatever_the_command_line_silences(tmp_path: Path) -> None:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
        found, _ = check_paths(
            [DATA / "crawler_hovers.yaml"], Options(steps=10), silence=frozenset({"RS518"})
        )
    (report,) = found
    errors = [d.code for f in report.findings for d in f.diagnostics if d.is_error]
    assert report.failed and errors == ["RS518", "RS518"]


def test_a_root_the_loader_frees_while_the_spec_fixes_it_is_rs519(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["crawler_fixed"]
    errors = [d for d in report.all_diagnostics if d.is_error]
    assert [d.code for d in errors] == ["RS519"]
    (diagnostic,) = errors
    # fix_root_link is not written: at the description
    assert diagnostic.location.line == _line("crawler_fixed", "description:")
    assert "fix_root_link: true (the default)" in diagnostic.message
    assert "<freejoint/>" in diagnostic.message
    # the robot is checked as the free robot it is: on the floor, it falls when lifted
    assert all(f.status is Status.PASS for f in _gravity(report).values() if f.mode)
