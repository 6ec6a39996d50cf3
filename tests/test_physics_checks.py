"""``robospec check``'s physics checks on real SAPIEN physics (CPU, headless, no mocks): each
check with a robot that passes and one that fails, and the report built from them.

The shipped robots (the Panda, which passes every check; fetch and an inspire hand, broken
upstream) are read from the one check of every spec in specs/ that test_check_zoo.py judges
(tests/shipped_checks.py), not checked again. The other failing robots are copies of the shipped
Panda spec under a new uid with one change; to keep this module fast, a copy keeps only the
control modes its case needs (and the controllers those use), and they are checked in one batch.
"""

from __future__ import annotations

import io
import json
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import CRASHING_MODES, MANISKILL_SPECS

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.minutes,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]
pytest.importorskip("mani_skill")

from ruamel.yaml import YAML  # noqa: E402
from shipped_checks import shipped_spec_reports  # noqa: E402

from robospec.diagnostics import Diagnostic  # noqa: E402
from robospec.physics.batch import Options, RobotReport, check_paths  # noqa: E402
from robospec.physics.findings import Finding, Status  # noqa: E402
from robospec.physics.report import render_json, render_text  # noqa: E402

PANDA = MANISKILL_SPECS / "panda.yaml"
INSPIRE = MANISKILL_SPECS / "fixed_inspire_hand_right.yaml"
FETCH = MANISKILL_SPECS / "fetch.yaml"
ARM = [f"panda_joint{i}" for i in range(1, 8)]

Change = Callable[[Any], None]


# -- helpers ---------------------------------------------------------------------------------


def _yaml() -> YAML:
    yaml = YAML()
    yaml.width = 4096  # keep flow mappings on one line, as written
    yaml.preserve_quotes = True
    return yaml


def spec_copy(
    source: Path,
    folder: Path,
    uid: str,
    modes: list[str] | None = None,
    change: Change | None = None,
) -> Path:
    """``source`` written to ``folder/<uid>.yaml`` under ``uid``, keeping only ``modes`` (and
    the controllers they use, with what those extend), with ``change`` applied."""
    yaml = _yaml()
    data = yaml.load(source.read_text(encoding="utf-8"))
    data["uid"] = uid
    if modes is not None:
        for mode in list(data["control_modes"]):
            if mode not in modes:
                del data["control_modes"][mode]
        used = {
            name
            for mode in data["control_modes"].values()
            for group, name in mode.items()
            if group != "balance_passive_force"
        }
        while True:
            parents = {data["controllers"][name].get("extends") for name in used} - used - {None}
            if not parents:
                break
            used |= parents
        for name in list(data["controllers"]):
            if name not in used:
                del data["controllers"][name]
    if change is not None:
        change(data)
    out = io.StringIO()
    yaml.dump(data, out)
    path = folder / f"{uid}.yaml"
    path.write_text(out.getvalue(), encoding="utf-8")
    return path


def key_position(path: Path, *keys: str) -> tuple[int, int]:
    """1-based (line, column) of the last of ``keys`` in the YAML file ``path``."""
    node = _yaml().load(path.read_text(encoding="utf-8"))
    for key in keys[:-1]:
        node = node[key]
    line, column = node.lc.key(keys[-1])
    return line + 1, column + 1


def position(diagnostic: Diagnostic) -> tuple[int, int]:
    return diagnostic.location.line, diagnostic.location.column


def found(
    report: RobotReport, check: str, mode: str | None = "*", subject: str | None = None
) -> list[Finding]:
    return [
        f
        for f in report.findings
        if f.check == check
        and (mode == "*" or f.mode == mode)
        and (subject is None or f.subject == subject)
    ]


def one(report: RobotReport, check: str, mode: str | None = "*", subject: str | None = None):
    (finding,) = found(report, check, mode, subject)
    return finding


def codes(finding: Finding) -> list[str]:
    return [d.code for d in finding.diagnostics]


def error_codes(report: RobotReport) -> set[str]:
    return {d.code for d in report.all_diagnostics if d.is_error}


# -- the robots, checked once per module -----------------------------------------------------


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A folder for spec copies and a private robospec cache; the agents registered here are
    unregistered afterwards."""
    from mani_skill.agents.registration import REGISTERED_AGENTS

    agents, modules = set(REGISTERED_AGENTS), set(sys.modules)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOSPEC_CACHE_DIR", str(tmp_path_factory.mktemp("check_cache")))
        yield tmp_path_factory.mktemp("check_specs")
    for uid in set(REGISTERED_AGENTS) - agents:
        del REGISTERED_AGENTS[uid]
    for name in set(sys.modules) - modules:
        if name.startswith("robospec_agents."):
            del sys.modules[name]


@pytest.fixture(scope="module")
def panda(tmp_path_factory: pytest.TempPathFactory) -> RobotReport:
    """The shipped Panda spec, with the default thresholds and step counts."""
    report = shipped_spec_reports(tmp_path_factory, [PANDA, INSPIRE, FETCH])["rs_panda"]
    assert report.spec.endswith(PANDA.name)
    return report


@pytest.fixture(scope="module")
def zoo(tmp_path_factory: pytest.TempPathFactory) -> dict[str, RobotReport]:
    """ManiSkill robots broken upstream, as shipped: the right fixed inspire hand, and fetch."""
    reports = shipped_spec_reports(tmp_path_factory, [PANDA, INSPIRE, FETCH])
    return {uid: reports[uid] for uid in ("rs_fixed_inspire_hand_right", "rs_fetch")}


def _float_up(data: Any) -> None:
    """A floating Panda whose keyframe puts it 0.5 m up."""
    data["loader"] = {"fix_root_link": False}
    data["keyframes"]["rest"]["pose"] = {"p": [0, 0, 0.5]}


def _float(data: Any) -> None:
    """The same, with gravity on its links: ManiSkill disables gravity on every link of a robot
    whose mode balances passive force (its default)."""
    _float_up(data)
    data["control_modes"]["pd_joint_pos"]["balance_passive_force"] = False


def _checks(**sections: dict[str, Any]) -> Change:
    def change(data: Any) -> None:
        data["checks"] = sections

    return change


def _both(*changes: Change) -> Change:
    def change(data: Any) -> None:
        for each in changes:
            each(data)

    return change


def _controller(name: str, **values: Any) -> Change:
    def change(data: Any) -> None:
        data["controllers"][name].update(values)

    return change


FOLDED_ARM = [0, 1.0, 0, -2.5, 0, 0, 0]  # the wrist bent back: the right finger into link 5


def _folded(data: Any) -> None:
    data["keyframes"]["folded"] = {"qpos": {"arm": FOLDED_ARM, "gripper": 0.04}}


def _never_collide(data: Any) -> None:
    data["never_collide"] = [["panda_link5", "panda_rightfinger"]]


OVERPOWERED = _controller("arm_pos", lower=-10, upper=10, stiffness=1e5, damping=1e4)
OVERPOWERED_FORCE = _controller("arm_pos", force_limit=1e5)

# uid suffix: (modes, the one change)
VARIANTS: dict[str, tuple[list[str], Change]] = {
    "floating": (["pd_joint_pos"], _float),
    "floating_balanced": (["pd_joint_pos"], _float_up),
    "floating_loose": (
        ["pd_joint_pos"],
        _both(_float, _checks(keyframe_hold={"max_root_drift": 1.0, "max_joint_drift": 1.0})),
    ),
    "unknown_hold_mode": (["pd_joint_pos"], _checks(keyframe_hold={"mode": "pd_no_such_mode"})),
    "soft_arm": (["pd_joint_pos"], _controller("arm_pos", stiffness=1)),
    "underdamped_arm": (["pd_joint_pos"], _controller("arm_pos", stiffness=1e4, damping=1)),
    "quick_arm_required": (
        ["pd_joint_pos", "pd_joint_delta_pos"],
        _checks(step_response={"controllers": {"arm_pos": {"max_rise_time": 0.1}}}),
    ),
    "overpowered_limits": (["pd_joint_pos"], _both(OVERPOWERED, OVERPOWERED_FORCE)),
    "overpowered_limits_tolerated": (
        ["pd_joint_pos"],
        _both(
            OVERPOWERED,
            OVERPOWERED_FORCE,
            _checks(random_actions={"joint_limit_tolerance": 50}),
        ),
    ),
    "slow_joints_required": (["pd_joint_pos"], _checks(random_actions={"max_joint_speed": 1.0})),
    "folded": (["pd_joint_pos"], _folded),
    "folded_never_collide": (["pd_joint_pos"], _both(_folded, _never_collide)),
    "folded_deep_contacts_only": (
        ["pd_joint_pos"],
        _both(_folded, _checks(self_contact={"min_depth": 0.05})),
    ),
}


@pytest.fixture(scope="module")
def variant_paths(workspace: Path) -> dict[str, Path]:
    return {
        name: spec_copy(PANDA, workspace, f"rs_chk_{name}", modes, change)
        for name, (modes, change) in VARIANTS.items()
    }


@pytest.fixture(scope="module")
def variants(variant_paths: dict[str, Path]) -> dict[str, RobotReport]:
    """Every Panda variant, checked with 20 steps of hold and of random actions."""
    reports, extra = check_paths(list(variant_paths.values()), Options(steps=20))
    assert extra == []
    by_uid = {r.uid: r for r in reports}
    return {name: by_uid[f"rs_chk_{name}"] for name in VARIANTS}


# -- keyframe_hold (RS501) -------------------------------------------------------------------


def test_keyframe_hold_panda_rest_holds_still(panda: RobotReport) -> None:
    finding = one(panda, "keyframe_hold")
    assert (finding.mode, finding.subject, finding.status) == ("pd_joint_pos", "rest", Status.PASS)
    assert finding.metrics["steps"] == 50 and finding.metrics["held_by"] == "actions"
    assert finding.metrics["max_joint_drift"] < 1e-3
    assert finding.metrics["max_root_drift"] < 1e-3
    assert finding.metrics["finite"] is True


def test_keyframe_hold_floating_robot_in_mid_air_cannot_stand_and_says_why(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    # gravity on, 0.5 m up, nothing under it: its drives are held on a test stand (its root
    # held), and its fall is information with the reason, not a failure of its drives
    stand = one(variants["floating"], "keyframe_hold", subject="rest (test stand)")
    assert stand.metrics["held_by"] == "actions, root held"
    assert stand.metrics["max_root_drift"] < 0.01
    standing = one(variants["floating"], "keyframe_hold", subject="rest (standing)")
    assert standing.status is Status.INFO
    (diagnostic,) = standing.diagnostics
    assert diagnostic.code == "RS523" and not diagnostic.is_error
    assert "it touches no ground: the keyframe holds it in mid-air" in diagnostic.message
    assert position(diagnostic) == key_position(variant_paths["floating"], "keyframes", "rest")


def test_keyframe_hold_floating_robot_balanced_by_maniskill_does_not_fall(
    variants: dict[str, RobotReport],
) -> None:
    # balance_passive_force (ManiSkill's default) disables gravity on every link of the robot,
    # root included, so a floating Panda 0.5 m up stays there: the hold passes, and the gravity
    # check fails it (it hovers)
    report = variants["floating_balanced"]
    finding = one(report, "keyframe_hold", subject="rest (standing)")
    assert finding.status is Status.PASS
    assert finding.metrics["max_root_drift"] < 1e-3
    hovers = one(report, "gravity", "pd_joint_pos")
    assert hovers.status is Status.FAIL and codes(hovers) == ["RS518"]
    assert error_codes(report) == {"RS518"}


def test_keyframe_hold_max_joint_drift_from_the_spec_is_honoured_on_the_test_stand(
    variants: dict[str, RobotReport],
) -> None:
    # on the test stand under gravity the arm's shoulder sags; with the joints given room the
    # same hold passes
    strict = one(variants["floating"], "keyframe_hold", subject="rest (test stand)")
    loose = one(variants["floating_loose"], "keyframe_hold", subject="rest (test stand)")
    assert loose.status is Status.PASS
    assert strict.metrics["max_joint_drift"] == pytest.approx(loose.metrics["max_joint_drift"])
    if strict.metrics["max_joint_drift"] > 0.05:
        assert strict.status is Status.FAIL and codes(strict) == ["RS501"]
        (diagnostic,) = strict.diagnostics
        assert "on a test stand (its root held clear of the ground)" in diagnostic.message
        assert "more than max_joint_drift 0.05" in diagnostic.message
    else:
        assert strict.status is Status.PASS


def test_keyframe_hold_unknown_mode_is_rs501_at_the_checks_key(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    report = variants["unknown_hold_mode"]
    finding = one(report, "keyframe_hold")
    assert finding.status is Status.FAIL and finding.mode == "pd_no_such_mode"
    (diagnostic,) = finding.diagnostics
    assert diagnostic.code == "RS501"
    assert "'pd_no_such_mode' is not a control mode" in diagnostic.message
    assert diagnostic.hint == "name one of: pd_joint_pos"
    path = variant_paths["unknown_hold_mode"]
    assert position(diagnostic) == key_position(path, "checks", "keyframe_hold", "mode")
    assert diagnostic.location.file == str(path)
    assert error_codes(report) == {"RS501"}


def test_keyframe_hold_with_a_pos_vel_mode_holds_the_keyframe(workspace: Path) -> None:
    path = spec_copy(PANDA, workspace, "rs_chk_pos_vel_hold", ["pd_joint_pos_vel"])
    (report,), _ = check_paths([path], Options(steps=5))
    assert one(report, "keyframe_hold").status is Status.PASS


# -- random_actions (RS502-RS504) ------------------------------------------------------------


def test_random_actions_every_panda_mode_stays_finite_within_limits(panda: RobotReport) -> None:
    findings = found(panda, "random_actions")
    modes = [m for m in dict.fromkeys(f.mode for f in findings)]
    assert len(modes) == 11 and len(findings) == 22  # from load and from rest, per mode
    assert {f.subject for f in findings} == {"from load", "from rest"}
    for finding in findings:
        assert finding.status is Status.PASS, (finding.mode, finding.summary)
        assert finding.metrics["steps"] == 60 and finding.metrics["nan_step"] is None
        assert finding.metrics["max_limit_excess"] == 0.0
        assert finding.metrics["max_joint_speed"] < 200


def test_random_actions_inspire_hand_nan_names_the_mimic_joints_and_the_urdf_tag(
    zoo: dict[str, RobotReport],
) -> None:
    report = zoo["rs_fixed_inspire_hand_right"]
    failed = [f for f in found(report, "random_actions") if f.failed]
    assert {f.mode for f in failed} == {"pd_joint_pos", "pd_joint_delta_pos"}
    for finding in failed:
        assert codes(finding) == ["RS502"]
        assert finding.metrics["nan_step"] is not None
        (diagnostic,) = finding.diagnostics
        message = diagnostic.message
        assert "random actions made the state NaN" in message
        assert "the cause is the URDF <mimic> tags" in message
        for mimic, control in [
            ("right_hand_index_PIP_joint", "right_hand_index_MCP_joint"),
            ("right_hand_thumb_IP_joint", "right_hand_thumb_MCP_joint"),
        ]:
            assert f"'{mimic}' mimics '{control}'" in message
        assert "inspire_hand_right.urdf:" in message  # where the tags are
        assert diagnostic.hint is not None and "pd_joint_pos_mimic" in diagnostic.hint
        assert "right_hand_index_PIP_joint: right_hand_index_MCP_joint" in diagnostic.hint
        line, _ = key_position(INSPIRE, "control_modes", finding.mode)
        assert diagnostic.location.line == line
        assert diagnostic.location.file.endswith("fixed_inspire_hand_right.yaml")


def test_random_actions_fetch_pos_vel_nan_names_the_infinite_bounds(
    zoo: dict[str, RobotReport],
) -> None:
    report = zoo["rs_fetch"]
    failed = [f for f in found(report, "random_actions") if f.failed]
    assert {f.mode for f in failed} == {"pd_joint_pos_vel"}
    assert all(
        f.status is Status.PASS for f in found(report, "random_actions", "pd_joint_delta_pos")
    )
    for finding in failed:
        (diagnostic,) = finding.diagnostics
        assert diagnostic.code == "RS502"
        assert finding.metrics["nan_step"] == 1
        assert "the cause is group 'arm'" in diagnostic.message
        assert "normalized to [-1, 1] over infinite joint limits" in diagnostic.message
        assert "<mimic>" not in diagnostic.message
        assert diagnostic.hint == (
            "give the controller finite lower/upper, or set normalize_action: false"
        )


def test_random_actions_drive_that_overpowers_the_limits_is_rs503(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    report = variants["overpowered_limits"]
    findings = found(report, "random_actions")
    assert any("RS503" in codes(f) for f in findings)
    line = key_position(variant_paths["overpowered_limits"], "control_modes", "pd_joint_pos")
    for finding in findings:
        for diagnostic in finding.diagnostics:
            if diagnostic.code == "RS503":
                assert finding.metrics["max_limit_excess"] > 0
                assert "past its limit (tolerance 0.1)" in diagnostic.message
                joint = diagnostic.message.split("joint '")[1].split("'")[0]
                assert joint in ARM
                assert position(diagnostic) == line


def test_random_actions_joint_limit_tolerance_from_the_spec_is_honoured(
    variants: dict[str, RobotReport],
) -> None:
    # the same robot without the tolerance goes past its limits, by less than 50
    past = [
        float(d.message.split(" went ")[1].split(" past")[0])
        for f in found(variants["overpowered_limits"], "random_actions")
        for d in f.diagnostics
        if d.code == "RS503"
    ]
    assert past and max(past) < 50
    findings = found(variants["overpowered_limits_tolerated"], "random_actions")
    assert all("RS503" not in codes(f) for f in findings)
    assert all(f.metrics["max_limit_excess"] == 0.0 for f in findings)  # beyond the tolerance


def test_random_actions_max_joint_speed_from_the_spec_makes_a_runaway(
    variants: dict[str, RobotReport],
) -> None:
    findings = found(variants["slow_joints_required"], "random_actions")
    assert len(findings) == 2
    for finding in findings:
        assert finding.status is Status.FAIL and codes(finding) == ["RS504"]
        (diagnostic,) = finding.diagnostics
        joint = finding.metrics["fastest_joint"]
        assert f"joint '{joint}' ran away at" in diagnostic.message
        assert "(max_joint_speed 1)" in diagnostic.message
        assert finding.metrics["max_joint_speed"] > 1.0


# -- step_response (RS505-RS507) -------------------------------------------------------------


def test_step_response_panda_arm_rises_in_about_a_fifth_of_a_second(panda: RobotReport) -> None:
    finding = one(panda, "step_response", "pd_joint_pos", "arm (arm_pos)")
    assert finding.status is Status.PASS and finding.diagnostics == ()
    metrics = finding.metrics
    assert metrics["kind"] == "position"
    assert 0.15 < metrics["rise_time"] < 0.3  # stiffness 1e3, damping 1e2
    assert metrics["overshoot"] < 0.5
    assert metrics["settling_time"] is not None and metrics["settling_time"] < 0.5
    assert metrics["steady_state_error"] < 0.05
    assert [d["joint"] for d in finding.details] == ARM
    velocity = one(panda, "step_response", "pd_joint_vel", "arm (arm_vel)")
    assert velocity.status is Status.PASS and velocity.metrics["kind"] == "velocity"
    # one finding per controller: the gripper is stepped once, in the first mode using it
    assert len(found(panda, "step_response", subject="gripper")) == 1
    assert all(f.status is Status.PASS for f in found(panda, "step_response"))


def test_step_response_arm_with_stiffness_1_is_too_slow(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    finding = one(variants["soft_arm"], "step_response", "pd_joint_pos", "arm (arm_pos)")
    assert finding.status is Status.FAIL and codes(finding) == ["RS505"]
    assert finding.metrics["rise_time"] is None
    (diagnostic,) = finding.diagnostics
    assert "controller 'arm_pos' (pd_joint_pos/arm) is too slow" in diagnostic.message
    joint = diagnostic.message.split("joint '")[1].split("'")[0]
    assert joint in ARM
    assert "covered only" in diagnostic.message and "(max_rise_time 0.5 s)" in diagnostic.message
    assert position(diagnostic) == key_position(variant_paths["soft_arm"], "controllers", "arm_pos")
    # the gripper, untouched, still passes
    assert one(variants["soft_arm"], "step_response", subject="gripper").status is Status.PASS


def test_step_response_underdamped_arm_overshoots(variants: dict[str, RobotReport]) -> None:
    finding = one(variants["underdamped_arm"], "step_response", subject="arm (arm_pos)")
    assert finding.status is Status.FAIL and "RS506" in codes(finding)
    assert finding.metrics["overshoot"] > 0.5
    diagnostic = next(d for d in finding.diagnostics if d.code == "RS506")
    assert "controller 'arm_pos' (pd_joint_pos/arm) is unstable or underdamped" in (
        diagnostic.message
    )
    assert "overshot a position step by" in diagnostic.message
    assert "(max_overshoot 50%)" in diagnostic.message


def test_step_response_per_controller_limits_are_honoured(
    variants: dict[str, RobotReport],
) -> None:
    report = variants["quick_arm_required"]
    strict = one(report, "step_response", subject="arm (arm_pos)")
    assert strict.status is Status.FAIL and codes(strict) == ["RS505"]
    assert "(max_rise_time 0.1 s)" in strict.diagnostics[0].message
    assert f"took {strict.metrics['rise_time']:.3g} s to rise" in strict.diagnostics[0].message
    # the same gains under another name keep the spec-wide limit (0.5 s)
    relaxed = one(report, "step_response", subject="arm (arm_delta_pos)")
    assert relaxed.status is Status.PASS
    assert relaxed.metrics["rise_time"] == pytest.approx(strict.metrics["rise_time"], abs=0.02)


def test_step_response_passive_group_is_skipped(zoo: dict[str, RobotReport]) -> None:
    finding = one(zoo["rs_fixed_inspire_hand_right"], "step_response", subject="passive")
    assert finding.status is Status.SKIP and not finding.failed


# -- self_contact (RS508) --------------------------------------------------------------------


def test_self_contact_panda_rest_touches_nothing(panda: RobotReport) -> None:
    finding = one(panda, "self_contact", subject="rest")
    assert (finding.subject, finding.status) == ("rest", Status.PASS)
    assert finding.metrics["pairs"] == 0


def test_self_contact_folded_keyframe_names_the_links_and_suggests_never_collide(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    report = variants["folded"]
    assert one(report, "self_contact", subject="rest").status is Status.PASS
    finding = one(report, "self_contact", subject="folded")
    assert finding.status is Status.FAIL and codes(finding) == ["RS508"]
    assert [(d["link_a"], d["link_b"]) for d in finding.details] == [
        ("panda_link5", "panda_rightfinger")
    ]
    assert finding.details[0]["depth"] > 0.001
    (diagnostic,) = finding.diagnostics
    touching = (
        "at keyframe 'folded' these links of the robot touch: panda_link5 + panda_rightfinger"
    )
    assert touching in diagnostic.message
    assert diagnostic.hint is not None
    assert "never_collide: [[panda_link5, panda_rightfinger]]" in diagnostic.hint
    assert position(diagnostic) == key_position(variant_paths["folded"], "keyframes", "folded")


def test_self_contact_passes_once_the_pair_is_in_never_collide(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    from robospec.pipeline import compile_spec

    compiled = compile_spec(variant_paths["folded_never_collide"])
    # the variant must compile with its never_collide rule applied: a spec that lost it would
    # pass this test for the wrong reason (no rule, no contact check), so it fails instead
    assert compiled.ok, [d.format_text() for d in compiled.diagnostics if d.is_error]
    assert compiled.robot is not None and compiled.robot.never_collide
    finding = one(variants["folded_never_collide"], "self_contact", subject="folded")
    assert finding.status is Status.PASS, finding.summary


def test_self_contact_min_depth_from_the_spec_is_honoured(
    variants: dict[str, RobotReport],
) -> None:
    depth = one(variants["folded"], "self_contact", subject="folded").details[0]["depth"]
    assert depth < 0.05  # the folded finger presses about 2 cm into link 5
    finding = one(variants["folded_deep_contacts_only"], "self_contact", subject="folded")
    assert finding.status is Status.PASS and finding.metrics["pairs"] == 0


def test_self_contact_is_skipped_without_self_collisions(zoo: dict[str, RobotReport]) -> None:
    finding = one(zoo["rs_fixed_inspire_hand_right"], "self_contact")
    assert finding.status is Status.SKIP and finding.summary == "disable_self_collisions is set"


# -- action_layout ---------------------------------------------------------------------------


def test_action_layout_panda_joint_delta_pos_rows(panda: RobotReport) -> None:
    finding = one(panda, "action_layout", "pd_joint_delta_pos")
    assert finding.status is Status.INFO and not finding.failed
    assert finding.subject == "8 dims" and finding.metrics["dims"] == 8
    rows = finding.details
    assert [r["index"] for r in rows] == list(range(8))
    assert [r["target"] for r in rows] == [*ARM, "panda_finger_joint1"]
    assert all(r["normalized"] is True for r in rows)
    for row in rows[:7]:
        assert (row["group"], row["controller"]) == ("arm", "PDJointPosController")
        assert (row["low"], row["high"]) == pytest.approx((-0.1, 0.1))
    gripper = rows[7]
    assert (gripper["group"], gripper["controller"]) == ("gripper", "PDJointPosMimicController")
    assert (gripper["low"], gripper["high"]) == pytest.approx((-0.01, 0.04))


def test_action_layout_panda_ee_delta_pose_rows_are_named_axes(panda: RobotReport) -> None:
    rows = one(panda, "action_layout", "pd_ee_delta_pose").details
    assert [r["target"] for r in rows] == [
        "arm.x",
        "arm.y",
        "arm.z",
        "arm.rx",
        "arm.ry",
        "arm.rz",
        "panda_finger_joint1",
    ]
    assert [r["index"] for r in rows] == list(range(7))
    # panda_joint_pos: absolute targets over the joint limits, not normalized
    absolute = one(panda, "action_layout", "pd_joint_pos").details
    assert absolute[0]["normalized"] is False
    assert (absolute[0]["low"], absolute[0]["high"]) == pytest.approx((-2.8973, 2.8973))


def test_action_layout_fetch_base_rows_are_named(zoo: dict[str, RobotReport]) -> None:
    rows = one(zoo["rs_fetch"], "action_layout", "pd_joint_delta_pos").details
    assert len(rows) == 13
    base = [r for r in rows if r["group"] == "base"]
    assert [(r["index"], r["target"]) for r in base] == [(11, "base.v"), (12, "base.wz")]
    assert base[0]["controller"] == "PDBaseForwardVelController"
    body = [r["target"] for r in rows if r["group"] == "body"]
    assert body == ["head_pan_joint", "head_tilt_joint", "torso_lift_joint"]


# -- the report ------------------------------------------------------------------------------


def test_a_report_fails_exactly_when_a_finding_fails(
    panda: RobotReport, variants: dict[str, RobotReport]
) -> None:
    assert not panda.failed and error_codes(panda) == set()
    assert variants["soft_arm"].failed and error_codes(variants["soft_arm"]) == {"RS505"}
    assert error_codes(variants["folded"]) >= {"RS508"}


def test_json_report_has_the_documented_keys(
    panda: RobotReport, zoo: dict[str, RobotReport]
) -> None:
    reports = [panda, zoo["rs_fetch"]]
    data = json.loads(render_json(reports, []))
    assert set(data) == {"robots", "diagnostics", "summary"}
    assert data["summary"] == {
        "robots": 2,
        "passed": 1,
        "failed": 1,
        "not_checked": 0,
        "errors": sum(d.is_error for r in reports for d in r.all_diagnostics),
        "warnings": sum(not d.is_error for r in reports for d in r.all_diagnostics),
    }
    robot, fetch = data["robots"]
    assert set(robot) == {"spec", "uid", "status", "findings", "diagnostics", "messages"}
    for message in robot["messages"] + fetch["messages"]:
        assert set(message) == {"source", "level", "text", "count", "example", "meaning"}
    assert (robot["uid"], robot["status"]) == ("rs_panda", "pass")
    assert (fetch["uid"], fetch["status"]) == ("rs_fetch", "fail")
    for finding in robot["findings"] + fetch["findings"]:
        assert set(finding) == {
            "check",
            "mode",
            "subject",
            "status",
            "summary",
            "metrics",
            "details",
            "codes",
        }
    assert {f["check"] for f in robot["findings"]} == {
        "action_layout",
        "described",
        "ground",
        "keyframe_hold",
        "self_contact",
        "step_response",
        "random_actions",
    }
    failed = [f for f in fetch["findings"] if f["status"] == "fail"]
    # NaN in pd_joint_pos_vel; where this ManiSkill cannot build a mode, that mode's crash
    crashed = {f["mode"] for f in failed if f["codes"] == ["RS516"]}
    assert crashed == CRASHING_MODES.get("fetch", frozenset())
    assert failed and all(f["codes"] == ["RS502"] for f in failed if f["mode"] not in crashed)
    assert {d["code"] for d in fetch["diagnostics"] if d["severity"] == "error"} == {"RS502"} | (
        {"RS516"} if crashed else set()
    )
    for diagnostic in fetch["diagnostics"]:
        assert set(diagnostic) == {
            "file",
            "line",
            "column",
            "code",
            "severity",
            "message",
            "hint",
        }


def test_json_report_is_the_same_text_on_every_run(
    variants: dict[str, RobotReport], variant_paths: dict[str, Path]
) -> None:
    # checked again, alone: the same text as in the batch every variant was checked in
    names = ["soft_arm", "folded"]
    again = render_json(*check_paths([variant_paths[n] for n in names], Options(steps=20)))
    assert again == render_json([variants[n] for n in names], [])
    assert json.loads(again)["summary"]["failed"] == 2


def _reject(constant: str) -> None:
    raise ValueError(f"not JSON: {constant}")


def test_json_report_is_strict_json_even_with_infinite_action_bounds(
    zoo: dict[str, RobotReport],
) -> None:
    json.loads(render_json([zoo["rs_fetch"]], []), parse_constant=_reject)


def test_text_report_has_the_table_header_and_the_summary_line(
    panda: RobotReport, variants: dict[str, RobotReport]
) -> None:
    text = render_text([panda, variants["soft_arm"]], [])
    lines = text.splitlines()
    assert lines[0] == f"{panda.spec}: rs_panda: PASS"
    assert lines[1].split() == ["check", "mode", "subject", "result", "details"]
    assert "  action layout:" in lines
    assert any(
        line.startswith(f"{variants['soft_arm'].spec}: rs_chk_soft_arm: FAIL") for line in lines
    )
    assert any("step_response" in line and " FAIL " in line for line in lines)
    assert any(":" in line and "error[RS505]" in line for line in lines)
    assert lines[-1] == (
        "2 robot(s) checked: 1 passed, 1 failed, 0 not checked; 1 error(s), 0 warning(s)"
    )
