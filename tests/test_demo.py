"""scripts/demo, the README's main job, reads well: one line per robot of what it ran and what
became of the robot, the cause when a robot's state goes NaN, and what ManiSkill and SAPIEN
printed told once per distinct message, with a count and what it means."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MANISKILL_SPECS, ROOT

pytestmark = pytest.mark.maniskill

# an inspire hand goes NaN (URDF <mimic> tags left to PhysX); the G1 loads its STL collision
# meshes with load_multiple_collisions (one SAPIEN warning per mesh); ManiSkill's own logger
# warns about the floating Panda gripper's mimic controller (a logger made while the demo
# captured output, which once ended in "--- Logging error ---"); the Panda just runs
SPECS = ["fixed_inspire_hand_right", "unitree_g1", "floating_panda_gripper", "panda"]


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
        if line.startswith("rs_") and ("finite;" in line or "NaN at step" in line)
    }


def test_the_demo_says_per_robot_what_it_ran_and_what_became_of_it_in_a_table(
    demo: subprocess.CompletedProcess[str],
) -> None:
    assert demo.returncode == 0, demo.stdout[-3000:] + demo.stderr[-3000:]
    rows = _robot_rows(demo)
    assert set(rows) == {f"rs_{name}" for name in SPECS}
    assert "10 random actions in each robot's default control mode, on physx_cpu:" in demo.stdout
    assert rows["rs_panda"].split()[1:5] == ["11", "pd_joint_delta_pos", "8", "finite;"]
    assert "state NaN at step" in rows["rs_fixed_inspire_hand_right"]
    assert "finite;" in rows["rs_floating_panda_gripper"]
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
    assert "6 warning(s) (RS309 x6): `robospec validate " in demo.stdout
    assert len(said.splitlines()) <= 26, said
    # ManiSkill's logger is heard, told once like everything upstream says
    assert "mani_skill warning (1x): Mimic targets dictionary is missing" in demo.stdout


def test_a_robot_that_goes_nan_as_maniskills_own_is_labelled_so_and_says_why(
    demo: subprocess.CompletedProcess[str],
) -> None:
    row = _robot_rows(demo)["rs_fixed_inspire_hand_right"]
    number = row.rsplit("[", 1)[1].rstrip("]")
    note = next(line for line in demo.stdout.splitlines() if line.startswith(f"[{number}] "))
    assert (
        "ManiSkill's own agent 'fixed_inspire_hand_right', with the same description, goes NaN "
        "too (step " in note
    )
    assert "rs_fixed_inspire_hand_right reproduces ManiSkill's behaviour" in note
    assert "why: the URDF <mimic> tags (" in note
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
    stl = [line for line in told.splitlines() if "convex collision meshes from STL" in line]
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
