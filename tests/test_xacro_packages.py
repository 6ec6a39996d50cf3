"""xacro robots keep their meshes: ``$(find NAME)`` answered without ROS, and the expansion's
mesh paths rewritten so that they resolve from wherever robospec writes it (the register cache,
a built package).

rtb-data's Trossen arms and PUMA 560 passed ``check`` with every collision mesh lost: their
expansion, written elsewhere, named meshes by paths relative to the xacro file and by
``package://`` URIs SAPIEN could no longer find. The ``maniskill`` tests load such a robot
registered and built, and count its collision shapes against the description.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT
from mesh_files import STL
from test_description_meshes import package_xml, spec_text, write

from robospec.description.xacro import expand_xacro
from robospec.pipeline import compile_spec

XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="part" params="name mesh">
    <link name="${name}">
      <inertial>
        <mass value="1"/>
        <inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/>
      </inertial>
      <collision><geometry><mesh filename="${mesh}"/></geometry></collision>
    </link>
  </xacro:macro>
  <link name="base_link"/>
  <xacro:part name="upper_arm" mesh="package://arm_description/meshes/upper.stl"/>
  <xacro:part name="forearm" mesh="$(find arm_tools)/meshes/fore.stl"/>
  <xacro:part name="hand" mesh="../meshes/hand.stl"/>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="upper_arm"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <joint name="elbow" type="fixed"><parent link="upper_arm"/><child link="forearm"/></joint>
  <joint name="wrist" type="fixed"><parent link="forearm"/><child link="hand"/></joint>
</robot>
"""


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    """arm_description (the folder clearpath_arm, named by its package.xml) holds the xacro
    file and two meshes; arm_tools lives where only the spec's packages map finds it."""
    package = tmp_path / "src" / "clearpath_arm"
    write(package / "package.xml", package_xml("arm_description"))
    write(package / "urdf" / "arm.urdf.xacro", XACRO)
    write(package / "meshes" / "upper.stl", STL)
    write(package / "meshes" / "hand.stl", STL)
    write(tmp_path / "vendor" / "tools" / "meshes" / "fore.stl", STL)
    return tmp_path


def test_find_is_a_package_from_the_packages_map_or_the_folders_above(workspace: Path) -> None:
    xacro = workspace / "src" / "clearpath_arm" / "urdf" / "arm.urdf.xacro"
    text, diagnostics = expand_xacro(
        str(xacro), {}, packages={"arm_tools": str(workspace / "vendor" / "tools")}
    )
    assert diagnostics == [] and text is not None
    assert f'filename="{workspace / "vendor" / "tools" / "meshes" / "fore.stl"}"' in text


def test_find_of_a_package_found_nowhere_is_rs058_where_it_is_written(workspace: Path) -> None:
    xacro = workspace / "src" / "clearpath_arm" / "urdf" / "arm.urdf.xacro"
    text, [problem] = expand_xacro(str(xacro), {})
    assert text is None
    assert (problem.code, problem.location.line, problem.location.column) == ("RS058", 14, 36)
    assert "ROS package 'arm_tools' not found for $(find arm_tools)" in problem.message
    assert problem.hint is not None and "packages: {arm_tools: FOLDER}" in problem.hint


def spec(workspace: Path, uid: str) -> Path:
    return write(
        workspace / "specs" / f"{uid}.yaml",
        spec_text(
            "{xacro: ../src/clearpath_arm/urdf/arm.urdf.xacro, "
            "packages: {arm_tools: ../vendor/tools}}",
            uid=uid,
        ),
    )


def test_the_expansion_names_every_mesh_where_it_is_from_the_generated_module(
    workspace: Path,
) -> None:
    from robospec.output.modules import robot_files

    compiled = compile_spec(spec(workspace, "xacro_arm"))
    assert compiled.ok, compiled.diagnostics
    assert compiled.robot is not None
    module_dir = workspace / "somewhere" / "else"
    carried = robot_files(compiled.robot, "xacro_arm", module_dir)["xacro_arm.urdf"]
    assert "package://" not in carried and str(workspace) not in carried
    for name in ("clearpath_arm/meshes/upper.stl", "tools/meshes/fore.stl", "meshes/hand.stl"):
        assert name in carried
    for line in carried.splitlines():
        if "filename=" in line:
            relative = line.split('filename="')[1].split('"')[0]
            assert (module_dir / relative).resolve().is_file(), relative


def _shapes(uid: str) -> dict[str, int]:
    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        links = env.unwrapped.agent.robot.links
        return {link.name: len(link._objs[0].collision_shapes) for link in links}
    finally:
        env.close()


EVERY_SHAPE = {"base_link": 0, "upper_arm": 1, "forearm": 1, "hand": 1}


@pytest.mark.usefixtures("maniskill")
def test_a_registered_xacro_robot_has_every_collision_mesh(workspace: Path) -> None:
    import robospec

    robospec.register(spec(workspace, "rs_test_xacro_registered"), cache_dir=workspace / "cache")
    assert _shapes("rs_test_xacro_registered") == EVERY_SHAPE


@pytest.mark.usefixtures("maniskill")
def test_a_built_xacro_robot_has_every_collision_mesh(workspace: Path) -> None:
    out = workspace / "out" / "xacro_built"
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "robospec.cli",
            "build",
            str(spec(workspace, "rs_test_xacro_built")),
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    sys.path.insert(0, str(out.parent))
    try:
        importlib.import_module("xacro_built")
        assert _shapes("rs_test_xacro_built") == EVERY_SHAPE
    finally:
        sys.path.remove(str(out.parent))
