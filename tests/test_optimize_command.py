"""`robospec optimize SPEC -o OUT.yaml` end to end on ManiSkill's Panda: what it writes, what it
keeps, what it refuses to overwrite, and that the optimized robot registers, behaves as the
original under the same actions and passes `robospec check`."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest
import yaml
from conftest import MANISKILL_SPECS, PANDA_SPEC, invoke_robospec

from robospec.optimize.command import run_optimize
from robospec.optimize.options import OptimizeOptions, ShapeMethod
from robospec.optimize.outputs import MARK
from robospec.pipeline import compile_spec

# fewer samples than the default 10,000, enough for the Panda: with 60, pairs that touch under
# random actions pass for never colliding, and the rollouts part by 1.8e-2 rad in 40 steps
QUICK = OptimizeOptions(shapes=ShapeMethod.keep, samples=3000)


@pytest.fixture(scope="module")
def optimized(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Path, object]]:
    out = tmp_path_factory.mktemp("optimized") / "panda_fast.yaml"
    report, diagnostics = run_optimize(PANDA_SPEC, out, QUICK)
    assert report is not None, [d.format_text() for d in diagnostics]
    assert report.never_collide  # the matrix found pairs to declare
    yield out, report


def test_the_optimized_spec_validates_with_the_same_joints_in_the_same_order(
    optimized: tuple[Path, object],
) -> None:
    out, _ = optimized
    before, after = compile_spec(PANDA_SPEC), compile_spec(out)
    assert after.ok, [d.format_text() for d in after.diagnostics]
    assert before.robot is not None and after.robot is not None
    assert after.robot.active_joints == before.robot.active_joints
    assert [m.name for m in after.robot.modes] == [m.name for m in before.robot.modes]
    assert after.robot.uid == "rs_panda_optimized"
    # everything sits beside OUT, marked as robospec's
    assert out.read_text().startswith(f"# {MARK}")
    assert MARK in (out.parent / "panda_fast.urdf").read_text()


def test_every_link_the_spec_names_is_kept_and_only_fixed_links_are_merged(
    optimized: tuple[Path, object],
) -> None:
    out, report = optimized
    before, after = compile_spec(PANDA_SPEC), compile_spec(out)
    assert before.context is not None and after.description is not None
    named = {name for _, name in before.context.bindings.link_names}
    assert named and all(after.description.link(name) is not None for name in named)
    # panda_link8 hangs on the fixed panda_joint8 and nothing names it
    assert report.merged == [("panda_link8", "panda_link7", "panda_joint8")]  # type: ignore[attr-defined]
    assert "panda_hand_tcp" in report.kept  # type: ignore[attr-defined]


def test_keep_pins_a_link_the_spec_does_not_name(tmp_path: Path) -> None:
    options = OptimizeOptions(keep=("panda_link8",), shapes=ShapeMethod.keep, samples=0)
    report, _ = run_optimize(PANDA_SPEC, tmp_path / "kept.yaml", options)
    assert report is not None and report.merged == []


def test_it_never_overwrites_a_file_it_did_not_write(tmp_path: Path) -> None:
    out = tmp_path / "panda_fast.yaml"
    out.write_text("uid: mine\n")
    report, diagnostics = run_optimize(PANDA_SPEC, out, QUICK)
    assert report is None
    assert [(d.code, d.location.file) for d in diagnostics] == [("RS604", str(out))]
    assert out.read_text() == "uid: mine\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["panda_fast.yaml"]  # nothing staged


def test_running_again_replaces_its_own_output(tmp_path: Path) -> None:
    out = tmp_path / "again.yaml"
    options = OptimizeOptions(shapes=ShapeMethod.keep, samples=0)
    first, _ = run_optimize(PANDA_SPEC, out, options)
    text = out.read_text()
    second, diagnostics = run_optimize(PANDA_SPEC, out, options)
    assert first is not None and second is not None, diagnostics
    assert out.read_text() == text  # deterministic
    assert sorted(p.name for p in tmp_path.iterdir()) == ["again.srdf", "again.urdf", "again.yaml"]


def test_an_mjcf_robot_is_not_condensed() -> None:
    result = invoke_robospec(
        "optimize", str(MANISKILL_SPECS / "humanoid.yaml"), "-o", "unused.yaml", "--samples", "0"
    )
    assert result.exit_code == 1
    assert "error[RS607]" in result.output and "MJCF" in result.output
    assert not Path("unused.yaml").exists()


def test_an_mjcf_compiled_by_mujoco_is_condensed_and_keeps_its_armature(tmp_path: Path) -> None:
    """``loader: mujoco``: the robot is the URDF MuJoCo's model is written as, so optimize
    condenses it; the optimized spec names its own URDF (no loader, no MJCF mends) and says the
    joints' armature, which that URDF cannot carry."""
    import shutil

    reference = Path(__file__).parent / "specs" / "reference"
    shutil.copy(reference / "arm3.xml", tmp_path / "arm3.xml")
    text = (reference / "arm3.yaml").read_text(encoding="utf-8")
    named = "  mjcf: arm3.xml\n"
    assert named in text
    spec = tmp_path / "arm3.yaml"
    # (an MJCF mend, which the URDF written from the mended MJCF has applied already)
    spec.write_text(
        text.replace(named, named + "  loader: mujoco\n  mend: {mesh_names: mujoco}\n"),
        encoding="utf-8",
    )
    out = tmp_path / "arm3_fast.yaml"
    report, diagnostics = run_optimize(spec, out, OptimizeOptions(samples=0))
    assert report is not None, [d.format_text() for d in diagnostics]
    written = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert written["description"] == {"urdf": "arm3_fast.urdf"}
    before, after = compile_spec(spec), compile_spec(out)
    assert after.ok, [d.format_text() for d in after.diagnostics]
    assert before.robot is not None and after.robot is not None
    assert before.robot.armature == (("shoulder_yaw", 0.01), ("elbow", 0.01), ("wrist", 0.01))
    assert after.robot.armature == before.robot.armature


def test_an_unknown_shapes_method_is_a_usage_error_naming_the_methods(tmp_path: Path) -> None:
    # typer refuses it before anything runs (exit 2), as it does a malformed number
    out = tmp_path / "p.yaml"
    result = invoke_robospec("optimize", str(PANDA_SPEC), "-o", str(out), "--shapes", "bogus")
    assert result.exit_code == 2
    message = " ".join(result.output.replace("│", " ").split())
    assert "'bogus' is not one of 'keep', 'convert', 'hull', 'coacd', 'primitives'" in message
    assert list(tmp_path.iterdir()) == []


def test_a_shapes_method_named_in_python_is_the_cli_s_choice() -> None:
    assert OptimizeOptions(shapes="hull").shapes is ShapeMethod.hull  # type: ignore[arg-type]
    assert OptimizeOptions(profile="fast").shape_method is ShapeMethod.primitives
    assert OptimizeOptions().shape_method is ShapeMethod.convert
    with pytest.raises(ValueError, match="bogus"):
        OptimizeOptions(shapes="bogus")  # type: ignore[arg-type]


def test_a_refused_run_in_json_is_its_diagnostics_alone(tmp_path: Path) -> None:
    result = invoke_robospec(
        "optimize", str(PANDA_SPEC), "-o", str(tmp_path / "p.yaml"), "--profile", "fsat",
        "--format", "json",
    )  # fmt: skip
    assert result.exit_code == 1
    data = json.loads(result.output)
    assert list(data) == ["diagnostics"]
    assert [d["code"] for d in data["diagnostics"]] == ["RS670"]
    assert list(tmp_path.iterdir()) == []


def test_the_json_report_says_what_changed(tmp_path: Path) -> None:
    result = invoke_robospec(
        "optimize", str(PANDA_SPEC), "-o", str(tmp_path / "p.yaml"), "--shapes", "keep",
        "--samples", "0", "--format", "json",
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["links"] == {"before": 15, "after": 14}
    assert data["merged"] == [
        {"link": "panda_link8", "into": "panda_link7", "joint": "panda_joint8"}
    ]
    assert data["never_collide"] == {"samples": 0, "entries": []}


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.filterwarnings("ignore::UserWarning")
def test_the_optimized_panda_registers_behaves_alike_and_passes_check(
    maniskill: ModuleType, optimized: tuple[Path, object], tmp_path: Path
) -> None:
    import numpy as np
    import torch

    import robospec
    from robospec.maniskill.headless import make_empty_env
    from robospec.physics.command import run_check

    out, _ = optimized
    uids = [
        *robospec.register(PANDA_SPEC, cache_dir=tmp_path),
        *robospec.register(out, cache_dir=tmp_path),
    ]
    envs = [make_empty_env(uid, "pd_joint_delta_pos") for uid in uids]
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, size=(40, envs[0].action_space.shape[-1])).astype(np.float32)
    states = []
    for env in envs:
        env.reset(seed=0)
        for action in actions:
            env.step(torch.from_numpy(action))
        states.append(env.unwrapped.agent.robot.get_qpos())
        env.close()
    divergence = float((states[0] - states[1]).abs().max())
    # the same robot with link 8 folded into link 7 and pairs that never touch declared so:
    # the same motion up to float rounding (5e-6 rad here)
    assert divergence < 1e-4, f"rollouts diverge by {divergence:.2e} rad after 40 steps"
    code, text = run_check([out], None, "text", gpu=False, num_envs=1, render_dir=None)
    assert code == 0, text


def _urdf_specs() -> list[Path]:
    """The shipped specs whose description is a URDF or xacro (read without compiling: this
    runs at collection)."""
    specs = sorted((PANDA_SPEC.parent.parent).rglob("*.yaml"))
    return [p for p in specs if "urdf:" in p.read_text() or "xacro:" in p.read_text()]


@pytest.mark.parametrize("spec", _urdf_specs(), ids=lambda p: p.stem)
def test_no_link_a_shipped_spec_names_is_lost(spec: Path) -> None:
    from robospec.optimize.condense import condense
    from robospec.optimize.links import absolute_meshes, links_to_keep

    compiled = compile_spec(spec)
    assert compiled.ok and compiled.robot is not None and compiled.context is not None
    urdf = absolute_meshes(compiled.robot.description.read_text(), compiled.description)
    keep = links_to_keep(compiled, ())
    condensed = condense(urdf, keep)
    left = {link.get("name") for link in condensed.robot.iter("link")}
    assert {name for _, name in compiled.context.bindings.link_names} <= left
    assert not {m.link for m in condensed.merged} & keep


def test_a_failure_of_ours_is_a_diagnostic_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from robospec.optimize import condense

    def broken(*_: object) -> None:
        raise RuntimeError("boom")

    monkeypatch.setattr(condense, "condense", broken)
    report, diagnostics = run_optimize(PANDA_SPEC, tmp_path / "p.yaml", QUICK)
    assert report is None
    assert [(d.code, d.message) for d in diagnostics] == [
        ("RS900", "internal error: RuntimeError: boom")
    ]
    assert list(tmp_path.iterdir()) == []


def test_out_in_a_folder_that_does_not_exist_yet_makes_it(tmp_path: Path) -> None:
    out = tmp_path / "new" / "folder" / "p.yaml"
    report, diagnostics = run_optimize(
        PANDA_SPEC, out, OptimizeOptions(shapes=ShapeMethod.keep, samples=0)
    )
    assert report is not None, [d.format_text() for d in diagnostics]
    assert compile_spec(out).ok


def test_a_relative_out_names_the_meshes_it_writes_from_the_new_urdf(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # hull writes a mesh per collision beside the new URDF
    monkeypatch.chdir(tmp_path)
    out = Path("sub") / "p.yaml"
    report, diagnostics = run_optimize(
        PANDA_SPEC, out, OptimizeOptions(shapes=ShapeMethod.hull, samples=0)
    )
    assert report is not None, [d.format_text() for d in diagnostics]
    compiled = compile_spec(tmp_path / out)
    assert compiled.ok
    assert [d.format_text() for d in compiled.diagnostics] == []


def test_out_under_a_file_is_a_located_error_not_a_traceback(tmp_path: Path) -> None:
    (tmp_path / "a_file").write_text("")
    report, diagnostics = run_optimize(PANDA_SPEC, tmp_path / "a_file" / "p.yaml", QUICK)
    assert report is None
    assert [(d.code, d.location.file) for d in diagnostics] == [("RS603", "<command line>")]


def test_links_whose_mass_sapien_takes_from_their_shapes_stay_and_are_reported(
    tmp_path: Path,
) -> None:
    # the touch Allegro's sensor pads hang on fixed joints with collision boxes and no inertial;
    # its spec names them (touch:), which keeps them anyway: a copy without touch does not
    data = yaml.safe_load((MANISKILL_SPECS / "allegro_hand_right_touch.yaml").read_text())
    del data["touch"]
    spec = tmp_path / "untouched.yaml"
    spec.write_text(yaml.safe_dump(data, sort_keys=False))
    options = OptimizeOptions(shapes=ShapeMethod.keep, samples=0)
    report, diagnostics = run_optimize(spec, tmp_path / "touch.yaml", options)
    assert report is not None, [d.format_text() for d in diagnostics]
    assert len(report.unmerged) == 16 and all("link_" in name for name in report.unmerged)
    assert "their mass (or their parent's) SAPIEN takes" in report.to_text()
    assert report.to_json()["unmerged"] == report.unmerged
