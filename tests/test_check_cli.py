"""The ``robospec check`` and ``robospec demo`` command lines: exit codes, JSON and text output,
located diagnostics instead of tracebacks, and the options that need hardware this machine may
lack (``--gpu``, ``--render``, a display for ``demo``).

Runs that load robots go through the typer app in this process (conftest.invoke_robospec: SAPIEN
is imported once); the ones that fail before any robot loads run the command in a child process.
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import (
    INSTALL_MANISKILL,
    MISSPELLED_JOINT_SPEC,
    PANDA_SPEC,
    ROOT,
    invoke_robospec,
    maniskill_assets,
    run_robospec,
)

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]


@pytest.fixture(scope="module")
def registry(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A folder for specs; the agents the in-process runs register are unregistered after."""
    from mani_skill.agents.registration import REGISTERED_AGENTS

    if not (maniskill_assets() / "robots/panda/panda_v2.urdf").is_file():
        pytest.fail(f"ManiSkill's panda is not installed: {INSTALL_MANISKILL}")
    agents, modules = set(REGISTERED_AGENTS), set(sys.modules)
    yield tmp_path_factory.mktemp("check_cli")
    for uid in set(REGISTERED_AGENTS) - agents:
        del REGISTERED_AGENTS[uid]
    for name in set(sys.modules) - modules:
        if name.startswith("robospec_agents."):
            del sys.modules[name]


@pytest.fixture(scope="module")
def soft_panda(registry: Path) -> Path:
    """The Panda with one mode, pd_joint_pos, whose arm has stiffness 1 (too slow: RS505)."""
    text = PANDA_SPEC.read_text(encoding="utf-8")
    head, _, _ = text.partition("controllers:")
    path = registry / "soft_panda.yaml"
    path.write_text(
        head.replace("uid: rs_panda", "uid: rs_cli_soft_panda")
        + """controllers:
  arm_pos:
    {type: pd_joint_pos, joints: arm, lower: null, upper: null,
     stiffness: 1, damping: 1e2, force_limit: 100, normalize_action: false}
  gripper:
    {type: pd_joint_pos_mimic, joints: gripper, lower: -0.01, upper: 0.04, stiffness: 1e3,
     damping: 1e2, force_limit: 100, mimic: {panda_finger_joint2: panda_finger_joint1}}
control_modes:
  pd_joint_pos: {arm: arm_pos, gripper: gripper}
""",
        encoding="utf-8",
    )
    return path


def invoke(*args: str):
    return invoke_robospec("check", *args)


def test_check_panda_exits_zero_and_steps_reach_the_json_metrics(registry: Path) -> None:
    result = invoke(str(PANDA_SPEC), "--steps", "5", "--format", "json")
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert report["summary"]["passed"] == 1 and report["summary"]["errors"] == 0
    (robot,) = report["robots"]
    assert (robot["uid"], robot["status"]) == ("rs_panda", "pass")
    stepped = [f for f in robot["findings"] if f["check"] in ("keyframe_hold", "random_actions")]
    assert len(stepped) == 1 + 22
    assert {f["metrics"]["steps"] for f in stepped} == {5}


def test_check_failing_spec_exits_one_with_a_located_diagnostic(soft_panda: Path) -> None:
    result = invoke(str(soft_panda))
    assert result.exit_code == 1
    assert result.exception is None or isinstance(result.exception, SystemExit)
    lines = result.stdout.splitlines()
    assert lines[0] == f"{soft_panda}: rs_cli_soft_panda: FAIL"
    line = 1 + soft_panda.read_text().splitlines().index("  arm_pos:")
    assert any(
        row.startswith(f"{soft_panda}:{line}:3: error[RS505] controller 'arm_pos'") for row in lines
    ), result.stdout
    assert lines[-1].startswith("1 robot(s) checked: 0 passed, 1 failed")


def test_check_default_steps_reach_the_json_metrics(soft_panda: Path) -> None:
    result = invoke(str(soft_panda), "--format", "json")
    assert result.exit_code == 1
    (robot,) = json.loads(result.stdout)["robots"]
    steps = {
        f["check"]: f["metrics"]["steps"] for f in robot["findings"] if "steps" in f["metrics"]
    }
    assert steps == {"keyframe_hold": 50, "random_actions": 60}
    assert robot["status"] == "fail"
    assert [d["code"] for d in robot["diagnostics"]] == ["RS505"]


def test_check_spec_with_a_syntax_error_is_a_located_error_not_a_traceback(
    tmp_path: Path,
) -> None:
    spec = tmp_path / "broken.yaml"
    spec.write_text('robospec: 1\nuid: rs_broken\ndescription: {urdf: "x.urdf"\n')
    result = run_robospec("check", str(spec))
    assert result.returncode == 1
    assert "Traceback" not in result.stdout + result.stderr
    (located,) = [line for line in result.stdout.splitlines() if "error[" in line]
    assert located.startswith(f"{spec}:")
    _, line, column, rest = located.split(":", 3)
    # the mapping never closed, at its brace (RS015)
    assert (int(line), int(column)) == (3, 14) and rest.startswith(" error[RS015]")
    assert "0 passed, 0 failed, 1 not checked" in result.stdout


def test_check_missing_file_is_a_located_error_not_a_traceback(tmp_path: Path) -> None:
    missing = tmp_path / "no_such_spec.yaml"
    result = run_robospec("check", str(missing), "--format", "json")
    assert result.returncode == 1
    assert "Traceback" not in result.stdout + result.stderr
    report = json.loads(result.stdout)
    (diagnostic,) = report["diagnostics"]
    assert (diagnostic["file"], diagnostic["line"], diagnostic["code"]) == (
        str(missing),
        1,
        "RS001",
    )
    assert report["summary"]["errors"] == 1


def test_check_spec_whose_description_is_missing_is_not_checked(tmp_path: Path) -> None:
    spec = tmp_path / "lost.yaml"
    spec.write_text(
        PANDA_SPEC.read_text(encoding="utf-8")
        .replace("uid: rs_panda", "uid: rs_cli_lost")
        .replace("{maniskill_assets}/robots/panda/panda_v2.urdf", "no/such/robot.urdf")
    )
    result = run_robospec("check", str(spec), "--format", "json")
    assert result.returncode == 1
    assert "Traceback" not in result.stdout + result.stderr
    report = json.loads(result.stdout)
    (robot,) = report["robots"]
    assert robot["status"] == "error" and robot["findings"] == []
    errors = [d for d in robot["diagnostics"] if d["severity"] == "error"]
    assert errors and all(d["file"] == str(spec) and d["line"] > 1 for d in errors)
    assert report["summary"]["not_checked"] == 1


def test_check_gpu_without_cuda_is_rs511() -> None:
    import torch

    if torch.cuda.is_available():
        pytest.skip("this machine has a CUDA device")
    result = run_robospec("check", "--gpu", str(PANDA_SPEC))
    assert result.returncode == 1
    assert "Traceback" not in result.stdout + result.stderr
    assert result.stdout.startswith(
        "<command line>:1:1: error[RS511] --gpu needs a CUDA device and this machine has none"
    )
    assert "0 robot(s) checked" in result.stdout


def test_check_render_without_a_render_device_is_rs512(tmp_path: Path) -> None:
    import sapien

    # asked of SAPIEN itself, not of robospec's render_device_error (which RS512 comes from):
    # a detector that broke would otherwise skip this test instead of failing it
    try:
        sapien.render.RenderSystem()
    except RuntimeError:
        pass  # no render device: RS512 is due
    else:
        pytest.skip("this machine has a render device")
    images = tmp_path / "images"
    result = run_robospec("check", "--render", str(images), str(PANDA_SPEC), "--format", "json")
    assert result.returncode == 1
    assert "Traceback" not in result.stdout + result.stderr
    report = json.loads(result.stdout)
    assert [d["code"] for d in report["diagnostics"]] == ["RS512"]
    assert report["diagnostics"][0]["message"].startswith("--render needs a render device")
    assert report["robots"] == [] and not images.exists()


def test_demo_without_a_display_is_rs513_not_a_traceback() -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    result = run_robospec("demo", str(PANDA_SPEC), env=env)
    assert result.returncode == 1
    assert "Traceback" not in result.stdout + result.stderr
    assert "error[RS513] the viewer needs a screen: no display" in result.stderr
    assert result.stderr.startswith(f"{PANDA_SPEC}:1:1: error[RS513]")


def test_demo_unknown_mode_is_rs513_naming_the_modes() -> None:
    result = invoke_robospec(
        "demo",
        str(PANDA_SPEC),
        "-c",
        "pd_no_such_mode",
        env={"DISPLAY": None, "WAYLAND_DISPLAY": None},
    )
    assert result.exit_code == 1
    assert "control mode 'pd_no_such_mode' is not one of: pd_joint_delta_pos, pd_joint_pos" in (
        result.output
    )


def test_check_on_an_invalid_spec_shows_the_diagnostic_as_validate_does() -> None:
    """No `?` for the robot that did not compile, and the source line with its caret."""
    result = run_robospec("check", str(MISSPELLED_JOINT_SPEC.relative_to(ROOT)))
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert lines[0] == "docs/examples/codes/RS201/fail.yaml: not compiled: ERROR"
    at = lines.index(
        "docs/examples/codes/RS201/fail.yaml:6:51: error[RS201] unknown joint 'panda_joint77'"
    )
    assert lines[at + 1].startswith("  6 |   arm: [panda_joint1,")
    assert lines[at + 2].endswith("^" * len("panda_joint77"))
    assert "hint: did you mean 'panda_joint7'?" in lines[at + 3]
