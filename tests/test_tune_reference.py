"""robospec tune --reference, what needs no simulation: reading a recorded trajectory (CSV and
NPZ) and every way a reference or the command line can be wrong, each a located diagnostic and
exit 2 before anything is simulated (never a traceback)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from robospec.tune.reference.command import reference_report
from robospec.tune.reference.trajectory import read_reference
from tests.conftest import PANDA_SPEC

ARM = tuple(f"panda_joint{i}" for i in range(1, 8))


def _csv(path: Path, header: str, rows: list[str]) -> Path:
    path.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    return path


def _moving_csv(path: Path, joints: tuple[str, ...] = ("panda_joint1",)) -> Path:
    header = ", ".join(["t", *(f"target:{j}, qpos:{j}" for j in joints)])
    rows = []
    for k in range(20):
        cells = [f"{k * 0.01:.2f}"]
        for _ in joints:
            cells += ["0.1", f"{0.1 * (1 - np.exp(-k / 5)):.6f}"]
        rows.append(", ".join(cells))
    return _csv(path, header, rows)


def test_a_csv_reference_reads_joints_by_their_column_names(tmp_path: Path) -> None:
    reference, problems = read_reference(_moving_csv(tmp_path / "r.csv", ARM[:2]))
    assert problems == [] and reference is not None
    assert reference.joints == ARM[:2]
    assert reference.target.shape == reference.qpos.shape == (20, 2)
    assert reference.location("panda_joint2").column == 65  # its qpos column in the header


def test_an_npz_reference_reads_its_four_arrays(tmp_path: Path) -> None:
    t = np.arange(20) * 0.01
    np.savez(
        tmp_path / "r.npz", t=t, target=np.ones((20, 2)), qpos=np.zeros((20, 2)), joints=ARM[:2]
    )
    reference, problems = read_reference(tmp_path / "r.npz")
    assert problems == [] and reference is not None and reference.joints == ARM[:2]


@pytest.mark.parametrize(
    ("header", "rows", "code", "line", "column"),
    [
        ("t, target:a, qpos:a, speed:a", ["0, 1, 2, 3"] * 12, "RS641", 1, 22),  # unknown column
        ("t, target:a", ["0, 1"] * 12, "RS641", 1, 4),  # a target without its qpos
        ("time_s, target:a, qpos:a", ["0, 1, 2"] * 12, "RS641", 1, 1),  # no time column
        ("t, target:a, qpos:a", ["0, 1, 2", "0.01, x, 2"], "RS641", 3, 7),  # not a number
        ("t, target:a, qpos:a", ["0, 1, 2", "0.01, 1, nan"], "RS642", 3, 10),  # NaN
        ("t, target:a, qpos:a", ["0, 1, 2", "0.01, 1"], "RS641", 3, 1),  # a short row
    ],
)
def test_a_malformed_csv_is_located_at_the_cell(
    tmp_path: Path, header: str, rows: list[str], code: str, line: int, column: int
) -> None:
    reference, problems = read_reference(_csv(tmp_path / "r.csv", header, rows))
    assert reference is None
    assert [(d.code, d.location.line, d.location.column) for d in problems][:1] == [
        (code, line, column)
    ]


def test_time_going_backwards_or_too_few_samples_is_rs643(tmp_path: Path) -> None:
    rows = [f"{0.01 * k}, 0, 0" for k in range(12)]
    rows[5] = "0.01, 0, 0"
    _, problems = read_reference(_csv(tmp_path / "r.csv", "t, target:a, qpos:a", rows))
    assert [d.code for d in problems] == ["RS643"] and "sample 5" in problems[0].message
    _, problems = read_reference(_csv(tmp_path / "s.csv", "t, target:a, qpos:a", rows[:3]))
    assert [d.code for d in problems] == ["RS643"]


def test_an_npz_with_missing_arrays_wrong_shapes_or_nan_says_which(tmp_path: Path) -> None:
    t = np.arange(20) * 0.01
    np.savez(tmp_path / "a.npz", t=t, target=np.zeros((20, 1)), joints=["a"])
    np.savez(
        tmp_path / "b.npz", t=t, target=np.zeros((20, 2)), qpos=np.zeros((20, 1)), joints=["a"]
    )
    bad = np.zeros((20, 1))
    bad[7, 0] = np.nan
    np.savez(tmp_path / "c.npz", t=t, target=np.zeros((20, 1)), qpos=bad, joints=["a"])
    found = {name: read_reference(tmp_path / name)[1] for name in ("a.npz", "b.npz", "c.npz")}
    assert [d.code for d in found["a.npz"]] == ["RS641"] and "qpos" in found["a.npz"][0].message
    assert any("target has shape (20, 2)" in d.message for d in found["b.npz"])
    assert [d.code for d in found["c.npz"]] == ["RS642"] and "qpos[7, 0]" in found["c.npz"][
        0
    ].message


def test_a_missing_or_unknown_kind_of_file_is_rs640(tmp_path: Path) -> None:
    assert read_reference(tmp_path / "none.csv")[1][0].code == "RS640"
    (tmp_path / "r.json").write_text("{}", encoding="utf-8")
    assert read_reference(tmp_path / "r.json")[1][0].code == "RS640"
    (tmp_path / "broken.npz").write_bytes(b"not a zip")
    assert read_reference(tmp_path / "broken.npz")[1][0].code == "RS640"


def _report(tmp_path: Path, reference: str, *controllers: str) -> tuple[int, dict]:
    code, text = reference_report(
        PANDA_SPEC, None, reference, list(controllers), False, None, "json"
    )
    return code, json.loads(text)


def test_a_joint_the_robot_lacks_is_rs644_at_its_column_with_a_suggestion(tmp_path: Path) -> None:
    path = _moving_csv(tmp_path / "r.csv", ("panda_joint1", "panda_joint_2"))
    code, report = _report(tmp_path, str(path))
    assert code == 2
    (found,) = [d for d in report["diagnostics"] if d["code"] == "RS644"]
    assert (found["file"], found["line"], found["column"]) == (str(path), 1, 66)
    assert "panda_joint2" in found["hint"]


def test_a_joint_no_chosen_controller_drives_is_rs645(tmp_path: Path) -> None:
    path = _moving_csv(tmp_path / "r.csv", ("panda_joint1", "panda_finger_joint1"))
    code, report = _report(tmp_path, str(path), "arm_pos")
    assert code == 2
    assert [d["code"] for d in report["diagnostics"]] == ["RS645"]
    assert "panda_finger_joint1" in report["diagnostics"][0]["message"]
    code, report = _report(tmp_path, str(path), "no_such_controller")
    assert code == 2 and report["diagnostics"][0]["code"] == "RS645"


def test_a_joint_that_does_not_move_is_rs646(tmp_path: Path) -> None:
    rows = [f"{0.01 * k}, 0.1, 0.0" for k in range(20)]
    path = _csv(tmp_path / "r.csv", "t, target:panda_joint1, qpos:panda_joint1", rows)
    code, report = _report(tmp_path, str(path))
    assert code == 2 and [d["code"] for d in report["diagnostics"]] == ["RS646"]


def test_mujoco_for_a_urdf_robot_is_a_usage_error_rs647(tmp_path: Path) -> None:
    code, report = _report(tmp_path, "mujoco")
    assert code == 2 and [d["code"] for d in report["diagnostics"]] == ["RS647"]
    assert report["status"] == "error"


def test_mujoco_for_a_compiled_mjcf_reads_the_mjcf_the_spec_names(tmp_path: Path) -> None:
    """``loader: mujoco`` resolves to the URDF MuJoCo's model is written as; --reference mujoco
    still reads the MJCF the spec names (here: one with no position actuator, RS647 at it)."""
    mjcf = Path(__file__).parent / "data" / "mjcf" / "compiled" / "ball_ghost.xml"
    spec = tmp_path / "ball_ghost.yaml"
    spec.write_text(
        "robospec: 1\nuid: rs_ball_ghost_mj\n"
        f'description: {{mjcf: "{mjcf.as_posix()}", loader: mujoco}}\n'
        'groups: {all: "*"}\n'
        "controllers:\n  all: {type: pd_joint_pos, joints: all, lower: null, upper: null,\n"
        "    stiffness: 100, damping: 10, normalize_action: false}\n"
        "control_modes:\n  pd_joint_pos: {all: all}\n",
        encoding="utf-8",
    )
    code, text = reference_report(spec, None, "mujoco", [], False, None, "json")
    report = json.loads(text)
    found = [d for d in report["diagnostics"] if d["code"] == "RS647"]
    assert code == 2 and len(found) == 1, report["diagnostics"]
    assert found[0]["file"] == str(mjcf) and "no position actuator" in found[0]["message"]
