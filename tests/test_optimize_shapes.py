"""robospec.optimize.shapes on real meshes: ManiSkill's Unitree G1, whose STL collision meshes
SAPIEN splits into connected parts (with a warning per mesh) when loaded with multiple
collisions.

The SAPIEN side runs in a child process (SAPIEN's warnings go to the process's stderr, which only
a process boundary captures whole); those tests are marked ``maniskill``.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import trimesh
from conftest import SAME_ON_EVERY_MANISKILL, maniskill_assets
from lxml import etree

from robospec.optimize.shapes import MissingDependency, optimize_collisions
from robospec.optimize.shapes.obj import assimp_reads, number

# links whose STL meshes SAPIEN splits into 1, 2, 10 and 20 parts (logo_link's are letters)
G1_LINKS = ("pelvis", "head_link", "left_elbow_pitch_link", "logo_link", "left_hip_pitch_link")
STL_WARNING = "loading multiple convex collision meshes from STL file is unsupported"


def _robot(links: tuple[str, ...] = G1_LINKS) -> etree._Element:
    """The G1's URDF cut down to ``links``, fixed to the first (shapes are per link), mesh paths
    absolute, visuals dropped (SAPIEN cannot load visuals without a rendering device)."""
    g1 = maniskill_assets() / "robots" / "g1_humanoid"
    source = etree.parse(str(g1 / "g1.urdf")).getroot()
    robot = etree.Element("robot", name="g1_part")
    for link in source.findall("link"):
        if link.get("name") in links:
            for visual in link.findall("visual"):
                link.remove(visual)
            robot.append(link)
    for child in links[1:]:
        joint = etree.SubElement(robot, "joint", name=f"to_{child}", type="fixed")
        etree.SubElement(joint, "parent", link=links[0])
        etree.SubElement(joint, "child", link=child)
    for mesh in robot.iter("mesh"):
        mesh.set("filename", str(g1 / mesh.get("filename")))
    return robot


def _write_urdf(robot: etree._Element, path: Path) -> Path:
    path.write_bytes(etree.tostring(robot))
    return path


# What SAPIEN builds, per link: each collision shape's cooked vertices, from the URDF's loader
# with load_multiple_collisions; stderr comes back whole. One link per actor: no joints needed.
_SAPIEN_SHAPES = textwrap.dedent(
    """
    import json, sys
    import sapien
    from sapien.wrapper.urdf_loader import URDFLoader

    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    result = {}
    for urdf in sys.argv[1:]:
        loader = URDFLoader()
        loader.set_scene(scene)
        loader.load_multiple_collisions_from_file = True
        articulations, actors, _ = loader.parse(urdf)
        for builder in [b for a in articulations for b in a.link_builders] + actors:
            entity = builder.build_entity()
            component = entity.find_component_by_type(sapien.physx.PhysxRigidBaseComponent)
            result.setdefault(urdf, {})[builder.name] = [
                s.get_vertices().tolist() for s in component.collision_shapes
            ]
    print(json.dumps(result))
    """
)


def _sapien_shapes(*urdfs: Path) -> tuple[dict[str, dict[str, list]], str]:
    done = subprocess.run(
        [sys.executable, "-c", _SAPIEN_SHAPES, *map(str, urdfs)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1]), done.stderr


def _volume(points: np.ndarray) -> float:
    return float(trimesh.convex.convex_hull(points).volume)


@pytest.mark.maniskill
def test_convert_builds_the_shapes_sapien_built_from_the_stl_without_its_warning(
    tmp_path: Path,
) -> None:
    robot = _robot()
    converted, changes = optimize_collisions(robot, tmp_path / "assets", method="convert")
    before = _write_urdf(robot, tmp_path / "before.urdf")
    after = _write_urdf(converted, tmp_path / "after.urdf")
    shapes_of, stderr = _sapien_shapes(before, after)
    # the warning, once per STL mesh before; never after
    assert stderr.count(STL_WARNING) == len(G1_LINKS)
    assert all(c.method == "convert" for c in changes)

    _, stderr_after = _sapien_shapes(after)
    assert STL_WARNING not in stderr_after
    identical = 0
    total = 0
    for link in G1_LINKS:
        old, new = shapes_of[str(before)][link], shapes_of[str(after)][link]
        change = next(c for c in changes if c.link == link)
        assert change.shapes_before == change.shapes_after == len(old) == len(new)
        for a, b in zip(map(np.array, old), map(np.array, new), strict=True):
            total += 1
            identical += a.shape == b.shape and np.array_equal(a, b)
            # the same hull: bounds and volume
            assert np.allclose(a.min(0), b.min(0), atol=1e-6, rtol=0)
            assert np.allclose(a.max(0), b.max(0), atol=1e-6, rtol=0)
            assert _volume(b) == pytest.approx(_volume(a), rel=1e-6, abs=1e-15)
    # PhysX is fed the very points, in the very order: the cooked vertices are the same bits
    assert identical == total == sum(c.shapes_before for c in changes) == 35


def test_convert_writes_one_obj_per_part_deterministically(tmp_path: Path) -> None:
    robot = _robot(("left_elbow_pitch_link", "pelvis"))
    original = etree.tostring(robot)
    first, changes = optimize_collisions(robot, tmp_path / "a", method="convert")
    second, _ = optimize_collisions(robot, tmp_path / "b", method="convert")
    assert etree.tostring(robot) == original  # the input is not changed
    elbow = next(c for c in changes if c.link == "left_elbow_pitch_link")
    assert elbow.written == tuple(f"left_elbow_pitch_link_0_{i}.obj" for i in range(10))
    assert elbow.vertices_after == elbow.vertices_before  # every point, in one part or another
    for name in (n for c in changes for n in c.written):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
    text = etree.tostring(first).decode().replace(str(tmp_path / "a"), "ASSETS")
    assert text == etree.tostring(second).decode().replace(str(tmp_path / "b"), "ASSETS")
    collisions = first.find("link[@name='left_elbow_pitch_link']").findall("collision")
    assert len(collisions) == 10
    assert all(Path(c.find("geometry/mesh").get("filename")).is_absolute() for c in collisions)


def test_convert_keeps_what_is_not_an_stl_split(tmp_path: Path) -> None:
    mesh = trimesh.creation.box((0.1, 0.2, 0.3))
    mesh.export(tmp_path / "box.obj")
    mesh.export(tmp_path / "box.stl")
    robot = etree.fromstring(
        f"""<robot name="r"><link name="a">
        <collision><geometry><mesh filename="{tmp_path / "box.obj"}"/></geometry></collision>
        <collision><geometry><sphere radius="0.1"/></geometry></collision>
        <collision><geometry><mesh filename="{tmp_path / "box.stl"}"/></geometry></collision>
        </link></robot>"""
    )
    _, changes = optimize_collisions(robot, tmp_path / "out", method="convert")
    assert [(c.method, c.shapes_before) for c in changes] == [
        ("kept", 1),
        ("kept", 1),
        ("convert", 1),
    ]
    # without multiple collisions an STL loads as one hull, silently: nothing to convert
    _, changes = optimize_collisions(
        robot, tmp_path / "out2", method="convert", multiple_collisions=False
    )
    assert {c.method for c in changes} == {"kept"}
    # what is kept is reported as it stays: a primitive one shape, a mesh its vertices
    assert [(c.shapes_after, c.vertices_after) for c in changes] == [
        (c.shapes_before, c.vertices_before) for c in changes
    ]
    assert [c.shapes_after for c in changes] == [1, 1, 1] and changes[0].vertices_after > 0


@pytest.mark.slow
def test_hull_caps_vertices_and_keeps_nearly_all_the_volume(tmp_path: Path) -> None:
    links = ("pelvis", "head_link", "torso_link")
    robot = _robot(links)
    hulled, changes = optimize_collisions(robot, tmp_path, method="hull", max_vertices=32)
    for change in changes:
        assert change.method == "hull" and change.shapes_after == 1
        written = trimesh.load(tmp_path / change.written[0], force="mesh", process=False)
        assert len(written.vertices) == change.vertices_after <= 32
        assert written.is_convex and written.is_watertight
        full = trimesh.load(change.source, force="mesh").convex_hull
        # inside the full hull (up to float32 rounding: its vertices are the mesh's points) and
        # close to it in volume
        normals = full.face_normals
        offsets = np.einsum("ij,ij->i", normals, full.triangles[:, 0])
        assert np.all(written.vertices @ normals.T <= offsets + 1e-6)
        # 32 vertices cannot hold a round shape within a few % (an inscribed 32-vertex
        # polyhedron of a sphere keeps ~85% of it); 128 do
        assert written.volume == pytest.approx(full.volume, rel=0.15)
        assert written.volume <= full.volume * (1 + 1e-9)
    _, finer = optimize_collisions(robot, tmp_path / "fine", method="hull", max_vertices=128)
    for change in finer:
        written = trimesh.load(tmp_path / "fine" / change.written[0], force="mesh")
        full = trimesh.load(change.source, force="mesh").convex_hull
        assert len(written.vertices) <= 128
        assert written.volume == pytest.approx(full.volume, rel=0.03)
    assert {c.find("geometry/mesh").get("filename") for c in hulled.iter("collision")} == {
        str(tmp_path / f"{link}_0.obj") for link in links
    }


# SAPIEN weighs a link without an <inertial> by its shapes: primitives leave those alone
INERTIAL = '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial>'


def _one_mesh_robot(path: Path, origin: str = "", inertial: str = INERTIAL) -> etree._Element:
    return etree.fromstring(
        f"""<robot name="r"><link name="part">{inertial}<collision>{origin}
        <geometry><mesh filename="{path}" scale="2 2 2"/></geometry>
        </collision></link></robot>"""
    )


def test_primitives_turn_a_box_mesh_into_a_box(tmp_path: Path) -> None:
    box = trimesh.creation.box((0.1, 0.2, 0.4))
    turn = trimesh.transformations.rotation_matrix(0.3, (0, 0, 1))
    turn[:3, 3] = (0.05, 0, 0.01)
    box.apply_transform(turn)
    box.export(tmp_path / "box.stl")
    robot = _one_mesh_robot(tmp_path / "box.stl", '<origin xyz="0 0 1" rpy="0 0 0"/>')
    result, changes = optimize_collisions(robot, tmp_path / "out", method="primitives")
    assert [c.method for c in changes] == ["box"]
    element = result.find("link/collision")
    size = sorted(float(v) for v in element.find("geometry/box").get("size").split())
    assert size == pytest.approx([0.2, 0.4, 0.8], abs=1e-6)  # the mesh's scale, baked in
    # the box in the link frame covers the scaled, moved mesh exactly
    xyz = [float(v) for v in element.find("origin").get("xyz").split()]
    rpy = [float(v) for v in element.find("origin").get("rpy").split()]
    pose = trimesh.transformations.euler_matrix(*rpy, axes="sxyz")
    pose[:3, 3] = xyz
    fitted = trimesh.creation.box(
        [float(v) for v in element.find("geometry/box").get("size").split()]
    )
    fitted.apply_transform(pose)
    expected = box.copy()
    expected.apply_scale(2)
    expected.apply_translation((0, 0, 1))
    assert np.allclose(np.sort(fitted.vertices, 0), np.sort(expected.vertices, 0), atol=1e-6)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_primitives_fit_a_sphere_and_a_capsule(tmp_path: Path) -> None:
    trimesh.creation.icosphere(subdivisions=4, radius=0.1).export(tmp_path / "ball.stl")
    trimesh.creation.capsule(height=0.3, radius=0.05, count=[64, 64]).export(tmp_path / "pill.stl")
    for name, kind in (("ball", "sphere"), ("pill", "capsule")):
        robot = _one_mesh_robot(tmp_path / f"{name}.stl")
        result, changes = optimize_collisions(robot, tmp_path, method="primitives")
        assert [c.method for c in changes] == [kind]
        shape = result.find(f"link/collision/geometry/{kind}")
        assert float(shape.get("radius")) == pytest.approx(0.2 if kind == "sphere" else 0.1, 0.01)
        if kind == "capsule":
            assert float(shape.get("length")) == pytest.approx(0.6, rel=0.01)


@pytest.mark.slow
def test_a_complex_mesh_fits_no_primitive_and_becomes_what_sapien_makes_of_it(
    tmp_path: Path,
) -> None:
    robot = _robot(("pelvis",))
    for link in robot.iter("link"):  # weighed by its <inertial>, not by its shapes
        link.insert(0, etree.fromstring(INERTIAL))
    result, changes = optimize_collisions(robot, tmp_path, method="primitives")
    (change,) = changes
    assert change.method == "convert" and change.reason == "no primitive within the bound"
    assert change.fit_error is not None and change.fit_error > 0.005
    converted, _ = optimize_collisions(robot, tmp_path / "c", method="convert")
    assert len(result.findall("link/collision")) == len(converted.findall("link/collision"))


def test_a_link_weighed_by_its_shapes_keeps_them(tmp_path: Path) -> None:
    # no <inertial>: SAPIEN takes its mass from its shapes, which a box would change
    trimesh.creation.box((0.1, 0.2, 0.4)).export(tmp_path / "box.stl")
    robot = _one_mesh_robot(tmp_path / "box.stl", inertial="")
    result, changes = optimize_collisions(
        robot, tmp_path / "out", method="primitives", multiple_collisions=False
    )
    assert [(c.method, c.reason) for c in changes] == [("kept", "mass from its collision shapes")]
    assert result.find("link/collision/geometry/mesh") is not None


@pytest.mark.slow  # coacd's decomposition takes half a minute here: out of the fast loop
@pytest.mark.skipif(
    importlib.util.find_spec("coacd") is None,
    reason="coacd is not installed (pip install 'robospec[optimize]')",
)
@SAME_ON_EVERY_MANISKILL
def test_coacd_decomposes_into_convex_parts(tmp_path: Path) -> None:
    robot = _robot(("left_ankle_pitch_link",))  # a small link: coacd takes seconds on it
    result, changes = optimize_collisions(
        robot, tmp_path, method="coacd", max_vertices=32, tolerance=0.2
    )
    (change,) = changes
    assert change.method == "coacd" and change.shapes_after == len(change.written) >= 1
    assert len(result.find("link").findall("collision")) == change.shapes_after
    full = trimesh.load(change.source, force="mesh")
    for name in change.written:
        part = trimesh.load(tmp_path / name, force="mesh", process=False)
        assert part.is_convex and len(part.vertices) <= 32
        assert np.all(part.bounds[0] >= full.bounds[0] - 0.01)
        assert np.all(part.bounds[1] <= full.bounds[1] + 0.01)


def test_coacd_missing_is_a_missing_dependency(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "coacd", None)  # import coacd raises ImportError
    robot = etree.fromstring('<robot name="r"><link name="a"/></robot>')
    with pytest.raises(MissingDependency) as raised:
        optimize_collisions(robot, tmp_path, method="coacd")
    assert raised.value.package == "coacd"
    assert raised.value.hint == "pip install 'robospec[optimize]'"
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("x", [0.0, 1.5, -0.123456789, 3.0e-9, -7.0348554e-09, 12345.678])
def test_numbers_read_back_by_assimp_as_the_same_float32(x: float) -> None:
    text = number(x)
    assert assimp_reads(text) == float(np.float32(x))
    assert float(text) == pytest.approx(float(np.float32(x)), rel=1e-6)


def test_a_mesh_trimesh_cannot_read_is_kept_as_sapien_reads_it(tmp_path: Path) -> None:
    # COLLADA needs pycollada, which robospec does not install; SAPIEN reads it with assimp
    (tmp_path / "part.dae").write_text("<COLLADA/>")
    robot = etree.fromstring(
        f"""<robot name="r"><link name="a"><collision><geometry>
        <mesh filename="{tmp_path / "part.dae"}"/></geometry></collision></link></robot>"""
    )
    for method in ("convert", "hull", "primitives"):
        out, changes = optimize_collisions(robot, tmp_path / method, method=method)
        assert [(c.method, c.shapes_after) for c in changes] == [("kept", 1)]
        assert etree.tostring(out) == etree.tostring(robot)
