"""For an MJCF robot, MuJoCo judges ``check``'s keyframe hold (robospec.physics.mujoco_hold,
issue 36 class 7): the same hold, as long, under the file's own position servos. Where MuJoCo
holds it and ManiSkill does not, RS501 says the spec's drives fail; where neither holds it,
RS535 (a warning at the file's actuator) says the description cannot, in place of RS501.

The robots are made to show it (tests/data/check/mujoco_hold/): a two-link arm whose servos
hold it (strong.xml), loaded as MuJoCo compiles it with the same gains in the spec (holds) and
by ManiSkill's loader with a spec too weak (weak_spec); and the arm with servos too weak to
carry it in MuJoCo either (weak.xml, weak_file). Real MuJoCo and real ManiSkill, 0.5 s holds
(10 control steps at 20 Hz).
"""

from __future__ import annotations

from pathlib import Path

import pytest

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]
pytest.importorskip("mani_skill")

from robospec.physics.batch import Options, RobotReport, check_paths  # noqa: E402
from robospec.physics.findings import Finding, Status  # noqa: E402

DATA = Path(__file__).parent / "data" / "check" / "mujoco_hold"
SPECS = {name: DATA / f"{name}.yaml" for name in ("holds", "weak_spec", "weak_file")}
SPECS["no_actuators"] = DATA.parent / "crawler_falls.yaml"  # an MJCF without <actuator>


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, RobotReport]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        found, extra = check_paths(list(SPECS.values()), Options(steps=10), isolate=False)
    assert extra == []
    by_spec = {Path(report.spec).resolve(): report for report in found}
    return {name: by_spec[path.resolve()] for name, path in SPECS.items()}


def _hold(report: RobotReport, subject: str = "reach") -> Finding:
    (finding,) = [f for f in report.findings if f.check == "keyframe_hold" and f.subject == subject]
    return finding


def _line(path: Path, text: str) -> int:
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_an_mjcf_arm_its_servos_hold_in_mujoco_holds_in_maniskill_with_both_drifts_reported(
    reports: dict[str, RobotReport],
) -> None:
    hold = _hold(reports["holds"])
    assert hold.status is Status.PASS and hold.diagnostics == ()
    assert hold.metrics["max_joint_drift"] < 0.05
    assert hold.metrics["mujoco_max_joint_drift"] < 0.05
    assert "MuJoCo" in hold.summary


def test_where_mujoco_holds_and_maniskill_does_not_rs501_says_the_spec_drives_fail(
    reports: dict[str, RobotReport],
) -> None:
    hold = _hold(reports["weak_spec"])
    assert hold.status is Status.FAIL
    (diagnostic,) = hold.diagnostics
    assert diagnostic.code == "RS501" and diagnostic.is_error
    assert "MuJoCo holds it under the file's own actuators" in diagnostic.message
    assert "the spec's drives in ManiSkill fail it, not the description" in diagnostic.message
    assert "robospec tune --reference mujoco" in (diagnostic.hint or "")
    assert hold.metrics["max_joint_drift"] > 0.3
    assert hold.metrics["mujoco_max_joint_drift"] < 0.05


def test_servos_too_weak_to_hold_it_in_mujoco_either_warn_rs535_at_the_actuator_not_rs501(
    reports: dict[str, RobotReport],
) -> None:
    hold = _hold(reports["weak_file"])
    assert hold.status is Status.INFO and not hold.failed
    (diagnostic,) = hold.diagnostics
    assert diagnostic.code == "RS535" and not diagnostic.is_error
    xml = DATA / "weak.xml"
    assert diagnostic.location.file.endswith("weak.xml")
    assert diagnostic.location.line == _line(xml, 'name="shoulder_servo"')
    assert "cannot be held by the description either" in diagnostic.message
    assert hold.metrics["mujoco_joint"] == "shoulder"
    # both sides drift: MuJoCo's figure and ManiSkill's, each in the finding
    assert hold.metrics["mujoco_max_joint_drift"] > 0.2
    assert hold.metrics["max_joint_drift"] > 0.2
    codes = {d.code for f in reports["weak_file"].findings for d in f.diagnostics}
    assert "RS501" not in codes


def test_an_mjcf_without_actuators_is_not_judged_in_mujoco_and_says_why(
    reports: dict[str, RobotReport],
) -> None:
    stand = _hold(reports["no_actuators"], "rest (test stand)")
    assert stand.metrics["mujoco"] == "the file has no actuators"
    assert stand.metrics["mujoco_max_joint_drift"] is None
    assert "MuJoCo not judged" in stand.summary
    # standing on the ground is ManiSkill's alone: the file's floor is not its ground
    standing = [f for f in reports["no_actuators"].findings if f.subject == "rest (standing)"]
    assert all("mujoco" not in f.metrics for f in standing)
