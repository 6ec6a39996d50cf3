"""``robospec doc``: the Markdown robot card — Mermaid kinematic tree (sanitized ids, escaped
labels, active joints marked), the action layout of every mode computed statically (and proven
equal to the live controllers' layout in ManiSkill), keyframes and cameras; deterministic, and
never written for a spec with errors."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import CRASHING_MODES, MANISKILL_SPECS, PANDA_SPEC, ROOT, run_robospec

from robospec.authoring.card import mermaid_label, node_ids
from robospec.authoring.commands import run_doc, run_new
from robospec.authoring.layout import mode_layout
from robospec.pipeline import compile_spec

pytestmark = pytest.mark.minutes  # CI starts it first (tests/conftest.py)


def card(spec: Path, out: Path) -> str:
    result = run_doc(spec, out).write()
    assert not result.failed, result.diagnostics
    return out.read_text()


def section(text: str, title: str) -> list[str]:
    lines = text.splitlines()
    start = lines.index(title) + 1
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("## ")), len(lines))
    return lines[start:end]


def mermaid(text: str) -> list[str]:
    lines = text.splitlines()
    start = lines.index("```mermaid")
    return lines[start + 2 : lines.index("```", start + 1)]


def test_panda_card_has_the_robot_tree_joints_actions_keyframes_and_cameras(
    tmp_path: Path,
) -> None:
    text = card(PANDA_SPEC, tmp_path / "panda.md")
    assert text.startswith("# rs_panda\n")
    titles = [li for li in text.splitlines() if li.startswith("## ")]
    assert titles == [
        "## Kinematic tree",
        "## Active joints",
        "## Action layout",
        "## Keyframes",
        "## Cameras",
    ]
    assert "| description | urdf: `{maniskill_assets}/robots/panda/panda_v2.urdf` |" in text
    assert "graph TD" in text


def test_tree_has_a_node_per_link_and_an_edge_per_joint_thick_for_active_ones(
    tmp_path: Path,
) -> None:
    compiled = compile_spec(PANDA_SPEC)
    assert compiled.description is not None
    description = compiled.description
    lines = mermaid(card(PANDA_SPEC, tmp_path / "panda.md"))
    nodes = [li for li in lines if re.fullmatch(r'  \w+\["[^"]*"\]', li)]
    edges = [li for li in lines if "--" in li or "==" in li]
    assert len(nodes) == len(description.links)
    assert len(edges) == len(description.joints)
    assert len([e for e in edges if "==>" in e]) == len(description.active_joint_names)
    assert '  l_panda_link3 ==>|"panda_joint4 (revolute)"| l_panda_link4' in lines
    assert '  l_panda_hand -->|"panda_hand_tcp_joint (fixed)"| l_panda_hand_tcp' in lines


def test_node_ids_are_sanitized_and_unique_and_labels_escaped() -> None:
    ids = node_ids(["a-b", "a_b", "end", 'x "y" <z>'])
    assert all(re.fullmatch(r"[A-Za-z0-9_]+", i) for i in ids.values())
    assert len(set(ids.values())) == 4
    assert mermaid_label('say "hi" <b> | & more') == "say #quot;hi#quot; #lt;b#gt; #124; #amp; more"


def test_odd_link_names_become_safe_mermaid(tmp_path: Path) -> None:
    urdf = tmp_path / "odd.urdf"
    urdf.write_text(
        '<robot name="odd"><link name="base &quot;0&quot;"/><link name="tip|&lt;1&gt;"/>'
        '<joint name="j &amp; k" type="revolute"><parent link="base &quot;0&quot;"/>'
        '<child link="tip|&lt;1&gt;"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
        "</joint></robot>\n"
    )
    spec = tmp_path / "odd.yaml"
    result = run_new(urdf, spec, None, force=False, simulate=False).write()
    assert not result.failed, result.diagnostics
    lines = mermaid(card(spec, tmp_path / "odd.md"))
    assert lines == [
        '  l_base__0_["base #quot;0#quot;"]',
        '  l_tip__1_["tip#124;#lt;1#gt;"]',
        '  l_base__0_ ==>|"j #amp; k (revolute)"| l_tip__1_',
    ]


def test_action_layout_lists_each_dimension_with_bounds_and_normalization(tmp_path: Path) -> None:
    text = card(PANDA_SPEC, tmp_path / "panda.md")
    rows = section(text, "## Action layout")
    delta = rows[rows.index("### pd_joint_delta_pos (8 dims)") :]
    assert delta[4] == (
        "| 0 | `arm` | `arm_delta_pos` (pd_joint_pos) | `panda_joint1` | -0.1 | 0.1 | yes |"
    )
    assert delta[11] == (
        "| 7 | `gripper` | `gripper` (pd_joint_pos_mimic) | `panda_finger_joint1` "
        "| -0.01 | 0.04 | yes |"
    )
    ee = rows[rows.index("### pd_ee_delta_pose (7 dims)") :]
    assert ee[7] == (
        "| 3 | `arm` | `arm_ee_delta_pose` (pd_ee_pose) | `arm.rx` | -0.1 | 0.1 | yes |"
    )
    absolute = rows[rows.index("### pd_joint_pos (8 dims)") :]
    assert "| 3 | `arm` | `arm_pos` (pd_joint_pos) | `panda_joint4` | -3.0718 | -0.0698 | no |" in (
        absolute
    )


def test_keyframes_table_has_a_value_per_joint_and_cameras_their_mount_and_lens(
    tmp_path: Path,
) -> None:
    text = card(MANISKILL_SPECS / "panda_wristcam.yaml", tmp_path / "p.md")
    keyframes = section(text, "## Keyframes")
    assert "| `panda_joint4` | -1.9635 |" in keyframes  # -5π/8
    assert "| pose p | [0, 0, 0] |" in keyframes
    cameras = [li for li in section(text, "## Cameras") if li.startswith("| `")]
    assert len(cameras) == 1
    assert cameras[0].startswith("| `hand_camera` | `camera_link` |")
    assert "128×128" in cameras[0]


def test_card_is_deterministic_and_names_no_machine_path(tmp_path: Path) -> None:
    spec = tmp_path / "specs" / "fetch.yaml"
    spec.parent.mkdir()
    spec.write_text((MANISKILL_SPECS / "fetch.yaml").read_text())
    first = card(spec, tmp_path / "cards" / "a.md")
    second = card(spec, tmp_path / "cards" / "b.md")
    assert first == second
    assert "(<../specs/fetch.yaml>)" in first
    assert str(tmp_path) not in first and "site-packages" not in first


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_spec_with_errors_gets_diagnostics_and_no_card(tmp_path: Path) -> None:
    spec = tmp_path / "bad.yaml"
    run_new(
        ROOT / "specs/robots/twolink/twolink.urdf.xacro", spec, None, force=False, simulate=False
    ).write()
    lines = spec.read_text().splitlines()
    line = next(i for i, text in enumerate(lines) if text.startswith("  arm: ["))
    lines[line] = lines[line].replace("twolink_joint3", "twolink_joint9")
    spec.write_text("\n".join(lines) + "\n")
    out = tmp_path / "bad.md"
    result = run_robospec("doc", str(spec), "-o", str(out))
    assert result.returncode == 1
    assert f"{spec}:{line + 1}:" in result.stderr and "error[RS201]" in result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists()
    out.write_text("old card\n")
    assert run_robospec("doc", str(spec), "-o", str(out)).returncode == 1
    assert out.read_text() == "old card\n"


def test_doc_command_writes_the_card_linking_to_the_spec(tmp_path: Path) -> None:
    out = tmp_path / "cards" / "panda.md"
    result = run_robospec("doc", str(PANDA_SPEC), "-o", str(out))
    assert result.returncode == 0, result.stderr
    text = out.read_text()
    assert text == card(PANDA_SPEC, tmp_path / "cards" / "again.md")
    (link,) = re.findall(r"\| spec \| \[`[^`]*`\]\(<([^>]*)>\) \|", text)
    assert (out.parent / link).resolve() == PANDA_SPEC.resolve()


def test_doc_without_out_writes_the_card_named_after_the_spec_where_it_is_run(
    tmp_path: Path,
) -> None:
    result = run_robospec("doc", str(PANDA_SPEC), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "wrote panda.md" in result.stdout + result.stderr
    assert (tmp_path / "panda.md").read_text() == card(PANDA_SPEC, tmp_path / "again.md")


# -- the static layout equals ManiSkill's live controllers -----------------------------------


@pytest.mark.usefixtures("maniskill")
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize(
    "spec",
    [
        *(
            MANISKILL_SPECS / name
            for name in (
                "panda.yaml",
                "fetch.yaml",
                "allegro_hand_right.yaml",
                "fixed_inspire_hand_right.yaml",
            )
        ),
        ROOT / "docs/examples/tutorial/my_mobile_base.yaml",  # pd_base_vel: base.vx, vy, wz
    ],
    ids=lambda path: path.name,
)
def test_static_action_layout_equals_the_live_controllers_in_every_mode(spec: Path) -> None:
    import numpy as np

    from robospec import register
    from robospec.physics import action_layout
    from robospec.physics.check_run import CheckRun
    from robospec.physics.findings import METRIC_DIGITS, significant

    compiled = compile_spec(spec)
    assert compiled.robot is not None and compiled.context is not None
    assert compiled.description is not None
    register(spec)
    run = CheckRun(compiled.robot.uid, compiled.context, compiled.context.spec.checks)
    try:
        broken = run.open_modes()  # modes this ManiSkill cannot build leave the run
        live = {f.mode: f.details for f in action_layout.check(run)}
    finally:
        run.close()
    assert set(broken) == CRASHING_MODES.get(spec.stem, frozenset())
    assert set(live) == {m.name for m in compiled.robot.modes} - set(broken)
    for mode in (m for m in compiled.robot.modes if m.name in live):
        static = [
            (
                r.index,
                r.group,
                r.target,
                significant(float(np.float32(r.low)), METRIC_DIGITS),
                significant(float(np.float32(r.high)), METRIC_DIGITS),
                r.normalized,
            )
            for r in mode_layout(compiled.robot, compiled.description, mode)
        ]
        actual = [
            (d["index"], d["group"], d["target"], d["low"], d["high"], d["normalized"])
            for d in live[mode.name]
        ]
        assert static == actual, mode.name
    if spec.stem == "my_mobile_base":  # a base's velocities are labelled, not its joints
        first = mode_layout(compiled.robot, compiled.description, compiled.robot.modes[0])
        assert [row.target for row in first[:3]] == ["base.vx", "base.vy", "base.wz"]


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_unwritable_card_is_rs603_and_exit_1(tmp_path: Path) -> None:
    spec = tmp_path / "twolink.yaml"
    run_new(
        ROOT / "specs/robots/twolink/twolink.urdf.xacro", spec, None, force=False, simulate=False
    ).write()
    (tmp_path / "afile").write_text("")
    out = tmp_path / "afile" / "card.md"
    result = run_robospec("doc", str(spec), "-o", str(out))
    assert result.returncode == 1
    assert f"{out}:1:1: error[RS603] cannot write {out}" in result.stderr
    assert "Traceback" not in result.stderr


def test_doc_plots_links_the_step_plots_check_and_tune_wrote_for_this_robot(
    tmp_path: Path,
) -> None:
    # check --plot / tune --plot write DIR/<uid>/<controller>.png; a controller without a
    # picture, and another robot's, are not linked
    plots = tmp_path / "plots"
    (plots / "rs_panda").mkdir(parents=True)
    (plots / "rs_panda" / "arm_pos.png").write_bytes(b"\x89PNG")
    (plots / "rs_other").mkdir()
    (plots / "rs_other" / "arm_delta_pos.png").write_bytes(b"\x89PNG")
    out = tmp_path / "cards" / "panda.md"
    result = run_robospec("doc", str(PANDA_SPEC), "-o", str(out), "--plots", str(plots))
    assert result.returncode == 0, result.stderr
    links = re.findall(r"!\[([^\]]*)\]\(([^)]*)\)", out.read_text())
    assert links == [("arm_pos step response", "../plots/rs_panda/arm_pos.png")]
    assert (out.parent / links[0][1]).resolve() == (plots / "rs_panda" / "arm_pos.png").resolve()


@pytest.mark.slow  # draws the robot (seconds)
def test_doc_images_lists_every_file_it_wrote(tmp_path: Path) -> None:
    """The card, then each picture: what a reader opens next, not the card's name alone."""
    out = tmp_path / "panda.md"
    result = run_robospec("doc", str(PANDA_SPEC), "-o", str(out), "--images")
    assert result.returncode == 0, result.stderr
    said = result.stdout.splitlines()
    pictures = sorted(str(p) for p in (tmp_path / "panda_images").rglob("*.png"))
    assert pictures
    assert said[0] == f"wrote {out}"
    assert sorted(said[1:]) == [f"wrote {p}" for p in pictures]
