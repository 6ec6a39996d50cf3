"""The files a URDF's visuals and collisions name: found (package:// the ROS way), readable, and
loaded by the generated agent even where SAPIEN's own loader would not find them.

The fast tests build small description trees in a temporary folder; the ``maniskill`` ones
prove each claim against SAPIEN itself: what its loader resolves, which files it reads, that a
missing collision mesh loads as a link without collision shapes, and that a robot registered or
built by robospec has every collision shape its description names.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT
from mesh_files import BINARY_STL, STL

from robospec.description import load_description
from robospec.description.mesh_formats import unreadable_reason
from robospec.description.packages import PackageFinder, sapien_mesh_path
from robospec.diagnostics import Severity
from robospec.pipeline import compile_spec

INERTIAL = '<mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/>'


def urdf(*collisions: str, visuals: tuple[str, ...] = (), name: str = "arm") -> str:
    """A two-link arm whose upper arm has these collision (and visual) mesh file names."""
    shapes = "".join(
        f'\n    <visual><geometry><mesh filename="{v}"/></geometry></visual>' for v in visuals
    ) + "".join(
        f'\n    <collision><geometry><mesh filename="{c}"/></geometry></collision>'
        for c in collisions
    )
    return f"""<?xml version="1.0"?>
<robot name="{name}">
  <link name="base_link"/>
  <link name="upper_arm">
    <inertial>{INERTIAL}</inertial>{shapes}
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="upper_arm"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
</robot>
"""


def spec_text(description: str, uid: str = "mesh_arm") -> str:
    return textwrap.dedent(
        f"""\
        robospec: 1
        uid: {uid}
        description: {description}
        controllers:
          arm: {{type: pd_joint_pos, joints: shoulder, lower: null, upper: null,
                stiffness: 100, damping: 10, normalize_action: false}}
        control_modes:
          pd_joint_pos: {{arm: arm}}
        """
    )


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def package_xml(name: str) -> str:
    return f'<?xml version="1.0"?>\n<package format="2">\n  <name>{name}</name>\n</package>\n'


def diagnose(path: Path, packages: dict[str, str] | None = None) -> list[Any]:
    description, diagnostics = load_description(str(path), "urdf", packages=packages)
    assert description is not None
    return [d for d in diagnostics if d.code >= "RS056"]


# -- found or not -----------------------------------------------------------------------------


def test_a_missing_collision_mesh_is_an_error_and_a_missing_visual_one_a_warning(
    tmp_path: Path,
) -> None:
    path = write(tmp_path / "arm.urdf", urdf("meshes/gone.stl", visuals=("meshes/gone.dae",)))
    visual, collision = diagnose(path)
    assert (visual.code, visual.severity, visual.location.line) == ("RS056", Severity.WARNING, 6)
    assert (collision.code, collision.severity, collision.location.line) == (
        "RS056",
        Severity.ERROR,
        7,
    )
    assert "collision mesh 'meshes/gone.stl' of link 'upper_arm' not found" in collision.message
    assert collision.hint is not None and "without this collision shape" in collision.hint


def test_missing_meshes_of_one_folder_are_one_diagnostic_that_lists_their_lines(
    tmp_path: Path,
) -> None:
    path = write(tmp_path / "arm.urdf", urdf("m/a.stl", "m/b.stl", "m/c.stl"))
    [problem] = diagnose(path)
    assert problem.location.line == 6
    assert "(and 2 more collision meshes in 'm' not found: lines 7, 8)" in problem.message


def test_relative_absolute_and_file_uris_name_files_on_disk(tmp_path: Path) -> None:
    mesh = write(tmp_path / "meshes" / "part.stl", STL)
    path = write(tmp_path / "arm.urdf", urdf("meshes/part.stl", str(mesh), f"file://{mesh}"))
    assert diagnose(path) == []
    description, _ = load_description(str(path), "urdf")
    assert description is not None
    assert {m.path for m in description.mesh_files} == {str(mesh)}


def test_a_file_uri_is_found_by_robospec_but_not_by_sapien(tmp_path: Path) -> None:
    mesh = write(tmp_path / "meshes" / "part.stl", STL)
    path = write(tmp_path / "arm.urdf", urdf(f"file://{mesh}"))
    description, _ = load_description(str(path), "urdf")
    assert description is not None
    [found] = description.mesh_files
    assert (found.path, found.loader_path) == (str(mesh), None)


# -- package:// -------------------------------------------------------------------------------


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    """A ROS-like tree: a description package whose folder is not its name (as rtb-data's
    Ridgeback), a mesh package named by its folder, and one nothing names."""
    src = tmp_path / "ws" / "src"
    write(src / "clearpath_arm_description" / "package.xml", package_xml("arm_description"))
    write(src / "clearpath_arm_description" / "meshes" / "body.stl", STL)
    write(src / "arm_parts" / "meshes" / "part.stl", STL)
    write(src / "elsewhere" / "support" / "meshes" / "tool.stl", STL)
    return src


def test_a_package_is_the_folder_above_whose_package_xml_names_it(workspace: Path) -> None:
    path = write(
        workspace / "clearpath_arm_description" / "urdf" / "arm.urdf",
        urdf("package://arm_description/meshes/body.stl"),
    )
    description, diagnostics = load_description(str(path), "urdf")
    assert description is not None and diagnostics == []
    [found] = description.mesh_files
    assert found.path == str(workspace / "clearpath_arm_description" / "meshes" / "body.stl")
    assert found.loader_path is None  # SAPIEN looks for a folder called arm_description


def test_a_package_is_a_folder_of_its_name_holding_the_file_as_sapien_finds_it(
    workspace: Path,
) -> None:
    path = write(
        workspace / "clearpath_arm_description" / "urdf" / "arm.urdf",
        urdf("package://arm_parts/meshes/part.stl"),
    )
    description, diagnostics = load_description(str(path), "urdf")
    assert description is not None and diagnostics == []
    [found] = description.mesh_files
    assert found.path == found.loader_path == str(workspace / "arm_parts" / "meshes" / "part.stl")


def test_the_packages_map_names_a_package_nothing_else_finds(workspace: Path) -> None:
    path = write(
        workspace / "clearpath_arm_description" / "urdf" / "arm.urdf",
        urdf("package://tool_support/meshes/tool.stl"),
    )
    [problem] = diagnose(path)
    assert problem.code == "RS058" and "tool_support" in problem.message
    assert diagnose(path, {"tool_support": str(workspace / "elsewhere" / "support")}) == []


def test_an_unknown_package_is_one_error_at_its_first_collision_use(workspace: Path) -> None:
    path = write(
        workspace / "arm.urdf",
        urdf(
            "package://nowhere/meshes/a.stl",
            "package://nowhere/meshes/b.stl",
            visuals=("package://nowhere/meshes/v.dae",),
        ),
    )
    [problem] = diagnose(path)
    assert (problem.code, problem.severity, problem.location.line) == (
        "RS058",
        Severity.ERROR,
        7,
    )
    assert "ROS package 'nowhere' not found" in problem.message
    assert "and 2 more files" in problem.message
    assert problem.hint is not None and "packages: {nowhere: FOLDER}" in problem.hint


def test_three_slashes_after_package_name_no_package(workspace: Path) -> None:
    path = write(workspace / "arm.urdf", urdf("package:///arm_parts/meshes/part.stl"))
    [problem] = diagnose(path)
    assert problem.code == "RS058" and "three slashes" in problem.message


def test_find_answers_a_package_by_package_xml_map_or_folder_name(workspace: Path) -> None:
    finder = PackageFinder(
        str(workspace / "clearpath_arm_description" / "urdf"),
        {"tool_support": str(workspace / "elsewhere" / "support")},
    )
    assert finder.find("arm_description") == str(workspace / "clearpath_arm_description")
    assert finder.find("arm_parts") == str(workspace / "arm_parts")
    assert finder.find("tool_support") == str(workspace / "elsewhere" / "support")
    assert finder.find("nowhere") is None


# -- readable or not --------------------------------------------------------------------------

# file name -> content, and whether SAPIEN reads it (tests/test_description_meshes.py proves
# these against SAPIEN below)
MESH_FILES: dict[str, tuple[bytes, bool]] = {
    "ascii.stl": (STL.encode(), True),
    "upper.STL": (STL.encode(), True),
    "binary.stl": (BINARY_STL, True),
    "binary_with_solid_header.stl": (b"solid" + BINARY_STL[5:], True),
    "one_byte_too_many.stl": (BINARY_STL + b"\0", False),
    "empty.stl": (b"", False),
    "lfs.stl": (b"version https://git-lfs.github.com/spec/v1\noid sha256:0\nsize 1\n", False),
    "no_vertices.obj": (b"# a comment and nothing else\n", False),
    "mesh.vtk": (b"# vtk DataFile Version 3.0\n", False),
    "ascii_stl_named.txt": (STL.encode(), True),  # recognised by its first bytes
    "binary_stl_named.txt": (BINARY_STL, False),  # a binary STL has no signature
    "no_suffix": (BINARY_STL, False),
    "obj_without_suffix": (b"o part\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n", True),
}


@pytest.mark.parametrize("name", sorted(MESH_FILES))
def test_what_robospec_says_sapien_cannot_read(tmp_path: Path, name: str) -> None:
    content, readable = MESH_FILES[name]
    path = tmp_path / name
    path.write_bytes(content)
    assert (unreadable_reason(str(path)) is None) == readable


def test_an_unreadable_collision_mesh_is_an_error_that_says_why(tmp_path: Path) -> None:
    write(tmp_path / "part.vtk", "# vtk DataFile Version 3.0\n")
    [problem] = diagnose(write(tmp_path / "arm.urdf", urdf("part.vtk")))
    assert (problem.code, problem.severity) == ("RS057", Severity.ERROR)
    assert "'.vtk' is not a mesh format it reads" in problem.message


def test_textures_are_looked_for_but_not_read_as_meshes(tmp_path: Path) -> None:
    write(tmp_path / "skin.png", "not judged")
    text = urdf().replace(
        "</robot>",
        '  <material name="skin"><texture filename="skin.png"/></material>\n'
        '  <material name="gone"><texture filename="gone.png"/></material>\n</robot>',
    )
    [problem] = diagnose(write(tmp_path / "arm.urdf", text))
    assert (problem.code, problem.severity) == ("RS056", Severity.WARNING)
    assert "texture 'gone.png' of material 'gone' not found" in problem.message


# -- in a spec --------------------------------------------------------------------------------


def test_spec_packages_are_folders_relative_to_the_spec(workspace: Path) -> None:
    write(
        workspace / "clearpath_arm_description" / "urdf" / "arm.urdf",
        urdf("package://tool_support/meshes/tool.stl"),
    )
    spec = write(
        workspace / "specs" / "arm.yaml",
        spec_text(
            "{urdf: ../clearpath_arm_description/urdf/arm.urdf, "
            "packages: {tool_support: ../elsewhere/support}}"
        ),
    )
    compiled = compile_spec(spec)
    assert compiled.ok, compiled.diagnostics
    assert compiled.robot is not None
    # SAPIEN would not find tool_support: the agent carries a URDF that names the file
    assert dict(compiled.robot.description.mesh_paths) == {
        "package://tool_support/meshes/tool.stl": str(
            workspace / "elsewhere" / "support" / "meshes" / "tool.stl"
        )
    }


def test_a_packages_entry_that_is_no_folder_is_an_error_at_its_value(workspace: Path) -> None:
    write(workspace / "arm.urdf", urdf("package://arm_parts/meshes/part.stl"))
    spec = write(
        workspace / "arm.yaml",
        spec_text("{urdf: arm.urdf, packages: {tool_support: ../nothing/here}}"),
    )
    [problem] = compile_spec(spec).diagnostics
    assert (problem.code, problem.location.line) == ("RS058", 3)
    assert "package 'tool_support': no folder '../nothing/here'" in problem.message


def test_a_description_sapien_resolves_the_same_is_loaded_where_it_is(workspace: Path) -> None:
    write(workspace / "arm.urdf", urdf("package://arm_parts/meshes/part.stl"))
    compiled = compile_spec(write(workspace / "arm.yaml", spec_text("{urdf: arm.urdf}")))
    assert compiled.ok and compiled.robot is not None
    assert compiled.robot.description.mesh_paths == ()
    assert not compiled.robot.description.carried


def test_validate_looks_for_meshes_without_a_mesh_library(workspace: Path) -> None:
    write(workspace / "arm.urdf", urdf("package://arm_parts/meshes/part.stl"))
    spec = write(workspace / "arm.yaml", spec_text("{urdf: arm.urdf}"))
    code = (
        "import sys\n"
        "from robospec.cli import main\n"
        f"sys.argv = ['robospec', 'validate', {str(spec)!r}]\n"
        "try:\n    main()\n"
        "except SystemExit as exit:\n    assert not exit.code, exit.code\n"
        "heavy = {'trimesh', 'yourdfpy', 'numpy', 'sapien'} & set(sys.modules)\n"
        "assert not heavy, heavy\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=False
    )
    assert result.returncode == 0, result.stderr


# -- against SAPIEN ---------------------------------------------------------------------------


def _physx_scene() -> Any:
    import sapien

    return sapien.Scene([sapien.physx.PhysxCpuSystem()])


@pytest.mark.usefixtures("maniskill")
def test_sapien_opens_the_files_robospec_says_it_opens(workspace: Path) -> None:
    loader_module = importlib.import_module("sapien.wrapper.urdf_loader")
    urdf_dir = str(workspace / "clearpath_arm_description" / "urdf")
    names = [
        "package://arm_parts/meshes/part.stl",  # a folder of that name, above
        "package://arm_description/meshes/body.stl",  # named only by package.xml
        "package://clearpath_arm_description/meshes/body.stl",  # its folder's name
        "package:///arm_parts/meshes/part.stl",
        "../meshes/body.stl",
        "../meshes/none.stl",
        str(workspace / "arm_parts" / "meshes" / "part.stl"),
    ]
    for name in names:
        sapien_found = loader_module._try_very_hard_to_find_file(name, urdf_dir)
        expected = sapien_mesh_path(name, urdf_dir)
        if expected is None:  # SAPIEN hands back the name (less package://) and PhysX fails
            assert not Path(urdf_dir, sapien_found).is_file(), name
        else:
            assert Path(sapien_found).resolve() == Path(expected).resolve(), name


@pytest.mark.usefixtures("maniskill")
@pytest.mark.parametrize("name", sorted(MESH_FILES))
def test_sapien_reads_exactly_the_meshes_robospec_accepts(tmp_path: Path, name: str) -> None:
    import sapien

    content, readable = MESH_FILES[name]
    path = tmp_path / name
    path.write_bytes(content)
    _physx_scene()
    try:
        sapien.physx.PhysxCollisionShapeConvexMesh(
            filename=str(path), scale=[1, 1, 1], material=sapien.physx.get_default_material()
        )
        loaded = True
    except RuntimeError:
        loaded = False
    assert loaded == readable


def _collision_shapes_in_sapien(path: Path) -> dict[str, int]:
    """Collision shapes per link of the articulation SAPIEN's URDF loader builds from ``path``,
    as ManiSkill calls the loader (the scene must outlive the articulation: keep both here)."""
    scene = _physx_scene()
    articulation_builders, _actors, _cameras = scene.create_urdf_loader().parse(str(path))
    articulation = articulation_builders[0].build()
    shapes = {link.name: len(link.collision_shapes) for link in articulation.links}
    del articulation, scene
    return shapes


@pytest.mark.usefixtures("maniskill")
def test_sapien_loads_a_link_whose_collision_mesh_is_missing_without_any_shape(
    tmp_path: Path,
) -> None:
    write(tmp_path / "meshes" / "part.stl", STL)
    found = _collision_shapes_in_sapien(write(tmp_path / "found.urdf", urdf("meshes/part.stl")))
    missing = _collision_shapes_in_sapien(write(tmp_path / "gone.urdf", urdf("meshes/gone.stl")))
    assert found["upper_arm"] == 1
    assert missing["upper_arm"] == 0  # and not a word from SAPIEN


def _shapes_of_registered(uid: str) -> dict[str, int]:
    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        robot = env.unwrapped.agent.robot
        return {link.name: len(link._objs[0].collision_shapes) for link in robot.links}
    finally:
        env.close()


def _package_robot(workspace: Path, uid: str) -> Path:
    """A spec whose URDF names a mesh by package.xml (SAPIEN cannot find it), one by folder
    name (it can) and one through the spec's packages map (it cannot)."""
    write(
        workspace / "clearpath_arm_description" / "urdf" / "arm.urdf",
        urdf(
            "package://arm_description/meshes/body.stl",
            "package://arm_parts/meshes/part.stl",
            "package://tool_support/meshes/tool.stl",
        ),
    )
    return write(
        workspace / "specs" / f"{uid}.yaml",
        spec_text(
            "{urdf: ../clearpath_arm_description/urdf/arm.urdf, "
            "packages: {tool_support: ../elsewhere/support}}",
            uid=uid,
        ),
    )


@pytest.mark.usefixtures("maniskill")
def test_a_registered_agent_has_every_collision_shape_its_description_names(
    workspace: Path, tmp_path: Path
) -> None:
    import robospec

    spec = _package_robot(workspace, "rs_test_package_meshes")
    description = workspace / "clearpath_arm_description" / "urdf" / "arm.urdf"
    assert _collision_shapes_in_sapien(description)["upper_arm"] == 1  # SAPIEN alone
    robospec.register(spec, cache_dir=tmp_path / "cache")
    assert _shapes_of_registered("rs_test_package_meshes") == {"base_link": 0, "upper_arm": 3}


@pytest.mark.usefixtures("maniskill")
def test_a_built_package_carries_the_description_with_its_meshes(
    workspace: Path, tmp_path: Path
) -> None:
    spec = _package_robot(workspace, "rs_test_built_meshes")
    out = tmp_path / "out" / "built_meshes"
    result = subprocess.run(
        [sys.executable, "-m", "robospec.cli", "build", str(spec), "-o", str(out)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    carried = (out / "rs_test_built_meshes.urdf").read_text()
    assert "package://" not in carried
    sys.path.insert(0, str(out.parent))
    try:
        importlib.import_module("built_meshes")
        assert _shapes_of_registered("rs_test_built_meshes") == {"base_link": 0, "upper_arm": 3}
    finally:
        sys.path.remove(str(out.parent))


def test_a_carried_urdf_brings_the_srdf_sapien_reads_beside_it(workspace: Path) -> None:
    from robospec.output.modules import robot_files

    folder = workspace / "clearpath_arm_description" / "urdf"
    write(folder / "arm.urdf", urdf("package://arm_description/meshes/body.stl"))
    srdf = (
        '<robot name="arm"><disable_collisions link1="base_link" link2="upper_arm" '
        'reason="Adjacent"/></robot>\n'
    )
    write(folder / "arm.srdf", srdf)
    compiled = compile_spec(write(folder / "arm.yaml", spec_text("{urdf: arm.urdf}")))
    assert compiled.ok and compiled.robot is not None
    files = robot_files(compiled.robot, "arm", workspace / "out")
    assert files["arm.srdf"] == srdf
    assert 'filename="../clearpath_arm_description/meshes/body.stl"' in files["arm.urdf"]


@pytest.mark.parametrize("folder", ["a\\0b", "x" * 5000], ids=["nul_byte", "name_too_long"])
def test_a_packages_entry_no_file_system_takes_is_an_error_not_a_crash(
    workspace: Path, folder: str
) -> None:
    write(workspace / "arm.urdf", urdf("package://arm_parts/meshes/part.stl"))
    spec = write(
        workspace / "arm.yaml", spec_text(f'{{urdf: arm.urdf, packages: {{p: "{folder}"}}}}')
    )
    [problem] = compile_spec(spec).diagnostics
    assert (problem.code, problem.location.line) == ("RS058", 3)


def test_a_description_path_with_a_nul_byte_is_an_error_not_a_crash(workspace: Path) -> None:
    spec = write(workspace / "arm.yaml", spec_text('{urdf: "arm\\0.urdf"}'))
    [problem] = compile_spec(spec).diagnostics
    assert (problem.code, problem.location.line) == ("RS050", 3)
