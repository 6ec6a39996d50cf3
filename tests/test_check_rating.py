"""A joint whose rated force cannot carry gravity where ``robospec check`` steps it is a located
warning about the rating (RS534, robospec.physics.rating), not an error about its gains; a spec
whose force_limit is below the rating is still told to raise it (issue 36 class 3). The arm is
made to show it: tests/data/check/rated/heavy_arm.urdf, a shoulder rated 3 N m under a 1 kg
link 0.3 m out (2.94 N m of gravity)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import invoke_robospec

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]
pytest.importorskip("mani_skill")

from robospec.physics.batch import Options, RobotReport, check_paths  # noqa: E402

DATA = Path(__file__).parent / "data" / "check" / "rated"


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, RobotReport]:
    paths = [DATA / "heavy_arm.yaml", DATA / "limited.yaml"]
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        found, extra = check_paths(paths, Options(steps=20), isolate=False)
    assert extra == []
    return {Path(r.spec).stem: r for r in found}


def _step_codes(report: RobotReport) -> list[tuple[str, str]]:
    return [
        (d.code, d.severity.value)
        for f in report.findings
        if f.check == "step_response"
        for d in f.diagnostics
    ]


def test_a_joint_whose_rating_cannot_carry_gravity_is_a_warning_about_the_rating_not_its_gains(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["heavy_arm"]
    assert _step_codes(report) == [("RS534", "warning")]
    (diagnostic,) = [d for f in report.findings for d in f.diagnostics if d.code == "RS534"]
    urdf = DATA / "heavy_arm.urdf"
    line = next(n for n, t in enumerate(urdf.read_text().splitlines(), 1) if "<joint " in t)
    assert diagnostic.location.file.endswith("heavy_arm.urdf") and diagnostic.location.line == line
    assert "rated 3 N m (its <limit effort>)" in diagnostic.message
    load = float(diagnostic.message.split("gravity alone puts ")[1].split(" N m")[0])
    assert 0.9 * 3 <= load <= 2.95  # 1 kg, 0.3 m out: 2.94 N m, less as the arm turns
    assert all(not f.failed for f in report.findings if f.check == "step_response")


def test_a_force_limit_under_the_rating_is_still_an_error_about_the_spec(
    reports: dict[str, RobotReport],
) -> None:
    codes = _step_codes(reports["limited"])
    assert "RS534" not in {code for code, _ in codes}
    assert {code for code, severity in codes if severity == "error"} & {"RS505", "RS506", "RS507"}


def test_new_says_the_rating_gravity_takes_and_check_warns_about_it_in_the_spec_new_wrote(
    tmp_path: Path,
) -> None:
    shutil.copy(DATA / "lifter.xml", tmp_path / "lifter.xml")
    spec = tmp_path / "lifter.yaml"
    result = invoke_robospec("new", str(tmp_path / "lifter.xml"), "-o", str(spec))
    assert result.exit_code == 0, result.output
    # the refinement measured it: RS609 says gravity takes the rating, the header says so too
    assert "warning[RS609]" in result.output and "gravity alone puts" in result.output
    header = spec.read_text().split("robospec: 1")[0]
    assert "Ratings gravity nearly takes: shoulder (rated 4.5 N m" in " ".join(header.split())
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path / "cache"))
        (report,), _ = check_paths([spec], Options(steps=20), isolate=False)
    codes = _step_codes(report)
    assert codes and {code for code, _ in codes} == {"RS534"}
    assert all(severity == "warning" for _, severity in codes)
