"""``description: {mjcf: FILE, loader: mujoco}``: the MJCF compiled by MuJoCo and written as a
derived URDF (robospec.derive.mujoco_urdf), which resolve treats as the robot's URDF — its
joints and links as MuJoCo has them, written never beside the user's file, carried into a built
package with its meshes — while a spec without ``loader`` keeps ManiSkill's MJCF loader. (That
ManiSkill then simulates MuJoCo's masses and poses: tests/test_mujoco_urdf_sim.py.)"""

from __future__ import annotations

import math
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import MANISKILL_SPECS, ROOT
from lxml import etree

from robospec.description import load_description
from robospec.diagnostics import has_errors
from robospec.pipeline import compile_spec

COMPILED = Path(__file__).parent / "data" / "mjcf" / "compiled"

SPEC = """\
robospec: 1
uid: ball_ghost
description: {{mjcf: {path}, loader: mujoco}}
groups: {{all: "*"}}
controllers:
  all: {{type: pd_joint_pos, joints: all, lower: null, upper: null, stiffness: 100,
         damping: 10, normalize_action: false}}
control_modes:
  pd_joint_pos: {{all: all}}
"""


def _robot_folder(tmp_path: Path) -> Path:
    """A copy of ball_ghost.xml and the mesh it names, in a folder of its own."""
    folder = tmp_path / "robot"
    (folder / "meshes").mkdir(parents=True)
    text = (COMPILED / "ball_ghost.xml").read_text(encoding="utf-8")
    text = text.replace("../gaps/meshes/cube_m.stl", "meshes/cube_m.stl")
    (folder / "ball_ghost.xml").write_text(text, encoding="utf-8")
    shutil.copy(COMPILED.parent / "gaps" / "meshes" / "cube_m.stl", folder / "meshes")
    return folder


def _spec(tmp_path: Path) -> Path:
    folder = _robot_folder(tmp_path)
    spec = tmp_path / "ball_ghost.yaml"
    spec.write_text(SPEC.format(path="robot/ball_ghost.xml"), encoding="utf-8")
    assert folder.is_dir()
    return spec


def test_the_robot_has_mujocos_bodies_as_links_and_a_ball_joint_as_three_hinges(
    tmp_path: Path,
) -> None:
    result = compile_spec(_spec(tmp_path))
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    robot, description = result.robot, result.description
    assert robot is not None and description is not None
    assert robot.description_kind == "urdf"  # ManiSkill's URDF loader loads it
    assert description.root_link == "base"
    bodies = {"base", "shoulder", "forearm", "hand", "ghost", "body6"}  # body6: unnamed
    assert bodies <= set(description.link_names)
    kinds = {j.name: j.type for j in description.joints}
    assert [kinds[f"socket_{axis}"] for axis in "xyz"] == ["continuous"] * 3
    assert kinds["elbow"] == "revolute" and kinds["twist"] == "continuous"
    assert kinds["slide"] == "prismatic" and kinds["wrist"] == "revolute"
    assert robot.active_joints == (
        "socket_x",
        "socket_y",
        "socket_z",
        "elbow",
        "twist",
        "slide",
        "wrist",
    )
    elbow = next(j for j in description.joints if j.name == "elbow")
    # the range counts from ref (10 degrees): 0 is the pose the file writes
    assert elbow.lower == pytest.approx(-1.5707963, abs=1e-6)
    assert elbow.upper == pytest.approx(1.2217305, abs=1e-6)


def test_the_derived_urdf_is_written_in_the_cache_never_beside_the_users_file(
    tmp_path: Path,
) -> None:
    spec = _spec(tmp_path)
    before = sorted(p.name for p in (tmp_path / "robot").rglob("*"))
    result = compile_spec(spec)
    assert result.robot is not None
    ref = result.robot.description
    assert ref.derived and ref.generated_text is not None and not ref.has_srdf_beside
    assert sorted(p.name for p in (tmp_path / "robot").rglob("*")) == before
    # the mesh and the ellipsoid: OBJ files named by their content, in robospec's cache
    meshes = sorted({path for _uri, path in ref.mesh_paths})
    assert len(meshes) == 2 and all(Path(m).suffix == ".obj" for m in meshes)
    assert all((tmp_path / "robot") not in Path(m).parents for m in meshes)
    # the MJCF's mesh file is one its register cache entry depends on
    assert str(tmp_path / "robot" / "meshes" / "cube_m.stl") in ref.sources


@pytest.mark.slow  # a child process: over a second
def test_a_built_package_carries_the_urdf_and_copies_of_its_meshes(tmp_path: Path) -> None:
    spec = _spec(tmp_path)
    out = tmp_path / "pkg"
    done = subprocess.run(
        [sys.executable, "-m", "robospec.cli", "build", str(spec), "-o", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    urdf = out / "ball_ghost.urdf"
    objs = sorted(p.name for p in out.glob("ball_ghost.*.obj"))
    assert urdf.is_file() and len(objs) == 2
    text = urdf.read_text(encoding="utf-8")
    assert all(f'filename="{name}"' in text for name in objs)
    assert str(tmp_path) not in text  # nothing names the machine's paths
    description, diagnostics = load_description(str(urdf), "urdf")
    assert description is not None and not has_errors(diagnostics)
    assert "socket_x" in description.active_joint_names


def test_without_loader_an_mjcf_stays_maniskills_own_mjcf_loaders() -> None:
    result = compile_spec(MANISKILL_SPECS / "humanoid.yaml")
    assert result.robot is not None
    assert result.robot.description_kind == "mjcf"
    assert not result.robot.description.derived


def test_loader_is_refused_for_a_urdf(tmp_path: Path) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        SPEC.format(path="robot.urdf").replace("mjcf: robot.urdf", "urdf: robot.urdf"),
        encoding="utf-8",
    )
    (tmp_path / "robot.urdf").write_text('<robot name="r"><link name="a"/></robot>\n')
    errors = [d for d in compile_spec(spec).diagnostics if d.is_error]
    assert [(d.code, d.location.line) for d in errors] == [("RS102", 3)]
    assert "loader is only for mjcf descriptions" in errors[0].message


def test_a_file_mujoco_refuses_is_an_error_at_the_line_mujoco_names(tmp_path: Path) -> None:
    folder = _robot_folder(tmp_path)
    broken = (folder / "ball_ghost.xml").read_text(encoding="utf-8")
    broken = broken.replace('<joint name="twist" axis="0 0 1"/>', '<joint name="twist" axes="1"/>')
    (folder / "ball_ghost.xml").write_text(broken, encoding="utf-8")
    spec = tmp_path / "ball_ghost.yaml"
    spec.write_text(SPEC.format(path="robot/ball_ghost.xml"), encoding="utf-8")
    result = compile_spec(spec)
    errors = [d for d in result.diagnostics if d.is_error]
    assert [d.code for d in errors] == ["RS790"]
    line = broken.splitlines().index(next(t for t in broken.splitlines() if 'axes="1"' in t)) + 1
    assert errors[0].location.line == line and errors[0].location.file.endswith("ball_ghost.xml")
    assert "axes" in errors[0].message


@pytest.mark.slow  # new reads the file twice (MuJoCo's route and ManiSkill's): over a second
def test_new_writes_loader_mujoco_saying_what_maniskills_loader_would_get_wrong(
    tmp_path: Path,
) -> None:
    from ruamel.yaml import YAML

    from robospec.authoring.commands import run_new

    folder = _robot_folder(tmp_path)
    out = tmp_path / "new.yaml"
    result = run_new(folder / "ball_ghost.xml", out, None, force=False, simulate=False).write()
    assert not result.failed, [d.format_text() for d in result.diagnostics]
    text = out.read_text(encoding="utf-8")
    (line,) = [t for t in text.splitlines() if t.strip().startswith("loader: mujoco")]
    assert "not load its ball joints (socket)" in line
    assert "give its 1 body of visual geoms only no mass" in line
    data = YAML(typ="safe").load(text)
    assert data["description"] == {"mjcf": "robot/ball_ghost.xml", "loader": "mujoco"}
    assert {"socket_x", "socket_y", "socket_z"} <= {
        j for joints in data["groups"].values() for j in joints
    }
    validated = compile_spec(out)
    assert not has_errors(validated.diagnostics)


def test_a_keyframe_without_a_pose_leaves_the_root_body_where_the_file_puts_it(
    tmp_path: Path,
) -> None:
    folder = _robot_folder(tmp_path)
    model = folder / "ball_ghost.xml"
    text = model.read_text(encoding="utf-8").replace(
        '<body name="base">', '<body name="base" pos="0 0 0.5" euler="0 0 90">'
    )
    model.write_text(text, encoding="utf-8")
    spec = _spec_at(tmp_path, "robot/ball_ghost.xml", "keyframes: {rest: {qpos: {all: 0}}}\n")
    result = compile_spec(spec)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    (rest,) = result.robot.keyframes
    assert rest.p == pytest.approx((0.0, 0.0, 0.5))
    assert rest.q == pytest.approx((0.7071068, 0.0, 0.0, 0.7071068), abs=1e-6)


def test_the_trees_a_scenes_actuators_drive_are_one_robot_its_free_cube_is_not(
    tmp_path: Path,
) -> None:
    """Two arms, each its own body tree welded to the world (a bimanual scene as gym-aloha
    writes it), and a free cube: the robot is both arms, hung from `world`, with the file's
    keyframe and actuators on both; the table and the cube are the scene's (RS791)."""
    spec = _spec_at(tmp_path, (COMPILED / "two_arms.xml").as_posix())
    result = compile_spec(spec)
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    robot, description = result.robot, result.description
    assert robot is not None and description is not None
    assert description.root_link == "world" and not description.floating_root
    arms = ("left_shoulder", "right_shoulder", "left_elbow", "right_elbow")
    assert sorted(robot.active_joints) == sorted(arms)
    assert "cube" not in description.link_names and "table" not in description.link_names
    (ready,) = description.keyframes
    assert dict(ready.qpos) == pytest.approx(
        {"left_shoulder": 0.3, "left_elbow": -0.6, "right_shoulder": -0.3, "right_elbow": 0.6}
    )
    assert {a.joint for a in description.actuators} == set(arms)
    (dropped,) = [d for d in result.diagnostics if "other body trees" in d.message]
    assert dropped.code == "RS791" and "bodies table, cube" in dropped.message


def _spec_at(tmp_path: Path, path: str, more: str = "") -> Path:
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC.format(path=path) + more, encoding="utf-8")
    return spec


_ARM = """\
<mujoco model="arm">
  <compiler angle="degree"/>
  <worldbody>
    <body name="upper">
      <joint name="shoulder" axis="0 1 0" range="-90 90"/>
      <geom type="capsule" size=".04 .15" pos="0 0 .15"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize(
    ("edit", "tag", "said"),
    [
        # a deprecated attribute: MuJoCo's warning names the <compiler>, no element
        (
            ('<compiler angle="degree"/>', '<compiler angle="degree" settotalmass="5"/>'),
            "compiler",
            "settotalmass",
        ),
        # a flex nothing holds together: the warning names the element (no robot is written:
        # a flex's vertex bodies slide without limits, which the URDF writer does not carry)
        (
            (
                "  <worldbody>\n",
                '  <worldbody>\n    <flexcomp name="cloth" type="grid" count="3 3 1" '
                'spacing=".05 .05 .05" radius=".01" dim="2" pos="3 0 0"/>\n',
            ),
            "flexcomp",
            "cloth",
        ),
    ],
)
def test_what_mujoco_warns_about_while_compiling_is_rs792_at_the_element_it_names(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    edit: tuple[str, str],
    tag: str,
    said: str,
) -> None:
    text = _ARM.replace(edit[0], edit[1], 1)
    assert text != _ARM
    (tmp_path / "arm.xml").write_text(text, encoding="utf-8")
    spec = tmp_path / "arm.yaml"
    spec.write_text(SPEC.format(path="arm.xml"), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    result = compile_spec(spec)
    found = [d for d in result.diagnostics if d.code == "RS792"]
    assert len(found) == 1 and not found[0].is_error, [str(d) for d in result.diagnostics]
    lines = text.splitlines()
    line = next(i for i, t in enumerate(lines, 1) if f"<{tag}" in t)
    where = found[0].location
    assert (where.line, where.column) == (line, lines[line - 1].index(f"<{tag}") + 1)
    assert where.file.endswith("arm.xml") and said in found[0].message
    if tag == "compiler":  # MuJoCo compiles the file, masses scaled: the robot is written
        assert result.robot is not None
    # MuJoCo's own handler would have appended it to a log in the working folder
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_a_compile_error_that_names_no_line_is_at_the_element_it_names(tmp_path: Path) -> None:
    # MuJoCo refuses joint damping on a flex's vertex bodies, naming the flex but no line
    flex = (
        '    <flexcomp name="cloth" type="grid" count="3 3 1" spacing=".05 .05 .05" '
        'radius=".01" dim="2" pos="3 0 0"/>\n'
    )
    text = _ARM.replace(
        "  <worldbody>\n", '  <default><joint damping="1"/></default>\n  <worldbody>\n' + flex
    )
    (tmp_path / "arm.xml").write_text(text, encoding="utf-8")
    spec = tmp_path / "arm.yaml"
    spec.write_text(SPEC.format(path="arm.xml"), encoding="utf-8")
    errors = [d for d in compile_spec(spec).diagnostics if d.is_error]
    assert [d.code for d in errors] == ["RS790"] and "line" not in errors[0].message
    line = text.splitlines().index(flex.rstrip("\n")) + 1
    where = errors[0].location
    assert (where.file.endswith("arm.xml"), where.line, where.column) == (True, line, 5)


FOURBAR = ROOT / "tests" / "data" / "new" / "fourbar.xml"


def test_a_connect_equality_is_carried_as_a_closed_loop_and_other_equalities_are_rs791(
    tmp_path: Path,
) -> None:
    # the four-bar's <connect>: a closure between its two bodies, anchored in the first's
    # frame as MuJoCo compiled it; nothing said of it
    folder = tmp_path / "robot"
    folder.mkdir()
    shutil.copy(FOURBAR, folder / "fourbar.xml")
    result = compile_spec(_spec_at(tmp_path, "robot/fourbar.xml"))
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    assert result.description is not None
    (closure,) = result.description.closures
    assert (closure.kind, closure.first, closure.second) == ("connect", "follower", "coupler")
    assert closure.anchor == pytest.approx((0.0, 0.0, 0.07))
    said = [d.message for d in result.diagnostics if d.code == "RS791"]
    assert not any("equality" in message for message in said), said
    # a joint equality beside it is not carried: RS791 counts it alone
    text = FOURBAR.read_text(encoding="utf-8").replace(
        "  </equality>",
        '    <joint name="tied" joint1="coupler_joint" joint2="crank_joint"/>\n  </equality>',
    )
    (folder / "fourbar.xml").write_text(text, encoding="utf-8")
    result = compile_spec(_spec_at(tmp_path, "robot/fourbar.xml"))
    assert result.description is not None and len(result.description.closures) == 1
    said = [d.message for d in result.diagnostics if d.code == "RS791"]
    assert any("equality constraints (<equality>): 1 in the model" in m for m in said), said


_SITES = """\
<mujoco model="arm">
  <worldbody>
    <site name="midair" pos="0 0 2"/>
    <body name="upper">
      <joint name="shoulder" axis="0 1 0" range="-1 1"/>
      <geom type="capsule" size=".04 .15" pos="0 0 .15"/>
      <site name="tip" pos="0 0 .3" quat="0 1 0 0"/>
      <site name="upper" pos="0 0 .1"/>
    </body>
    <body name="table" pos="1 0 0">
      <geom type="box" size=".3 .3 .02"/>
      <site name="on_table" pos="0 0 .02"/>
    </body>
  </worldbody>
</mujoco>
"""

_SITES_SPEC = """\
robospec: 1
uid: sited
description:
  mjcf: arm.xml
  loader: mujoco
  sites: {sites}
controllers:
  arm: {{type: pd_joint_pos, joints: [shoulder], lower: null, upper: null, stiffness: 100,
         damping: 10, normalize_action: false}}
control_modes:
  pd_joint_pos: {{arm: arm}}
tcp: tip
"""


def _sited(tmp_path: Path, sites: str, loader: str = "mujoco") -> Path:
    (tmp_path / "arm.xml").write_text(_SITES, encoding="utf-8")
    spec = tmp_path / "spec.yaml"
    text = _SITES_SPEC.format(sites=sites).replace("loader: mujoco", f"loader: {loader}")
    spec.write_text(text, encoding="utf-8")
    return spec


def test_a_site_the_spec_names_is_a_link_fixed_to_its_body_where_the_site_sits(
    tmp_path: Path,
) -> None:
    result = compile_spec(_sited(tmp_path, "[tip]"))
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]
    robot, description = result.robot, result.description
    assert robot is not None and description is not None
    assert robot.tcp is not None  # the tcp names the site's link
    (joint,) = [j for j in description.joints if j.child == "tip"]
    assert (joint.type, joint.parent) == ("fixed", "upper")
    text = robot.description.generated_text
    assert text is not None
    origin = etree.fromstring(text.encode()).find(f"joint[@name='{joint.name}']/origin")
    assert origin is not None
    assert [float(v) for v in origin.get("xyz", "").split()] == pytest.approx([0.0, 0.0, 0.3])
    # MuJoCo's quat "0 1 0 0": a half turn about x
    rpy = [abs(float(v)) for v in origin.get("rpy", "").split()]
    assert rpy == pytest.approx([math.pi, 0.0, 0.0])
    # the sites the spec does not name stay sites
    assert "midair" not in description.link_names and "upper_site" not in description.link_names


@pytest.mark.parametrize(
    ("sites", "said"),
    [
        ("[tip, tpi]", "has no site 'tpi'; its robot's sites: midair, tip, upper"),
        ("[tip, on_table]", "site 'on_table' sits on body 'table', which is not the robot's"),
        ("[tip, upper]", "a link is named 'upper' already"),
    ],
)
def test_a_site_that_cannot_be_a_link_is_rs793_at_the_specs_entry(
    tmp_path: Path, sites: str, said: str
) -> None:
    result = compile_spec(_sited(tmp_path, sites))
    errors = [d for d in result.diagnostics if d.is_error]
    assert [(d.code, d.location.line, d.location.column) for d in errors] == [("RS793", 6, 16)]
    assert said in errors[0].message
    assert errors[0].location.file.endswith("spec.yaml")


def test_sites_need_the_mjcf_compiled_by_mujoco(tmp_path: Path) -> None:
    errors = [d for d in compile_spec(_sited(tmp_path, "[tip]", "maniskill")).diagnostics]
    assert [d.code for d in errors if d.is_error] == ["RS102"]
    assert "add loader: mujoco" in errors[0].message
