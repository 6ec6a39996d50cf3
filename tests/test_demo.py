"""scripts/demo, the README's main job, reads well: one line per robot of what it ran, its
verdict as robospec check would give it and what became of the robot, in a stated order; the
cause when a robot's state goes NaN or runs away, and whether ManiSkill's own agent does the
same; what ManiSkill and SAPIEN printed told once per distinct message, with a count and what
it means; and last, what was built and what to do next."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MANISKILL_SPECS, ROOT

pytestmark = pytest.mark.maniskill

# an inspire hand goes NaN (URDF <mimic> tags left to PhysX), as ManiSkill's own does; the
# Allegro hand runs away, as ManiSkill's own does; the G1 loads its STL collision meshes with
# load_multiple_collisions (one SAPIEN warning per mesh); ManiSkill's own logger warns about the
# floating Panda gripper's mimic controller (a logger made while the demo captured output,
# which once ended in "--- Logging error ---"); the Panda just runs; the Ability hand of
# specs/composed goes NaN with no agent of ManiSkill's on its description: a failure
SPECS = [
    "fixed_inspire_hand_right",
    "allegro_hand_right",
    "unitree_g1",
    "floating_panda_gripper",
    "panda",
]
COMPOSED = "ability_hand_right"


def _specs(folder: Path) -> list[Path]:
    """The specs the demo runs; the inspire hand's copy without its keyframe, so that it starts
    each episode as SAPIEN builds it (every joint at 0), as ManiSkill's own hand does in
    Empty-v1 (from its keyframe, whose mimic joints stand where their tags put them, it stays
    finite over these steps)."""
    specs = [MANISKILL_SPECS / f"{name}.yaml" for name in SPECS]
    hand = specs[0].read_text(encoding="utf-8")
    keyframes = re.search(r"^keyframes:\n(?:(?: .*)?\n)+", hand, flags=re.M)
    assert keyframes is not None
    specs[0] = folder / specs[0].name
    specs[0].write_text(hand.replace(keyframes.group(0), ""), encoding="utf-8")
    return specs


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> subprocess.CompletedProcess[str]:
    out = tmp_path_factory.mktemp("demo") / "demo_agents"
    specs = _specs(tmp_path_factory.mktemp("specs"))
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "robospec.demo.tour",
            *(str(spec) for spec in specs),
            str(ROOT / "specs" / "composed" / f"{COMPOSED}.yaml"),
            "-o",
            str(out),
            "--steps",
            "10",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
        env={**os.environ, "ROBOSPEC_CACHE_DIR": str(tmp_path_factory.mktemp("cache"))},
    )


def _robot_rows(demo: subprocess.CompletedProcess[str]) -> dict[str, str]:
    """The table's rows, by robot."""
    return {
        line.split(" ", 1)[0]: line
        for line in demo.stdout.splitlines()
        if line.startswith("rs_") and re.search(r"  (ok|as ManiSkill|fails)  ", line)
    }


def test_the_demo_says_per_robot_what_it_ran_and_what_became_of_it_in_a_table(
    demo: subprocess.CompletedProcess[str],
) -> None:
    assert demo.returncode == 0, demo.stdout[-3000:] + demo.stderr[-3000:]
    rows = _robot_rows(demo)
    assert set(rows) == {f"rs_{name}" for name in [*SPECS, COMPOSED]}
    assert "10 random actions in each robot's default control mode, on physx_cpu" in demo.stdout
    assert rows["rs_panda"].split()[1:6] == ["11", "pd_joint_delta_pos", "8", "ok", "fastest"]
    assert "state NaN at step" in rows["rs_fixed_inspire_hand_right"]
    assert "  ok  " in rows["rs_floating_panda_gripper"]
    # one column each: the table's cells line up under its header
    header = next(line for line in demo.stdout.splitlines() if line.startswith("robot "))
    column = header.index("what became of it")
    assert all(row[column - 2 : column] == "  " for row in rows.values())


def test_the_demo_is_short_and_has_no_traceback(demo: subprocess.CompletedProcess[str]) -> None:
    said = demo.stdout + demo.stderr
    for fragment in ("Traceback", "Logging error", 'File "', "Call stack:", "closed file"):
        assert fragment not in said, said
    # the validation warnings are counted, not shown (robospec validate shows them)
    assert "hint:" not in said and "warning[RS" not in said
    assert "10 warning(s) (RS309 x10): `" in demo.stdout
    assert " validate " in demo.stdout.split("warning(s)", 1)[1].split("\n", 1)[0]
    # the notes are wrapped to fit a terminal
    assert all(len(line) <= 100 for line in _notes(demo).splitlines()), _notes(demo)
    assert len(said.splitlines()) <= 60, said
    # ManiSkill's logger is heard, told once like everything upstream says
    assert "mani_skill warning (1x): Mimic targets dictionary is missing" in demo.stdout


def _notes(demo: subprocess.CompletedProcess[str]) -> str:
    """The numbered notes under the table, as printed."""
    lines = demo.stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("[1] "))
    end = next(i for i in range(start, len(lines)) if not lines[i].strip())
    return "\n".join(lines[start:end])


def _note(demo: subprocess.CompletedProcess[str], uid: str) -> str:
    """The note a robot's row points at, its lines joined."""
    number = _robot_rows(demo)[uid].rsplit("[", 1)[1].rstrip("]")
    notes = re.split(r"\n(?=\[\d+\] )", _notes(demo))
    (note,) = [n for n in notes if n.startswith(f"[{number}] ")]
    return " ".join(part.strip() for part in note.splitlines())


def test_the_table_is_in_its_stated_order_fine_then_as_maniskill_then_failures(
    demo: subprocess.CompletedProcess[str],
) -> None:
    assert "then those that behave as ManiSkill's own agent does, then failures; by uid" in (
        demo.stdout.replace("\n", " ")
    )
    rows = list(_robot_rows(demo).items())
    order = ["ok", "as ManiSkill", "fails"]
    keys = [(order.index(next(v for v in order if f"  {v}  " in line)), uid) for uid, line in rows]
    assert keys == sorted(keys)
    assert [k for k, _ in keys] == [0, 0, 0, 1, 1, 2]


def test_a_runaway_is_judged_as_check_judges_it_with_units_and_as_maniskill_does(
    demo: subprocess.CompletedProcess[str],
) -> None:
    """The Allegro hand's joints fly hundreds of radians past their limits: not "finite", but
    what check fails it for (RS503, RS504), and what ManiSkill's own Allegro does too."""
    row = _robot_rows(demo)["rs_allegro_hand_right"]
    assert re.search(r"  as ManiSkill +runs away: joint_", row) and " rad past its limit [" in row
    note = _note(demo, "rs_allegro_hand_right")
    assert "runs away under random actions, which robospec check fails: joint_" in note
    assert "(joint_limit_tolerance 0.1 rad)" in note and "(max_joint_speed 200 rad/s)" in note
    assert (
        "ManiSkill's own agent 'allegro_hand_right', with the same description, runs away too"
        in note
    )
    assert "rs_allegro_hand_right reproduces ManiSkill's behaviour" in note
    assert "finite" not in demo.stdout


def test_a_robot_that_fails_on_its_own_is_a_failure_with_its_cause(
    demo: subprocess.CompletedProcess[str],
) -> None:
    row = _robot_rows(demo)[f"rs_{COMPOSED}"]
    assert re.search(r"  fails +state NaN at step", row), row
    note = _note(demo, f"rs_{COMPOSED}")
    assert "why: the URDF's 4 <mimic> tags (" in note and "reproduces" not in note
    assert f" check {ROOT / 'specs' / 'composed' / COMPOSED}.yaml` says how to mend it" in note


def test_the_demo_ends_with_what_was_built_and_three_commands_that_run_from_here(
    demo: subprocess.CompletedProcess[str],
) -> None:
    tail = demo.stdout.rstrip("\n").split("\n\nBuilt ", 1)[1].splitlines()
    assert tail[0].startswith(f"{demo.args[-3]}/: {len(SPECS) + 1} agents, registered by")
    commands = [line.strip() for line in tail if line.startswith("  ") and not line[2] == " "]
    assert [c.split()[1] for c in commands] == ["validate", "check", "serve"]
    # the one failure of its own is the robot to look at next
    assert commands[1].endswith(f"specs/composed/{COMPOSED}.yaml")
    for line in commands:
        program = line.split()[0]
        assert Path(program).is_file() or shutil.which(program), line


def test_a_robot_that_goes_nan_as_maniskills_own_is_labelled_so_and_says_why(
    demo: subprocess.CompletedProcess[str],
) -> None:
    row = _robot_rows(demo)["rs_fixed_inspire_hand_right"]
    assert re.search(r"  as ManiSkill +state NaN", row), row
    note = _note(demo, "rs_fixed_inspire_hand_right")
    assert (
        "ManiSkill's own agent 'fixed_inspire_hand_right', with the same description, goes NaN "
        "too (NaN at step " in note
    )
    assert "rs_fixed_inspire_hand_right reproduces ManiSkill's behaviour" in note
    assert "why: the URDF's 6 <mimic> tags (inspire_hand_right.urdf:" in note
    assert "SAPIEN turns them into PhysX mimic joints, which alone go NaN on the CPU" in note
    assert "finite=False" not in demo.stdout


def test_sapien_and_maniskill_output_is_told_once_per_message_with_a_count_and_a_meaning(
    demo: subprocess.CompletedProcess[str],
) -> None:
    # nothing raw: no SAPIEN log line, no Python warning with its source line
    for line in (demo.stdout + demo.stderr).splitlines():
        assert not line.startswith("[20"), line
        assert "UserWarning:" not in line, line
    told = demo.stdout.split("ManiSkill and SAPIEN said, each message once:\n", 1)[1]
    told = told.split("\n\n", 1)[0]
    # one message a paragraph, wrapped: its continuation lines indented deeper
    messages = re.split(r"\n(?=  \S)", told)
    joined = [" ".join(part.strip() for part in m.splitlines()) for m in messages]
    stl = [line for line in joined if "convex collision meshes from STL" in line]
    assert len(stl) == 1, told
    (line,) = stl
    assert line.strip().startswith("SAPIEN warning (")
    assert "x): " in line and "convex hull" in line and "[rs_unitree_g1]" in line
    count = int(line.split("(", 1)[1].split("x)", 1)[0])
    assert count > 10  # one per collision mesh of the G1


def test_scripts_demo_runs_this_module() -> None:
    script = (ROOT / "scripts" / "demo").read_text()
    assert "python -m robospec.demo.tour" in script
    assert Path(ROOT / "scripts" / "demo").stat().st_mode & 0o111
