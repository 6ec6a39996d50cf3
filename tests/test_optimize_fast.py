"""`robospec optimize --profile fast`: its options checked before anything runs (each a located
error), what it writes into the spec (primitive shapes where they fit, a measured contact
offset, a recommended sim config by category) and what its report measures; on ManiSkill's
Panda end to end, and on small robots made to show each change."""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import pytest
import trimesh
from conftest import PANDA_SPEC, ROOT, contact_offsets, invoke_robospec, run_robospec

from robospec.description import load_description
from robospec.optimize import options as optimize_options
from robospec.optimize.command import run_optimize
from robospec.optimize.contacts import (
    LARGEST_OFFSET,
    SMALLEST_OFFSET,
    disabled_pairs,
    profile_offset,
)
from robospec.optimize.fast import category_of
from robospec.optimize.options import OptimizeOptions, ShapeMethod
from robospec.optimize.spec_rewrite import rewrite_spec
from robospec.pipeline import compile_spec

OUT = "out/panda_fast.yaml"


def _optimize(*args: str) -> tuple[int, str]:
    result = invoke_robospec("optimize", str(PANDA_SPEC), "-o", OUT, *args)
    return result.exit_code, result.output


@pytest.mark.parametrize(
    ("args", "options", "code", "value"),
    [
        (("--profile", "fastest"), {"profile": "fastest"}, "RS670", "fastest"),
        (("--profile", "fast", "--max-error", "0.2"), {"max_error": 0.2}, "RS671", "0.2"),
        (("--profile", "fast", "--max-error", "0"), {"max_error": 0.0}, "RS671", "0"),
        (("--profile", "fast", "--max-error=-1e-3"), {"max_error": -1e-3}, "RS671", "-1e-3"),
        (
            ("--profile", "fast", "--contact-offset", "0.05"),
            {"contact_offset": 0.05},
            "RS672",
            "0.05",
        ),
        (
            ("--profile", "fast", "--contact-offset", "nan"),
            {"contact_offset": math.nan},
            "RS672",
            "nan",
        ),
        (
            ("--profile", "fast", "--category", "walking"),
            {"category": "walking"},
            "RS675",
            "walking",
        ),
        (("--max-error", "0.01"), {"profile": "default", "max_error": 0.01}, "RS676", "0.01"),
        (
            ("--contact-offset", "0.001"),
            {"profile": "default", "contact_offset": 0.001},
            "RS676",
            "0.001",
        ),
        (
            ("--category", "locomotion"),
            {"profile": "default", "category": "locomotion"},
            "RS676",
            "locomotion",
        ),
        (
            ("--profile", "fast", "--shapes", "hull", "--max-error", "0.01"),
            {"shapes": "hull", "max_error": 0.01},
            "RS676",
            "0.01",
        ),
    ],
)
def test_bad_options_are_located_errors_before_anything_is_written(
    args: tuple[str, ...], options: dict[str, object], code: str, value: str, tmp_path: Path
) -> None:
    arguments = ("optimize", str(PANDA_SPEC), "-o", OUT, *args)
    given = OptimizeOptions(**{"profile": "fast", **options}, arguments=arguments)  # type: ignore[arg-type]
    report, diagnostics = run_optimize(PANDA_SPEC, tmp_path / OUT, given)
    assert report is None
    (problem,) = [d for d in diagnostics if d.code == code]
    assert problem.location.file == "<command line>" and problem.location.line == 1
    command = " ".join(["robospec", *arguments])
    assert command[problem.location.column - 1 :].startswith(value), (problem, command)
    assert not (tmp_path / "out").exists()


def test_the_command_line_locates_its_own_options(tmp_path: Path) -> None:
    # as a user types it: the column of the value in the command line as given
    result = run_robospec(
        "optimize", str(PANDA_SPEC), "-o", str(tmp_path / "x.yaml"), "--profile", "fats"
    )
    assert result.returncode == 1
    line = next(line for line in result.stdout.splitlines() if "[RS670]" in line)
    command = " ".join(
        [
            "robospec",
            "optimize",
            str(PANDA_SPEC),
            "-o",
            str(tmp_path / "x.yaml"),
            "--profile",
            "fats",
        ]
    )
    column = int(line.split(":")[2])
    assert command[column - 1 :] == "fats" and "Traceback" not in result.stderr


def test_an_unknown_profile_gets_the_nearest_name() -> None:
    _, output = _optimize("--profile", "fsat")
    assert "error[RS670] unknown profile 'fsat'" in output and "did you mean 'fast'?" in output


def test_the_category_follows_the_root_unless_given() -> None:
    fixed, free = SimpleNamespace(fix_root_link=True), SimpleNamespace(fix_root_link=False)
    assert category_of(fixed, None) == "manipulation"
    assert category_of(free, None) == "locomotion"
    assert category_of(free, "manipulation") == "manipulation"


QUADRUPED_URDF = ROOT / "tests" / "data" / "new" / "quadruped.urdf"
WHEELED = """<robot name="rover"><link name="chassis"/><link name="left_wheel"/>
<link name="right_wheel"/><link name="arm"/>
<joint name="left_wheel_joint" type="continuous"><parent link="chassis"/>
<child link="left_wheel"/><axis xyz="0 1 0"/><limit effort="10" velocity="12"/></joint>
<joint name="right_wheel_joint" type="continuous"><parent link="chassis"/>
<child link="right_wheel"/><axis xyz="0 1 0"/><limit effort="10" velocity="12"/></joint>
<joint name="shoulder" type="revolute"><parent link="chassis"/><child link="arm"/>
<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="4"/></joint></robot>"""


@pytest.mark.parametrize(
    ("description", "category"),
    [(WHEELED, "manipulation"), (QUADRUPED_URDF, "locomotion")],
    ids=["wheels", "legs"],
)
def test_a_free_robot_on_wheels_manipulates_and_one_on_legs_walks(
    tmp_path: Path, description: str | Path, category: str
) -> None:
    path = description if isinstance(description, Path) else tmp_path / "rover.urdf"
    if isinstance(description, str):
        path.write_text(description, encoding="utf-8")
    free = SimpleNamespace(fix_root_link=False)
    robot, diagnostics = load_description(str(path), "urdf")
    assert robot is not None, diagnostics
    assert category_of(free, None, robot) == category


def test_the_offset_is_half_the_nearest_gap_within_its_bounds() -> None:
    assert profile_offset(None) == LARGEST_OFFSET  # no pair that never touches comes near
    assert profile_offset(0.0014) == pytest.approx(0.0007)
    assert profile_offset(1.0) == LARGEST_OFFSET
    assert profile_offset(0.0) == SMALLEST_OFFSET


def test_disabled_pairs_are_adjacent_ones_and_those_sharing_a_bit() -> None:
    links = ["a", "b", "c", "d"]
    disabled = disabled_pairs(links, {("a", "b")}, [(3, ("b", "c", "d")), (3, ("a",)), (5, ("x",))])
    # bit 3 from two rules is one clique of a, b, c and d; x is no link of this robot
    assert disabled == {("a", "b"), ("a", "c"), ("a", "d"), ("b", "c"), ("b", "d"), ("c", "d")}
    assert disabled_pairs(links, (), [(1, ("a", "b")), (2, ("c", "d"))]) == {
        ("a", "b"),
        ("c", "d"),
    }


SIMULATION = {
    "profile": "fast",
    "category": "locomotion",
    "contact_offset": 0.001,
    "solver_position_iterations": 4,
    "solver_velocity_iterations": 1,
}


@pytest.mark.parametrize("suffix", [".yaml", ".toml"])
def test_the_simulation_section_is_written_into_yaml_and_toml(tmp_path: Path, suffix: str) -> None:
    source = PANDA_SPEC if suffix == ".yaml" else PANDA_SPEC.parent.parent / "twolink.toml"
    out = tmp_path / f"out{suffix}"
    text = rewrite_spec(
        source,
        out,
        uid="fast",
        urdf="out.urdf",
        never_collide=[],
        header="# written by a test",
        simulation=SIMULATION,
    )
    if suffix == ".toml":
        import tomllib

        data = tomllib.loads(text.split("\n", 1)[1])
    else:
        from ruamel.yaml import YAML

        data = YAML(typ="safe").load(text)
    assert data["simulation"] == SIMULATION


def test_a_spec_section_already_there_keeps_its_other_keys(tmp_path: Path) -> None:
    spec = tmp_path / "spec.yaml"
    text = PANDA_SPEC.read_text(encoding="utf-8") + "simulation:\n  contact_offset: 0.01\n"
    spec.write_text(text, encoding="utf-8")
    out = rewrite_spec(
        spec,
        tmp_path / "o.yaml",
        uid="x",
        urdf="o.urdf",
        never_collide=[],
        header="#",
        simulation={"contact_offset": 0.002},
    )
    assert out.count("simulation:") == 1 and "contact_offset: 0.002" in out


# -- the Panda, optimized with the fast profile ------------------------------------------------


# the profile run end to end samples contacts in SAPIEN: its tests are marked maniskill
@pytest.fixture(scope="module")
def fast_panda(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Path, object]]:
    out = tmp_path_factory.mktemp("fast") / "panda_fast.yaml"
    options = OptimizeOptions(profile="fast", samples=1000, uid="rs_panda_fast_profile")
    report, diagnostics = run_optimize(PANDA_SPEC, out, options)
    assert report is not None, [d.format_text() for d in diagnostics]
    yield out, report


@pytest.mark.maniskill  # SAPIEN samples the collision matrix and counts contacts
def test_the_fast_spec_declares_its_profile_and_what_it_changes(
    fast_panda: tuple[Path, object],
) -> None:
    out, report = fast_panda
    compiled = compile_spec(out)
    assert compiled.ok and compiled.robot is not None
    simulation = compiled.robot.simulation
    assert simulation.profile == "fast" and simulation.category == "manipulation"
    assert simulation.solver_position_iterations == 15  # manipulation: 15 or more
    assert SMALLEST_OFFSET <= simulation.contact_offset <= LARGEST_OFFSET
    assert report.simulation["contact_offset"] == simulation.contact_offset  # type: ignore[attr-defined]
    # the same robot underneath: joints, modes and every link the spec names
    original = compile_spec(PANDA_SPEC)
    assert original.robot is not None and original.context is not None
    assert compiled.robot.active_joints == original.robot.active_joints
    assert compiled.description is not None
    named = {name for _, name in original.context.bindings.link_names}
    assert all(compiled.description.link(name) is not None for name in named)


@pytest.mark.maniskill  # SAPIEN samples the collision matrix and counts contacts
def test_the_report_measures_the_contacts_the_offset_saves(
    fast_panda: tuple[Path, object],
) -> None:
    _, report = fast_panda
    before, after = report.contacts  # type: ignore[attr-defined]
    assert before["offset"] == 0.02 and after["offset"] == report.simulation["contact_offset"]  # type: ignore[attr-defined]
    assert before["configurations"] == after["configurations"] == 1000
    assert after["pairs_per_configuration"] < before["pairs_per_configuration"]
    assert after["never_touching_pairs"] == 0
    data = report.to_json()  # type: ignore[attr-defined]
    assert data["profile"] == "fast" and data["contacts"] == [before, after]
    json.dumps(data)  # plain data only
    text = report.to_text()  # type: ignore[attr-defined]
    assert "profile fast" in text and "pairs of its links making contacts" in text


@pytest.mark.maniskill  # SAPIEN samples the collision matrix and counts contacts
def test_meshes_no_primitive_fits_are_listed_with_their_nearest_fit(
    fast_panda: tuple[Path, object],
) -> None:
    _, report = fast_panda
    # the Panda's links are rounded castings: no box, capsule or sphere within 5 mm
    missed = [s for s in report.shapes if s["reason"] == "no primitive within the bound"]  # type: ignore[attr-defined]
    assert missed and all(s["fit_error"] > 0.005 for s in missed)
    codes = [d.code for d in report.diagnostics]  # type: ignore[attr-defined]
    assert codes.count("RS674") == 1


def _boxy_robot(folder: Path) -> Path:
    """A fixed base and a box-shaped arm link on a revolute joint, and a second link shaped
    like a rounded blob (an icosphere squashed): a box fits the first within a micron, nothing
    fits the second within 5 mm. Both carry <inertial>s."""
    trimesh.creation.box((0.05, 0.05, 0.3)).export(folder / "arm.stl")
    blob = trimesh.creation.icosphere(subdivisions=2, radius=0.06)
    blob.apply_scale((1.0, 0.5, 1.6))
    blob.vertices[:, 0] += 0.02 * (blob.vertices[:, 2] > 0)  # leaning: not an ellipsoid either
    blob.export(folder / "blob.stl")
    inertial = (
        '<inertial><mass value="1"/>'
        '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
    )
    urdf = folder / "boxy.urdf"
    urdf.write_text(
        f"""<robot name="boxy">
  <link name="base">{inertial}</link>
  <link name="arm">{inertial}<collision><origin xyz="0 0 0.15"/>
    <geometry><mesh filename="arm.stl"/></geometry></collision></link>
  <link name="blob">{inertial}<collision><origin xyz="0 0 0.1"/>
    <geometry><mesh filename="blob.stl"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="blob"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""
    )
    spec = folder / "boxy.yaml"
    spec.write_text(
        """robospec: 1
uid: boxy
description: {urdf: boxy.urdf}
controllers:
  arm: {type: pd_joint_pos, joints: [j1, j2], lower: -1, upper: 1, stiffness: 100, damping: 10}
control_modes:
  pd_joint_pos: {arm: arm}
"""
    )
    return spec


@pytest.mark.maniskill  # SAPIEN samples the collision matrix and counts contacts
def test_a_box_shaped_link_becomes_a_box_and_a_rounded_one_keeps_its_mesh(
    tmp_path: Path,
) -> None:
    spec = _boxy_robot(tmp_path)
    out = tmp_path / "fast" / "boxy_fast.yaml"
    report, diagnostics = run_optimize(spec, out, OptimizeOptions(profile="fast", samples=200))
    assert report is not None, [d.format_text() for d in diagnostics]
    by_link = {s["link"]: s for s in report.shapes}
    assert by_link["arm"]["method"] == "box" and by_link["arm"]["fit_error"] < 1e-5
    assert by_link["blob"]["method"] == "kept" and by_link["blob"]["fit_error"] > 0.005
    urdf = (out.parent / "boxy_fast.urdf").read_text(encoding="utf-8")
    assert urdf.count("<box ") == 1 and "blob.stl" in urdf
    compiled = compile_spec(out)
    assert compiled.ok and compiled.robot is not None
    assert compiled.robot.simulation.category == "manipulation"  # its root is fixed


def test_a_larger_bound_turns_more_meshes_into_primitives(tmp_path: Path) -> None:
    spec = _boxy_robot(tmp_path)
    out = tmp_path / "loose" / "boxy.yaml"
    options = OptimizeOptions(profile="fast", samples=0, max_error=0.05, category="locomotion")
    report, _ = run_optimize(spec, out, options)
    assert report is not None
    assert {s["link"]: s["method"] for s in report.shapes} == {"arm": "box", "blob": "capsule"}
    assert report.simulation["solver_position_iterations"] == 4
    # no matrix (samples 0): nothing measured, the largest offset
    assert report.contacts == [] and report.simulation["contact_offset"] == LARGEST_OFFSET


def test_a_link_the_spec_names_that_condensing_would_drop_is_a_located_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # condensing keeps every link the spec names: make it drop one, as a link named where the
    # keep list does not look would be dropped, and the spec is refused where it names it
    from robospec.optimize import condense as condense_module

    real = condense_module.condense

    def dropping(robot: object, keep: object) -> object:
        condensed = real(robot, keep)
        for link in condensed.robot.findall("link"):
            if link.get("name") == "panda_hand_tcp":
                condensed.robot.remove(link)
        return condensed

    monkeypatch.setattr(condense_module, "condense", dropping)
    out = tmp_path / "dropped.yaml"
    report, diagnostics = run_optimize(
        PANDA_SPEC, out, OptimizeOptions(shapes=ShapeMethod.keep, samples=0, profile="fast")
    )
    assert report is None and not out.exists()
    located = [d for d in diagnostics if d.code == "RS673"]
    assert located and all(d.location.file == str(PANDA_SPEC) for d in located)
    lines = PANDA_SPEC.read_text(encoding="utf-8").splitlines()
    assert all("panda_hand_tcp" in lines[d.location.line - 1] for d in located)
    assert "--keep panda_hand_tcp" in (located[0].hint or "")


@pytest.mark.maniskill
@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_the_fast_panda_registers_takes_its_sim_config_and_steps(
    fast_panda: tuple[Path, object],
) -> None:
    import gymnasium as gym

    import robospec
    from robospec.maniskill.headless import headless_loading

    out, report = fast_panda
    (uid,) = robospec.register(str(out))
    config = robospec.sim_config_for(uid)
    assert config == {
        "scene_config": {"solver_position_iterations": 15, "solver_velocity_iterations": 1}
    }
    with headless_loading():
        env = gym.make(
            "PickCube-v1",
            robot_uids=uid,
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
            sim_config=config,
        )
    try:
        offsets = {round(o, 6) for o in contact_offsets(env.unwrapped.agent.robot.links)}
        assert offsets == {round(report.simulation["contact_offset"], 6)}  # type: ignore[attr-defined]
        env.reset(seed=0)
        for _ in range(5):
            _, reward, *_ = env.step(env.action_space.sample())
        assert math.isfinite(float(reward))
    finally:
        env.close()


@pytest.mark.maniskill  # SAPIEN samples the collision matrix and counts contacts
def test_the_cli_prints_the_profile_and_exits_0(tmp_path: Path) -> None:
    out = tmp_path / "cli.yaml"
    result = invoke_robospec(
        "optimize", str(PANDA_SPEC), "-o", str(out), "--profile", "fast", "--samples", "200"
    )
    assert result.exit_code == 0, result.output
    assert "profile fast" in result.output and "warning[RS674]" in result.output
    assert "profile: fast" in out.read_text(encoding="utf-8")


def test_the_default_profile_writes_no_simulation_section(tmp_path: Path) -> None:
    out = tmp_path / "plain.yaml"
    report, _ = run_optimize(PANDA_SPEC, out, OptimizeOptions(shapes=ShapeMethod.keep, samples=0))
    assert report is not None and report.profile == "default" and report.simulation == {}
    assert "simulation:" not in out.read_text(encoding="utf-8")
    assert optimize_options.PROFILES == ("default", "fast")
