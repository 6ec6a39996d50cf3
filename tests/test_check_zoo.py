"""`robospec check` over every spec in specs/: all pass except reproductions of ManiSkill agents
that are broken upstream, which fail with exactly the codes listed here, and a reason.

Each entry of ``KNOWN_BROKEN_UPSTREAM`` is an upstream problem the checks find in ManiSkill's
own agent (the spec reproduces it exactly: tests/test_equivalence.py proves the rollouts
bit-identical), so an entry has to go when ManiSkill fixes it. docs/check.md lists them too.
"""

from __future__ import annotations

from pathlib import Path

import pytest

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore:__array_wrap__ must accept context:DeprecationWarning"),
]
pytest.importorskip("mani_skill")

from robospec.physics.batch import RobotReport, check_paths  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent

_MIMIC = (
    "URDF <mimic> finger joints that no pd_joint_pos_mimic controller drives: PhysX mimic "
    "joints go NaN within a few CPU steps"
)
_G1 = (
    "stiffness 50 with damping 1 is underdamped: joints overshoot a small step by ~75% and fly "
    "past their limits under random actions"
)
KNOWN_BROKEN_UPSTREAM: dict[str, tuple[frozenset[str], str]] = {
    "rs_fetch": (
        frozenset({"RS502"}),
        "pd_joint_pos_vel normalizes actions over the infinite limits of the continuous arm "
        "joints: NaN targets from the first step",
    ),
    **{
        f"rs_{hand}": (frozenset({"RS502"}), _MIMIC)
        for hand in (
            "fixed_inspire_hand_left",
            "fixed_inspire_hand_right",
            "floating_inspire_hand_left",
            "floating_inspire_hand_right",
        )
    },
    "rs_xarm7_ability": (frozenset({"RS501", "RS502", "RS506"}), _MIMIC),
    "rs_floating_ability_hand_right": (
        frozenset({"RS501", "RS503", "RS504"}),
        "the rest keyframe puts each finger's q2 at 0 where the mimic controller holds it at "
        "1.0585 * q1 + 0.7235; random joint targets make the hand fly past its limits",
    ),
    "rs_humanoid": (
        frozenset({"RS506"}),
        "pd_joint_delta_pos's per-joint gains are underdamped: a 0.1 rad step overshoots ~70%",
    ),
    "rs_unitree_g1": (frozenset({"RS503", "RS504", "RS506"}), _G1),
    "rs_unitree_g1_simplified_legs": (frozenset({"RS504", "RS506"}), _G1),
}


@pytest.fixture(scope="module")
def reports() -> dict[str, RobotReport]:
    found, extra = check_paths([ROOT / "specs"])
    assert not extra
    return {r.uid or r.spec: r for r in found}


def _codes(report: RobotReport) -> set[str]:
    return {d.code for d in report.all_diagnostics if d.is_error}


def test_every_spec_passes_except_the_ones_broken_upstream(reports: dict[str, RobotReport]) -> None:
    failing = {uid: frozenset(_codes(r)) for uid, r in reports.items() if r.failed}
    assert failing == {uid: codes for uid, (codes, _) in KNOWN_BROKEN_UPSTREAM.items()}


def test_every_spec_was_really_checked(reports: dict[str, RobotReport]) -> None:
    for uid, report in reports.items():
        checks = {f.check for f in report.findings}
        assert {"keyframe_hold", "random_actions", "step_response", "action_layout"} <= checks, uid


def test_inspire_hand_fails_naming_its_mimic_joints_and_the_cause(
    reports: dict[str, RobotReport],
) -> None:
    report = reports["rs_fixed_inspire_hand_right"]
    nan = [d for d in report.all_diagnostics if d.code == "RS502"]
    assert nan
    for diagnostic in nan:
        assert "URDF <mimic>" in diagnostic.message
        assert "'right_hand_index_PIP_joint' mimics 'right_hand_index_MCP_joint'" in (
            diagnostic.message
        )
        assert diagnostic.hint is not None and "pd_joint_pos_mimic" in diagnostic.hint
        assert diagnostic.location.file.endswith("fixed_inspire_hand_right.yaml")
        assert diagnostic.location.line > 1  # at the control mode


def test_fetch_nan_names_the_infinite_bounds(reports: dict[str, RobotReport]) -> None:
    (mode,) = {
        f.mode for f in reports["rs_fetch"].findings if f.failed and f.check == "random_actions"
    }
    assert mode == "pd_joint_pos_vel"
    messages = [d.message for d in reports["rs_fetch"].all_diagnostics if d.code == "RS502"]
    assert all("infinite joint limits" in m for m in messages)


def test_ability_hand_keyframe_failure_explains_the_mimic_rule(
    reports: dict[str, RobotReport],
) -> None:
    (diagnostic,) = [
        d for d in reports["rs_floating_ability_hand_right"].all_diagnostics if d.code == "RS501"
    ]
    assert "mimic" in diagnostic.message and "'index_q2' is at 0" in diagnostic.message


def test_docs_list_every_robot_broken_upstream() -> None:
    text = (ROOT / "docs" / "check.md").read_text(encoding="utf-8")
    for uid in KNOWN_BROKEN_UPSTREAM:
        assert f"`{uid}`" in text, uid
