"""``robospec new FILE``: scaffolded specs validate with 0 errors for real robots (arms,
hands, mobile manipulators, a humanoid MJCF, a xacro arm), guess groups, turn URDF mimic joints
into a pd_joint_pos_mimic controller, start at a safe keyframe, and never overwrite a file
without --force. The end-to-end test registers the scaffolded Panda and steps it in ManiSkill.

Most tests scaffold with ``simulate=False`` (``--no-sim``): loading the robot in ManiSkill to
search its rest pose costs seconds, and tests/test_new_sim.py proves that part."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import TWOLINK_XACRO, invoke_robospec, maniskill_assets, run_robospec
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.authoring.description_file import read_description_file
from robospec.authoring.new import rest_pose
from robospec.authoring.new.exemptions import ADJACENT_WHY, COARSE_WHY, OVERLAPPING_WHY, THOROUGH
from robospec.authoring.new.scaffold import FILTERED_WHY
from robospec.pipeline import compile_spec
from robospec.schema import schema_text

LIMIT = '<limit lower="{lo}" upper="{hi}" effort="5" velocity="2"/>'

REAL_ROBOTS = [
    "panda/panda_v2.urdf",
    "xarm7/xarm7.urdf",
    "xarm7/xarm7_ability_right_hand.urdf",
    "allegro/allegro_hand_right.urdf",
    "allegro/allegro_hand_left.urdf",
    "fetch/fetch.urdf",
    "koch/follower_arm_v1.1.urdf",
    "so100/so100.urdf",
    "trifinger/trifingerpro.urdf",
    "inspire_hand/RH56DFX-2LR/urdf/inspire_hand_left.urdf",
    "inspire_hand/RH56DFX-2LR/urdf/inspire_hand_right_floating.urdf",
    "ability_hand/ability_hand_right.urdf",
    "dclaw/dclaw_gripper_glb.urdf",
    "g1_humanoid/g1_simplified_upper_body.urdf",
    "humanoid/humanoid.xml",
]


def load(path: Path) -> dict:
    return YAML(typ="safe").load(path.read_text())


def scaffold(description: Path, out: Path, uid: str | None = None) -> dict:
    result = run_new(description, out, uid, force=False, simulate=False).write()
    assert not result.failed, result.diagnostics
    assert result.written[0] == out
    return load(out)


def validate(spec: Path) -> None:
    compiled = compile_spec(spec)
    errors = [d.format_text() for d in compiled.diagnostics if d.is_error]
    assert errors == []
    assert compiled.robot is not None


@pytest.fixture(scope="module")
def real_scaffolds(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Each real robot's scaffold, written once for the module's tests that read it (Fetch's
    ready-pose search alone costs seconds)."""
    return {}


def real_scaffold(scaffolds: dict[str, Path], robot: str, folder: Path) -> tuple[Path, dict]:
    if robot not in scaffolds:
        out = folder / (robot.replace("/", "_") + ".yaml")
        scaffold(maniskill_assets() / "robots" / robot, out)
        scaffolds[robot] = out
    return scaffolds[robot], load(scaffolds[robot])


@pytest.mark.parametrize("robot", REAL_ROBOTS)
def test_scaffold_of_a_real_robot_validates_with_no_errors(
    real_scaffolds: dict[str, Path], tmp_path_factory: pytest.TempPathFactory, robot: str
) -> None:
    out, data = real_scaffold(real_scaffolds, robot, tmp_path_factory.mktemp("real"))
    validate(out)
    assert list(data["control_modes"]) == ["pd_joint_delta_pos", "pd_joint_pos"]
    # every group is driven in both modes
    for mode in data["control_modes"].values():
        assert set(mode) - {"balance_passive_force"} == set(data["groups"])


def test_scaffold_of_the_xacro_robot_validates_and_names_it_relative_to_the_spec(
    tmp_path: Path,
) -> None:
    out = tmp_path / "nested" / "twolink.yaml"
    data = scaffold(TWOLINK_XACRO, out)
    validate(out)
    relative = data["description"]["xacro"]
    assert not Path(relative).is_absolute()
    assert (out.parent / relative).resolve() == TWOLINK_XACRO.resolve()
    assert data["uid"] == "twolink"
    assert data["groups"] == {
        "arm": ["twolink_joint1", "twolink_joint2", "twolink_joint3"],
        "gripper": ["twolink_finger_joint1", "twolink_finger_joint2"],
    }


def test_panda_scaffold_guesses_arm_and_a_mimic_gripper_and_a_safe_keyframe(
    real_scaffolds: dict[str, Path], tmp_path_factory: pytest.TempPathFactory
) -> None:
    _, data = real_scaffold(real_scaffolds, "panda/panda_v2.urdf", tmp_path_factory.mktemp("real"))
    assert data["uid"] == "rs_panda"  # 'panda' is ManiSkill's own uid
    assert data["description"] == {"urdf": "{maniskill_assets}/robots/panda/panda_v2.urdf"}
    assert data["groups"]["arm"] == [f"panda_joint{i}" for i in range(1, 8)]
    gripper = data["controllers"]["gripper"]
    assert gripper["type"] == "pd_joint_pos_mimic"
    assert gripper["mimic"] == {"panda_finger_joint2": "panda_finger_joint1"}
    # joint4's limits (-3.0718, -0.0698) exclude 0: mid-range; the others hold 0
    assert data["keyframes"]["rest"]["qpos"]["arm"] == [0.0, 0.0, 0.0, -1.5708, 0.0, 0.0, 0.0]
    delta = data["controllers"]["arm_delta_pos"]
    assert (delta["lower"], delta["upper"], delta["use_delta"]) == (-0.1, 0.1, True)
    absolute = data["controllers"]["arm_pos"]
    # force limits: the URDF's effort ratings (87 N m for the first four joints, 12 for the
    # wrist); stiffness and damping: each joint's own, critically damped at 20 rad/s
    assert absolute["force_limit"] == {
        **{f"panda_joint{i}": 87 for i in range(1, 5)},
        **{f"panda_joint{i}": 12 for i in range(5, 8)},
    }
    from robospec.authoring.description_file import read_description_file
    from robospec.authoring.new.analysis import analyse
    from robospec.authoring.new.joint_gains import loads

    source, _ = read_description_file(maniskill_assets() / "robots/panda/panda_v2.urdf")
    assert source is not None
    rest = dict.fromkeys(absolute["stiffness"], 0.0) | {"panda_joint4": -1.5708}
    inertia = {name: load.inertia for name, load in loads(analyse(source), rest, False).items()}
    for joint, stiffness in absolute["stiffness"].items():
        # 20 rad/s about its inertia, softened where a 0.1 rad step would ask more than the
        # rating (RS609), and critically damped either way
        expected = inertia[joint] * 20.0**2
        assert stiffness == pytest.approx(min(expected, absolute["force_limit"][joint] / 0.1), 0.01)
        critical = 2 * (stiffness * inertia[joint]) ** 0.5
        assert absolute["damping"][joint] == pytest.approx(critical, 0.01)
    # the shoulder carries the whole arm, the last joint only the hand
    assert absolute["stiffness"]["panda_joint2"] > 100 * absolute["stiffness"]["panda_joint7"]


def test_fetch_scaffold_drives_its_planar_base_forward_like_fetch_does(
    real_scaffolds: dict[str, Path], tmp_path_factory: pytest.TempPathFactory
) -> None:
    _, data = real_scaffold(real_scaffolds, "fetch/fetch.urdf", tmp_path_factory.mktemp("real"))
    assert data["groups"]["base"] == [
        "root_x_axis_joint",
        "root_y_axis_joint",
        "root_z_rotation_joint",
    ]
    assert data["groups"]["head"] == ["head_pan_joint", "head_tilt_joint"]
    # fetch rolls on wheels (fixed joints in its URDF): forward speed and turn rate, as
    # ManiSkill's own Fetch; the root stays fixed, the planar joints move it
    for mode in data["control_modes"].values():
        assert data["controllers"][mode["base"]]["type"] == "pd_base_forward_vel"
        assert "balance_passive_force" not in mode
    assert "loader" not in data


def test_hand_of_identical_fingers_gets_one_group_per_finger_and_no_arm(
    real_scaffolds: dict[str, Path], tmp_path_factory: pytest.TempPathFactory
) -> None:
    robot = "allegro/allegro_hand_right.urdf"
    _, data = real_scaffold(real_scaffolds, robot, tmp_path_factory.mktemp("real"))
    assert list(data["groups"]) == ["finger1", "finger2", "finger3", "finger4"]
    assert data["groups"]["finger2"] == ["joint_4.0", "joint_5.0", "joint_6.0", "joint_7.0"]


def test_a_cad_assembly_name_gives_way_to_the_file_name_for_the_uid(tmp_path: Path) -> None:
    body = '<link name="a"/><link name="b"/>\n<joint name="j" type="continuous">'
    body += '<parent link="a"/><child link="b"/></joint>\n'
    urdf = _robot(tmp_path / "so_arm.urdf", "SO_5DOF_ARM100_8j_URDF.SLDASM", body)
    assert scaffold(urdf, tmp_path / "so_arm.yaml")["uid"] == "so_arm"


@pytest.mark.parametrize(
    ("name", "file", "uid"),
    [
        ("physics", "r2d2.urdf", "r2d2"),  # pybullet's r2d2 and pr2_gripper
        ("plane", "laikago_toes_zup.urdf", "laikago_toes_zup"),
        ("UF_ROBOT", "xarm7.urdf", "xarm7"),  # a vendor's two letters and a generic word
        ("robot", "my_arm.urdf", "my_arm"),
        ("ur5", "ur5_robot.urdf", "ur5"),  # a name that says which robot is kept
        ("go2_description", "robot.urdf", "go2"),  # ROS's package suffix is not the name
        ("a1_description", "robot.urdf", "a1"),  # a model's name carries a digit
    ],
)
def test_a_robot_name_that_names_no_robot_gives_way_to_the_file_name(
    tmp_path: Path, name: str, file: str, uid: str
) -> None:
    body = '<link name="a"/><link name="b"/>\n<joint name="j" type="continuous">'
    body += '<parent link="a"/><child link="b"/></joint>\n'
    urdf = _robot(tmp_path / file, name, body)
    assert scaffold(urdf, tmp_path / "spec.yaml")["uid"] == uid


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_the_description_is_the_one_positional_argument(tmp_path: Path) -> None:
    positional = run_robospec("new", str(TWOLINK_XACRO), "-o", str(tmp_path / "a.yaml"), "--no-sim")
    assert positional.returncode == 0, positional.stderr
    # one spelling: the description is FILE, there is no option for it
    alias = ["new", "--from-urdf", str(TWOLINK_XACRO), "-o", str(tmp_path / "b.yaml"), "--no-sim"]
    neither = run_robospec("new", "-o", str(tmp_path / "c.yaml"))
    for result, said in ((run_robospec(*alias), "No such option"), (neither, "Missing argument")):
        assert result.returncode == 2  # a usage error
        assert said in result.stderr and "robospec new [OPTIONS] FILE" in result.stderr
        assert "Traceback" not in result.stderr


def _robot(path: Path, name: str, body: str) -> Path:
    path.write_text(f'<?xml version="1.0"?>\n<robot name="{name}">\n{body}</robot>\n')
    return path


def test_mimic_chains_collapse_onto_their_leader_and_the_keyframe_keeps_the_relation(
    tmp_path: Path,
) -> None:
    body = (
        '<link name="base"/><link name="a"/><link name="b"/><link name="c"/>\n'
        '<joint name="ja" type="prismatic"><parent link="base"/><child link="a"/>'
        + LIMIT.format(lo=0.1, hi=0.5)
        + "</joint>\n"
        '<joint name="jb" type="prismatic"><parent link="base"/><child link="b"/>'
        + LIMIT.format(lo=0, hi=2)
        + '<mimic joint="ja" multiplier="2" offset="0.1"/></joint>\n'
        '<joint name="jc" type="prismatic"><parent link="base"/><child link="c"/>'
        + LIMIT.format(lo=0, hi=5)
        + '<mimic joint="jb" multiplier="3" offset="0.2"/></joint>\n'
    )
    urdf = _robot(tmp_path / "chain.urdf", "chain", body)
    out = tmp_path / "chain.yaml"
    data = scaffold(urdf, out)
    validate(out)
    (name,) = [n for n, c in data["controllers"].items() if c["type"] == "pd_joint_pos_mimic"]
    mimic = data["controllers"][name]["mimic"]
    assert mimic["jb"] == {"joint": "ja", "multiplier": 2.0, "offset": 0.1}
    jc = mimic["jc"]  # jc = 3 * (2 * ja + 0.1) + 0.2 = 6 * ja + 0.5
    assert (jc["joint"], jc["multiplier"]) == ("ja", 6.0)
    assert jc["offset"] == pytest.approx(0.5)
    # ja's limits exclude 0: mid-range 0.3; the followers follow it
    qpos = data["keyframes"]["rest"]["qpos"][name]
    assert qpos == pytest.approx([0.3, 0.7, 2.3])


def test_an_mjcf_tendon_coupling_becomes_a_mimic_controller_not_a_loose_joint(
    tmp_path: Path,
) -> None:
    # ManiSkill's loader drops the tendon: without a mimic controller the distal joint, which no
    # actuator drives, would be passive and flop
    out = tmp_path / "finger.yaml"
    data = scaffold(Path(__file__).parent / "data" / "new" / "tendon_finger.xml", out)
    validate(out)
    (mimic,) = [c for c in data["controllers"].values() if c.get("type") == "pd_joint_pos_mimic"]
    assert mimic["mimic"] == {"j0": {"joint": "j1", "multiplier": 1.14286, "offset": 0}}
    assert "passive" not in {c.get("type") for c in data["controllers"].values()}


def test_links_an_mjcf_s_collision_filters_keep_apart_are_declared_never_collide(
    tmp_path: Path,
) -> None:
    # contype 1, conaffinity 0: torso and shin never collide in MuJoCo (ManiSkill would collide
    # them); the foot's conaffinity 1 lets it collide with every link, so nothing keeps it apart
    mjcf = tmp_path / "leg.xml"
    mjcf.write_text(
        '<mujoco>\n<default><geom contype="1" conaffinity="0"/></default>\n<worldbody>\n'
        '<body name="torso"><geom size=".1"/>\n'
        '<body name="thigh" pos="0 0 -.3"><joint name="hip"/><geom size=".1"/>\n'
        '<body name="shin" pos="0 0 -.3"><joint name="knee"/><geom size=".1"/>\n'
        '<body name="foot" pos="0 0 -.3"><joint name="ankle"/>'
        '<geom size=".1" conaffinity="1"/>\n'
        "</body></body></body></body>\n</worldbody>\n</mujoco>\n"
    )
    out = tmp_path / "leg.yaml"
    data = scaffold(mjcf, out)
    validate(out)
    entries = [set(entry) for entry in data["never_collide"]]
    assert any({"torso", "shin"} <= entry for entry in entries)
    assert not any("foot" in entry for entry in entries)
    clique = next(entry for entry in data["never_collide"] if {"torso", "shin"} <= set(entry))
    assert f"#   {' + '.join(clique)}: {FILTERED_WHY}\n" in out.read_text()


def test_links_an_mjcf_s_contact_excludes_keep_apart_are_declared_never_collide(
    tmp_path: Path,
) -> None:
    # every geom collides with every other in MuJoCo (contype 1, conaffinity 1), but the file
    # excludes torso and shin, as robosuite's Baxter excludes its torso and shoulders; the
    # exclude of thigh and shin names a parent and its child, which collide nowhere anyway
    mjcf = tmp_path / "leg.xml"
    mjcf.write_text(
        "<mujoco>\n<worldbody>\n"
        '<body name="torso"><geom size=".1"/>\n'
        '<body name="thigh" pos="0 0 -.3"><joint name="hip"/><geom size=".1"/>\n'
        '<body name="shin" pos="0 0 -.3"><joint name="knee"/><geom size=".1"/>\n'
        '<body name="foot" pos="0 0 -.3"><joint name="ankle"/><geom size=".1"/>\n'
        "</body></body></body></body>\n</worldbody>\n"
        '<contact><exclude body1="torso" body2="shin"/><exclude body1="thigh" body2="shin"/>'
        "</contact>\n</mujoco>\n"
    )
    out = tmp_path / "leg.yaml"
    data = scaffold(mjcf, out)
    validate(out)
    assert [sorted(entry) for entry in data["never_collide"]] == [["shin", "torso"]]
    assert f"#   torso + shin: {FILTERED_WHY}\n" in out.read_text()


def test_uid_comes_from_the_robot_name_made_valid(tmp_path: Path) -> None:
    body = '<link name="a"/><link name="b"/>\n<joint name="j" type="continuous">'
    body += '<parent link="a"/><child link="b"/></joint>\n'
    urdf = _robot(tmp_path / "r.urdf", "my arm (v2)!", body)
    out = tmp_path / "r.yaml"
    data = scaffold(urdf, out)
    validate(out)
    assert data["uid"] == "my_arm_v2"
    # a continuous joint has no limits: the keyframe holds it at 0
    assert data["keyframes"]["rest"]["qpos"]["arm"] == 0.0


@pytest.fixture
def project(tmp_path: Path) -> Path:
    """A repository of its own (a .git folder bounds the walk for a schema): what the tests
    below find or miss cannot come from a schema somewhere above the temporary folder."""
    (tmp_path / "project" / ".git").mkdir(parents=True)
    return tmp_path / "project"


def test_modeline_points_at_the_nearest_schema_walking_up_relative(project: Path) -> None:
    (project / "schemas").mkdir()
    (project / "schemas" / "robospec.schema.json").write_text("{}")
    out = project / "specs" / "robots" / "twolink.yaml"
    scaffold(TWOLINK_XACRO, out)
    first = out.read_text().splitlines()[0]
    assert first == "# yaml-language-server: $schema=../../schemas/robospec.schema.json"


def test_the_walk_for_a_schema_stops_at_the_repository_root(project: Path) -> None:
    # a schema above the repository is another project's: not named, one is written beside
    (project.parent / "robospec.schema.json").write_text("{}")
    out = project / "specs" / "twolink.yaml"
    scaffold(TWOLINK_XACRO, out)
    assert out.read_text().splitlines()[0] == "# yaml-language-server: $schema=robospec.schema.json"
    assert (out.parent / "robospec.schema.json").is_file()


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_without_a_schema_to_name_new_writes_one_beside_the_spec(project: Path) -> None:
    out = project / "robots" / "twolink.yaml"
    scaffold(TWOLINK_XACRO, out)
    assert out.read_text().splitlines()[0] == "# yaml-language-server: $schema=robospec.schema.json"
    assert (out.parent / "robospec.schema.json").read_text() == schema_text()
    # the next spec in that folder names the same file, and nothing is rewritten
    second = project / "robots" / "second.yaml"
    result = run_new(TWOLINK_XACRO, second, "second", force=False, simulate=False).write()
    assert result.written == (second,)
    assert second.read_text().splitlines()[0].endswith("$schema=robospec.schema.json")


def test_sections_carry_comments_that_explain_them(tmp_path: Path) -> None:
    out = tmp_path / "twolink.yaml"
    scaffold(TWOLINK_XACRO, out)
    text = out.read_text()
    for line in ("groups:", "keyframes:", "controllers:", "control_modes:", "description:"):
        (found,) = [li for li in text.splitlines() if li.startswith(line)]
        assert "#" in found, found


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_existing_spec_is_never_overwritten_without_force(tmp_path: Path) -> None:
    out = tmp_path / "twolink.yaml"
    out.write_text("mine\n")
    result = run_robospec("new", str(TWOLINK_XACRO), "-o", str(out), "--no-sim")
    assert result.returncode == 1
    assert f"{out}:1:1: error[RS601]" in result.stderr
    assert "Traceback" not in result.stderr
    assert out.read_text() == "mine\n"
    result = run_robospec("new", str(TWOLINK_XACRO), "-o", str(out), "--force", "--no-sim")
    assert result.returncode == 0, result.stderr
    assert out.read_text().startswith("# yaml-language-server:")


@pytest.mark.parametrize(
    ("uid", "code"), [("bad uid!", "RS105"), ("panda", "RS306")], ids=["invalid", "maniskill"]
)
@pytest.mark.parametrize("spelling", ["separate", "equals"])
def test_bad_uid_option_points_at_the_argument_and_nothing_is_written(
    tmp_path: Path, uid: str, code: str, spelling: str
) -> None:
    out = tmp_path / "x.yaml"
    given = ["--uid", uid] if spelling == "separate" else [f"--uid={uid}"]
    arguments = ["new", str(TWOLINK_XACRO), "-o", str(out), *given]
    result = run_robospec(*arguments)
    assert result.returncode == 1
    # the column of the value in the command as typed: `robospec new ... --uid panda`
    typed = " ".join(["robospec", *arguments])
    column = typed.rindex(uid) + 1
    assert f"<command line>:1:{column}: error[{code}]" in result.stderr, result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists()


def test_uid_option_is_used(tmp_path: Path) -> None:
    out = tmp_path / "x.yaml"
    assert scaffold(TWOLINK_XACRO, out, uid="my_arm")["uid"] == "my_arm"


def test_malformed_description_gets_located_diagnostics_and_no_spec(tmp_path: Path) -> None:
    urdf = _robot(tmp_path / "bad.urdf", "bad", '<link name="a"/><link name="a"/>\n')
    out = tmp_path / "bad.yaml"
    result = run_robospec("new", str(urdf), "-o", str(out))
    assert result.returncode == 1
    assert f"{urdf}:3:" in result.stderr and "error[RS052]" in result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists()


def _knee_mjcf(path: Path, keys: str) -> Path:
    path.write_text(
        '<mujoco model="knee">\n  <compiler angle="radian"/>\n  <worldbody>\n'
        '    <body name="thigh"><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/>\n'
        '      <body name="shin" pos="0 0 -0.2">\n'
        '        <joint name="knee" type="hinge" axis="0 1 0" range="-2.775 0"/>\n'
        '        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/>\n'
        "      </body>\n    </body>\n  </worldbody>\n"
        f"  <keyframe>{keys}</keyframe>\n</mujoco>\n"
    )
    return path


def test_a_file_keyframe_past_a_joint_limit_is_clamped_into_it_with_a_note(
    tmp_path: Path,
) -> None:
    # the knee a hair below its lower limit, as an MJCF <key> may put it: copied as written,
    # validate would answer RS304
    mjcf = _knee_mjcf(tmp_path / "knee.xml", '<key name="crouch" qpos="-2.794"/>')
    out = tmp_path / "knee.yaml"
    data = scaffold(mjcf, out)
    validate(out)
    assert data["keyframes"]["crouch"]["qpos"] == {"arm": -2.775}
    (line,) = [line for line in out.read_text().splitlines() if "crouch:" in line]
    assert "knee -2.794 -> -2.775 (moved 0.019)" in line


@pytest.mark.usefixtures("maniskill")
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.filterwarnings("ignore::UserWarning")
def test_scaffolded_panda_registers_steps_in_both_modes_and_holds_its_keyframe(
    tmp_path: Path,
) -> None:
    import gymnasium as gym
    import numpy as np

    from robospec import register
    from robospec.physics import keyframe_hold
    from robospec.physics.batch import check_paths
    from robospec.physics.findings import Status

    out = tmp_path / "panda.yaml"
    panda = maniskill_assets() / "robots/panda/panda_v2.urdf"
    result = run_robospec("new", str(panda), "-o", str(out), "--uid", "rs_new_panda")
    assert result.returncode == 0, result.stderr
    check = run_robospec("validate", str(out))
    assert check.returncode == 0, check.stdout
    register(out)
    for mode in ("pd_joint_pos", "pd_joint_delta_pos"):
        env = gym.make(
            "Empty-v1",
            robot_uids="rs_new_panda",
            control_mode=mode,
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
        )
        try:
            env.reset(seed=0)
            assert env.action_space.shape == (8,)
            for _ in range(5):
                obs, *_ = env.step(env.action_space.sample())
            assert np.isfinite(np.asarray(obs)).all()
        finally:
            env.close()

    (report,), extra = check_paths([out])  # robospec check, every check
    assert extra == [] and not report.failed, report.all_diagnostics
    findings = [f for f in report.findings if f.check == keyframe_hold.NAME]
    assert findings and all(f.status is Status.PASS for f in findings), findings


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_json_format_puts_the_diagnostics_report_on_stdout(tmp_path: Path) -> None:
    import json

    out = tmp_path / "twolink.yaml"
    first = run_robospec("new", str(TWOLINK_XACRO), "-o", str(out), "-f", "json", "--no-sim")
    assert first.returncode == 0, first.stderr
    assert json.loads(first.stdout)["summary"]["errors"] == 0
    again = run_robospec("new", str(TWOLINK_XACRO), "-o", str(out), "-f", "json", "--no-sim")
    assert again.returncode == 1
    (diagnostic,) = json.loads(again.stdout)["diagnostics"]
    assert (diagnostic["code"], diagnostic["line"], diagnostic["column"]) == ("RS601", 1, 1)


def test_gripper_words_must_start_a_name_part(tmp_path: Path) -> None:
    limit = LIMIT.format(lo=-1, hi=1)
    body = '<link name="l0"/><link name="l1"/><link name="l2"/><link name="l3"/>\n'
    for name, parent, child in (
        ("shoulder", "l0", "l1"),
        ("steering", "l1", "l2"),  # "ring" inside a word: not a finger
        ("l_gripper_joint", "l2", "l3"),
    ):
        body += f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
        body += f'<child link="{child}"/>{limit}</joint>\n'
    urdf = _robot(tmp_path / "words.urdf", "words", body)
    out = tmp_path / "words.yaml"
    data = scaffold(urdf, out)
    validate(out)
    assert data["groups"] == {"arm": ["shoulder", "steering"], "gripper": ["l_gripper_joint"]}


def test_new_reads_a_description_given_as_a_spec_names_it(tmp_path: Path) -> None:
    """`{maniskill_assets}/...` is how specs name ManiSkill's files: new and inspect take it
    too, and the spec keeps that form."""
    out = tmp_path / "panda.yaml"
    given = "{maniskill_assets}/robots/panda/panda_v2.urdf"
    result = invoke_robospec("new", given, "-o", str(out), "--no-sim")
    assert result.exit_code == 0, result.output
    assert f"urdf: '{given}'" in out.read_text(encoding="utf-8")
    shown = invoke_robospec("inspect", given)
    assert shown.exit_code == 0 and "panda_joint1" in shown.stdout


def _arm_with_gripper(tmp_path: Path, frame: str, frame_parent: str = "hand") -> Path:
    """Four revolute joints, a hand welded to the last link, two fingers sliding on it, and
    ``frame`` welded to ``frame_parent``."""

    def link(name: str) -> str:
        return (
            f'<link name="{name}"><inertial><mass value="0.5"/><inertia ixx="0.001" '
            'iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>\n'
        )

    def joint(name: str, kind: str, parent: str, child: str, axis: str = "0 0 1") -> str:
        limit = LIMIT.format(lo=-1.5, hi=1.5) if kind == "revolute" else ""
        limit = LIMIT.format(lo=0, hi=0.04) if kind == "prismatic" else limit
        return (
            f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="0 0 0.1"/><axis xyz="{axis}"/>{limit}</joint>\n'
        )

    links = ["base", "link1", "link2", "link3", "link4", "hand", "left_finger", "right_finger"]
    body = "".join(link(name) for name in links) + f'<link name="{frame}"/>\n'
    for i in range(1, 5):
        body += joint(f"joint{i}", "revolute", links[i - 1], links[i])
    body += joint("hand_joint", "fixed", "link4", "hand")
    body += joint("left_finger_joint", "prismatic", "hand", "left_finger", "0 1 0")
    body += joint("right_finger_joint", "prismatic", "hand", "right_finger", "0 -1 0")
    body += joint(f"{frame}_joint", "fixed", frame_parent, frame)
    return _robot(tmp_path / "arm.urdf", "my_arm", body)


@pytest.mark.parametrize(
    "frame",
    [
        "tcp",
        "hand_tcp",
        "grasp_frame",
        "ee_link",
        "/arm/ee_gripper_link",
        "r_gripper_tool_frame",
        "tool0",
    ],
)
def test_a_link_named_as_a_tcp_welded_to_the_hand_is_the_tcp(tmp_path: Path, frame: str) -> None:
    """Not the midpoint between the fingers: the description's own frame, found across the
    hand's fixed joint to the arm (a revolute joint above it ends the search)."""
    spec = scaffold(_arm_with_gripper(tmp_path, frame), tmp_path / "arm.yaml")
    assert spec["tcp"] == frame
    assert spec["grasping"]["is_grasping"]["fingers"][0]["link"] == "left_finger"
    validate(tmp_path / "arm.yaml")


def test_a_frame_named_as_a_tcp_but_beyond_a_moving_joint_is_not_the_gripper_s_tcp(
    tmp_path: Path,
) -> None:
    urdf = _arm_with_gripper(tmp_path, "tool0", frame_parent="link2")
    spec = scaffold(urdf, tmp_path / "arm.yaml")
    assert spec["tcp"] == {
        "link": "hand",
        "midpoint": ["left_finger", "right_finger"],
        "orientation": "hand",
    }


def test_a_sensor_s_tool_link_welded_to_the_hand_is_not_taken_for_the_tcp(tmp_path: Path) -> None:
    """TALOS's wrist_left_ft_tool_link (a force-torque sensor's flange): "tool" is no tcp."""
    spec = scaffold(_arm_with_gripper(tmp_path, "wrist_ft_tool_link"), tmp_path / "arm.yaml")
    assert isinstance(spec["tcp"], dict) and spec["tcp"]["link"] == "hand"


def test_of_several_tcp_names_the_one_that_says_tcp_wins(tmp_path: Path) -> None:
    urdf = _arm_with_gripper(tmp_path, "tool0", frame_parent="link4")
    text = urdf.read_text().replace(
        "</robot>",
        '<link name="panda_hand_tcp"/><joint name="t" type="fixed"><parent link="hand"/>'
        '<child link="panda_hand_tcp"/></joint>\n</robot>',
    )
    urdf.write_text(text)
    assert scaffold(urdf, tmp_path / "arm.yaml")["tcp"] == "panda_hand_tcp"


def test_an_arm_without_a_gripper_takes_its_tool_flange_as_the_tcp_unless_two_arms_tie(
    tmp_path: Path,
) -> None:
    chain = "".join(
        f'<link name="l{i}"/><joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
        f'<child link="l{i}"/><axis xyz="0 0 1"/>{LIMIT.format(lo=-1, hi=1)}</joint>\n'
        for i in range(1, 4)
    )
    flange = (
        '<link name="tool0"/><joint name="f" type="fixed"><parent link="l3"/>'
        '<child link="tool0"/></joint>\n'
    )
    one = _robot(tmp_path / "one.urdf", "bare_arm", '<link name="l0"/>\n' + chain + flange)
    assert scaffold(one, tmp_path / "one.yaml")["tcp"] == "tool0"
    validate(tmp_path / "one.yaml")
    # two arms with a flange each, as deep: the scaffold does not choose between them
    left = chain.replace('"l', '"left_l').replace('"j', '"left_j').replace('"left_l0"', '"l0"')
    right = chain.replace('"l', '"right_l').replace('"j', '"right_j').replace('"right_l0"', '"l0"')
    flanges = flange.replace("tool0", "left_tool0").replace('"l3"', '"left_l3"').replace(
        'name="f"', 'name="lf"'
    ) + flange.replace("tool0", "right_tool0").replace('"l3"', '"right_l3"').replace(
        'name="f"', 'name="rf"'
    )
    two = _robot(tmp_path / "two.urdf", "two_arms", '<link name="l0"/>\n' + left + right + flanges)
    assert "tcp" not in scaffold(two, tmp_path / "two.yaml")


def _six_links(tmp_path: Path) -> Path:
    """A chain of six links on revolute joints from a base: l0 hangs from it, l1 from l0, ..."""
    links = '<link name="base"/>\n' + "".join(
        f'<link name="l{i}"/><joint name="j{i}" type="revolute">'
        f'<parent link="{"base" if i == 0 else f"l{i - 1}"}"/><child link="l{i}"/>'
        f'<axis xyz="0 0 1"/>{LIMIT.format(lo=-1, hi=1)}</joint>\n'
        for i in range(6)
    )
    return _robot(tmp_path / "six.urdf", "six", links)


def _answer_with(monkeypatch: pytest.MonkeyPatch, found: rest_pose.RestPose) -> None:
    """``new`` as if the rest-pose search in ManiSkill had answered ``found``."""
    monkeypatch.setattr(rest_pose, "maniskill_installed", lambda: True)
    monkeypatch.setattr(rest_pose, "probe_rest_pose", lambda *args, **kwargs: (found, None))


def test_the_header_gives_each_never_collide_pair_its_own_reason(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """One line per pair, saying why that pair: not one paragraph of every reason there is."""
    urdf = _six_links(tmp_path)
    # base + l0 one joint apart, l1 + l4 three: the second is coarse shapes, not the joint
    overlapping, coarse = ("base", "l0"), ("l1", "l4")
    yoke, welded, shapeless = ("l2", "l3"), ("base", "l5"), ("l0", "l5")
    found = rest_pose.rest_from_answer(
        {
            "qpos": [0.0] * 6,
            "touching": [[*overlapping, 0.002], [*coarse, 0.003]],
            "always": [list(overlapping), list(coarse)],
            "tried": THOROUGH,
            "adjacent": [list(yoke), list(welded), list(shapeless)],
            "adjacent_why": ["yoke", "welded", "shapeless"],
        },
        read_description_file(urdf)[0].description,  # type: ignore[union-attr]
    )
    _answer_with(monkeypatch, found)
    out = tmp_path / "six.yaml"
    result = run_new(urdf, out, "six", force=True, simulate=True).write()
    assert not result.failed, [d.format_text() for d in result.diagnostics]
    text = out.read_text()
    header = [line for line in text.splitlines() if line.startswith("#   ")]
    assert header == [
        f"#   base + l0: {OVERLAPPING_WHY}",
        f"#   l1 + l4: {COARSE_WHY}",
        f"#   l2 + l3: {ADJACENT_WHY['yoke']}",
        f"#   base + l5: {ADJACENT_WHY['welded']}",
        f"#   l0 + l5: {ADJACENT_WHY['shapeless']}",
    ]
    assert "These are joined only through" not in text  # the old run-on paragraph


def test_a_long_never_collide_list_is_written_one_pair_a_line_a_short_one_on_one_line() -> None:
    from robospec.importer.specdata import SpecDoc
    from robospec.importer.yamlout import to_yaml

    short = to_yaml(SpecDoc({"robospec": 1, "never_collide": [["a", "b"], ["c", "d"]]}), "s")
    assert "\nnever_collide: [[a, b], [c, d]]\n" in short
    pairs = [[f"left_upper_leg_{i}", f"chassis_{i}"] for i in range(4)]
    long = to_yaml(SpecDoc({"robospec": 1, "never_collide": pairs}), "s")
    listed = "".join(f"  - [{a}, {b}]\n" for a, b in pairs)
    assert f"\nnever_collide:\n{listed}" in long
    assert YAML(typ="safe").load(long)["never_collide"] == pairs
