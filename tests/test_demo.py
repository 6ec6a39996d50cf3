"""scripts/demo, the README's main job, reads well: one line per robot of what it ran and what
became of the robot, the cause when a robot's state goes NaN, and what ManiSkill and SAPIEN
printed told once per distinct message, with a count and what it means."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MANISKILL_SPECS, ROOT

pytestmark = pytest.mark.maniskill

# an inspire hand goes NaN (URDF <mimic> tags left to PhysX); the G1 loads its STL collision
# meshes with load_multiple_collisions (one SAPIEN warning per mesh); the Panda just runs
SPECS = ["fixed_inspire_hand_right", "unitree_g1", "panda"]


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> subprocess.CompletedProcess[str]:
    out = tmp_path_factory.mktemp("demo") / "demo_agents"
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "robospec.maniskill.demo",
            *(str(MANISKILL_SPECS / f"{name}.yaml") for name in SPECS),
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


def _robot_lines(demo: subprocess.CompletedProcess[str]) -> dict[str, str]:
    return {
        line.split(" ", 1)[0]: line
        for line in demo.stdout.splitlines()
        if line.startswith("rs_") and "control modes" in line
    }


def test_the_demo_says_per_robot_what_it_ran_and_what_became_of_it(
    demo: subprocess.CompletedProcess[str],
) -> None:
    assert demo.returncode == 0, demo.stdout[-3000:] + demo.stderr[-3000:]
    lines = _robot_lines(demo)
    assert set(lines) == {f"rs_{name}" for name in SPECS}
    assert "10 random steps on physx_cpu: every joint finite, the most moved" in lines["rs_panda"]
    assert "the state went NaN at step" in lines["rs_fixed_inspire_hand_right"]


def test_a_robot_that_goes_nan_because_of_its_description_says_why(
    demo: subprocess.CompletedProcess[str],
) -> None:
    lines = demo.stdout.splitlines()
    hand = next(i for i, line in enumerate(lines) if line.startswith("rs_fixed_inspire_hand"))
    why = lines[hand + 1].strip()
    assert why.startswith("why: the URDF <mimic> tags (")
    assert "SAPIEN turns them into PhysX mimic joints, which alone go NaN on the CPU" in why
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
    assert "python -m robospec.maniskill.demo" in script
    assert Path(ROOT / "scripts" / "demo").stat().st_mode & 0o111
