"""The derived-description stage (robospec.derive): each mend class changes exactly what it
names, says so at the element it changed, keeps every element on its line, and leaves the user's
file alone; what the spec declares that does not fit is a located diagnostic; `new` writes the
mends a robot needs and `build` carries the derived copy with its meshes.

The mend examples of the docs' catalogue (docs/examples/codes/RS7xx) are the descriptions these
tests mend; tests/test_derive_maniskill.py loads them in ManiSkill.
"""

from __future__ import annotations

import shutil
import typing
from pathlib import Path

import pytest
from conftest import CODE_EXAMPLES, invoke_robospec
from lxml import etree

from robospec.derive import MENDS, Source, derive, suggest_mends
from robospec.diagnostics import Severity
from robospec.model.mends import Mends
from robospec.pipeline import compile_spec

# mend class -> (the catalogue's broken description, the policy that mends it)
BROKEN: dict[str, tuple[str, typing.Any]] = {
    "xml": ("RS700/declared.urdf", "repair"),
    "namespaces": ("RS701/prefixed.urdf", "declare"),
    "substitutions": ("RS702/launched.urdf", "defaults"),
    "packages": ("RS703/nameless.urdf", "resolve"),
    "textures": ("RS704/textured.urdf", "drop"),
    "transmissions": ("RS705/reduction.urdf", "drop"),
    "inertia": ("RS706/skewed.urdf", "diagonal"),
    "mass": ("RS707/negative.urdf", "bound"),
    "integers": ("RS708/camera.urdf", "round"),
    "separators": ("RS722/commas.urdf", "spaces"),
    "limits": ("RS709/unlimited.urdf", "continuous"),
    "mimic": ("RS710/gripper.urdf", "controller"),
    "spherical": ("RS711/ball.urdf", "hinges"),
    "mirrors": ("RS714/mirrored.urdf", "copies"),
}
MJCF_BROKEN: dict[str, tuple[str, typing.Any]] = {
    "includes": ("RS712/mounted.xml", "inline"),
    "geoms": ("RS713/terrain.xml", "drop"),
    "mesh_names": ("RS715/unnamed.xml", "mujoco"),
    "asset_names": ("RS719/repeated.xml", "first"),
    "angles": ("RS728/fragment.xml", "radian"),
    "geom_meshes": ("RS723/defaulted.xml", "defaults"),
    "axes": ("RS724/unaxed.xml", "mujoco"),
    "mesh_scale": ("RS716/scaled.xml", "defaults"),
    "contype": ("RS717/touching.xml", "conaffinity"),
    "freejoint": ("RS718/floating.xml", "root"),
    "orientations": ("RS721/turned.xml", "quat"),
    "bodies": ("RS720/plated.xml", "merge"),
}
SOUND = CODE_EXAMPLES / "RS725" / "arm.urdf"
SOUND_MJCF = CODE_EXAMPLES / "RS074" / "arm.xml"


def _source(path: Path) -> Source:
    kind = "mjcf" if path.suffix == ".xml" else "urdf"
    return Source(str(path), path.name, kind, path.read_bytes())


def test_every_mend_class_is_a_field_of_the_spec_model_and_every_field_a_class() -> None:
    assert {m.NAME for m in MENDS if "urdf" in m.KINDS} == set(BROKEN) | {"xml", "namespaces"}
    assert {m.NAME for m in MENDS if "mjcf" in m.KINDS} == set(MJCF_BROKEN) | {"xml", "namespaces"}
    model_fields = set(Mends.model_fields)
    assert {m.NAME for m in MENDS} <= model_fields
    assert model_fields == {m.NAME for m in MENDS}


def test_each_mend_class_documents_its_note_code_and_the_problems_it_mends() -> None:
    from robospec.diagnostics.codes import CODES

    for mend in MENDS:
        assert mend.CODE in CODES, mend.NAME
        assert all(code in CODES for code in mend.FIXES), mend.NAME
        assert mend.WHY and mend.STAGE in ("text", "tree"), mend.NAME


@pytest.mark.parametrize("name", [*BROKEN, *MJCF_BROKEN])
def test_a_mend_changes_the_broken_description_and_notes_it_at_the_element(name: str) -> None:
    relative, policy = {**BROKEN, **MJCF_BROKEN}[name]
    path = CODE_EXAMPLES / relative
    derived = derive(_source(path), {name: policy})
    assert [o.status for o in derived.outcomes] == ["applied"]
    (note,) = derived.notes
    assert note.severity is Severity.NOTE
    assert note.location.file == path.name
    assert " -> " in note.message and f"mend '{name}'" in note.message
    assert derived.text != path.read_text()


@pytest.mark.parametrize("name", list(BROKEN))
def test_a_mend_of_a_sound_description_changes_nothing_and_is_stale(name: str) -> None:
    derived = derive(_source(SOUND), {name: BROKEN[name][1]})
    assert [o.status for o in derived.outcomes] == ["stale"]
    assert derived.notes == ()


@pytest.mark.parametrize("name", list(MJCF_BROKEN))
def test_an_mjcf_mend_of_a_sound_model_changes_nothing_and_is_stale(name: str) -> None:
    derived = derive(_source(SOUND_MJCF), {name: MJCF_BROKEN[name][1]})
    assert [o.status for o in derived.outcomes] == ["stale"]
    assert derived.notes == ()


@pytest.mark.parametrize("name", [n for n in BROKEN if n not in ("xml", "namespaces")])
def test_a_mended_description_keeps_every_element_on_its_line(name: str) -> None:
    relative, policy = BROKEN[name]
    path = CODE_EXAMPLES / relative
    derived = derive(_source(path), {name: policy})
    before = {
        (e.tag, e.get("name"), e.sourceline)
        for e in etree.fromstring(path.read_bytes()).iter()
        if isinstance(e.tag, str)
    }
    after = [
        (e.tag, e.get("name"), e.sourceline)
        for e in etree.fromstring(derived.text.encode()).iter()
        if isinstance(e.tag, str)
    ]
    # every element of the derived copy that the user's file has stands on its line there
    kept = [a for a in after if a[0] in ("link", "joint", "inertial", "collision", "limit")]
    moved = [a for a in kept if a not in before and (a[0], a[1]) in {(b[0], b[1]) for b in before}]
    assert moved == []


def test_the_xml_mend_cuts_what_follows_the_root_and_keeps_lines(tmp_path: Path) -> None:
    text = SOUND.read_bytes().rstrip() + b"\r\n\x00junk"
    path = tmp_path / "trailing.urdf"
    path.write_bytes(text)
    derived = derive(_source(path), {"xml": "repair"})
    assert derived.text.rstrip().endswith("</robot>")
    assert "content after the root element" in derived.notes[0].message
    assert derived.notes[0].location.line == text.count(b"\n") + 1


def test_inertia_policies_are_tried_in_order_and_bound_keeps_the_principal_axes(
    tmp_path: Path,
) -> None:
    from robospec.description.inertia import principal_axes, rejected

    text = SOUND.read_text().replace(
        'ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"',
        'ixx="-1e-9" iyy="0.01" izz="0.002" ixy="0.001" ixz="0" iyz="0"',
    )
    path = tmp_path / "negative_moment.urdf"
    path.write_text(text)
    alone = derive(_source(path), {"inertia": "diagonal"})
    assert alone.outcomes[0].status == "refused"
    assert "add 'bound'" in (alone.refusals[0].hint or "")
    both = derive(_source(path), {"inertia": ["diagonal", "bound"]})
    assert both.outcomes[0].status == "applied" and both.refusals == ()
    assert "(bound)" in both.notes[0].message
    inertia = etree.fromstring(both.text.encode()).find("link/inertial/inertia")
    assert inertia is not None
    values = [float(inertia.get(a, "")) for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
    assert not rejected(*values)
    _, axes_before = principal_axes(-1e-9, 0.001, 0, 0.01, 0, 0.002)
    _, axes_after = principal_axes(*values)
    for i in range(3):  # the same axes, up to their sign and order
        assert max(
            abs(sum(axes_before[k][i] * axes_after[k][j] for k in range(3))) for j in range(3)
        ) == pytest.approx(1, abs=1e-6)


def test_a_substitution_without_a_default_is_refused_at_its_element(tmp_path: Path) -> None:
    path = tmp_path / "arg.urdf"
    path.write_text(SOUND.read_text().replace('xyz="0 0 0.1"', 'xyz="$(arg offset)"'))
    derived = derive(_source(path), {"substitutions": "defaults"})
    (refusal,) = derived.refusals
    assert refusal.code == "RS727" and refusal.location.line == 18
    assert "no default" in refusal.message


def test_suggest_mends_what_needs_mending_and_nothing_else() -> None:
    for name, (relative, policy) in {**BROKEN, **MJCF_BROKEN}.items():
        chosen, derived = suggest_mends(_source(CODE_EXAMPLES / relative))
        if name == "mimic":  # a mimic pair loads: the scaffold's controller drives it
            assert chosen == {}
        else:
            assert chosen == {name: policy}, name
            assert derived.refusals == ()
    assert suggest_mends(_source(SOUND))[0] == {}


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_validate_notes_the_mend_in_the_description_and_never_writes_the_file(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS706", folder)
    before = (folder / "skewed.urdf").read_bytes()
    result = compile_spec(folder / "fail.yaml")
    assert [(d.code, d.severity.value) for d in result.diagnostics] == [("RS706", "note")]
    assert result.diagnostics[0].location.file.endswith("skewed.urdf")
    assert (folder / "skewed.urdf").read_bytes() == before
    assert result.robot is not None and result.robot.description.derived


def test_an_unknown_mend_class_or_policy_is_a_located_error_with_did_you_mean(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS706", folder)
    spec = folder / "fail.yaml"
    spec.write_text(
        spec.read_text().replace("inertia: diagonal", "inertia: diagnal, transmision: drop")
    )
    result = compile_spec(spec)
    found = {(d.code, d.location.line, d.hint) for d in result.diagnostics}
    assert (
        "RS102",
        4,
        "did you mean 'diagonal'? (expected one of 'diagonal', 'bound', 'balance' or 'shapes')",
    ) in found
    assert ("RS101", 4, "did you mean 'transmissions'?") in found


def test_build_carries_the_derived_copy_and_a_copy_of_each_mesh_it_names(tmp_path: Path) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS705", folder)
    result = invoke_robospec("build", str(folder / "fail.yaml"), "-o", str(tmp_path / "agents"))
    assert result.exit_code == 0, result.output
    package = tmp_path / "agents"
    urdf = etree.parse(str(package / "my_arm.urdf")).getroot()
    assert urdf.find("transmission") is None
    meshes = [m.get("filename") for m in urdf.iter("mesh")]
    assert meshes == ["my_arm.upper_arm.stl"]
    assert (package / "my_arm.upper_arm.stl").read_bytes() == (
        folder / "meshes" / "upper_arm.stl"
    ).read_bytes()
    assert "robot" not in (package / "my_arm.py").read_text()  # nothing names the original
    manifest = (package / "_robospec_manifest.txt").read_text()
    assert "my_arm.upper_arm.stl" in manifest
    # a second build of the same spec has nothing to change
    again = invoke_robospec("build", str(folder / "fail.yaml"), "-o", str(package), "--check")
    assert again.exit_code == 0, again.output


def test_new_writes_the_mends_a_robot_needs_with_why_and_its_spec_validates(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS705", folder)
    out = folder / "new.yaml"
    result = invoke_robospec("new", str(folder / "reduction.urdf"), "-o", str(out), "--no-sim")
    assert result.exit_code == 0, result.output
    text = out.read_text()
    assert "  mend:  # robospec mends a copy" in text
    assert "    transmissions: drop  # SAPIEN's parser stops at transmissions" in text
    validated = compile_spec(out)
    assert not [d for d in validated.diagnostics if d.is_error]
    assert "RS705" in {d.code for d in validated.diagnostics}


def test_a_number_list_with_a_stray_comma_is_refused_with_a_hint_naming_the_separators_mend(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS722", folder)
    spec = folder / "fail.yaml"
    spec.write_text(spec.read_text().replace(", mend: {separators: spaces}", ""))
    result = compile_spec(spec)
    (refused,) = [d for d in result.diagnostics if d.is_error]
    assert refused.code == "RS052" and refused.location.line == 18
    assert 'rpy="1.5707963, 1.3089969 1.5707963" is not 3 numbers' in refused.message
    assert refused.hint is not None and "{separators: spaces}" in refused.hint


def test_the_separators_mend_writes_the_numbers_as_written_and_names_element_and_attribute(
    tmp_path: Path,
) -> None:
    path = tmp_path / "commas.urdf"
    text = SOUND.read_text()
    text = text.replace('<origin xyz="0 0 0.1"/>', '<origin xyz="0,0,0.1" rpy="1.5707963, 0 0"/>')
    text = text.replace('<axis xyz="0 0 1"/>', '<axis xyz="0, 0, 1,"/>')
    path.write_text(text)
    derived = derive(_source(path), {"separators": "spaces"})
    mended = etree.fromstring(derived.text.encode())
    origin, axis = mended.find("joint/origin"), mended.find("joint/axis")
    assert (origin.get("xyz"), origin.get("rpy"), axis.get("xyz")) == (
        "0 0 0.1",
        "1.5707963 0 0",
        "0 0 1",
    )
    (note,) = derived.notes
    assert note.code == "RS722" and note.location.line == 18
    assert 'joint \'shoulder\' <origin> xyz=: "0,0,0.1" -> "0 0 0.1"' in note.message


def test_a_number_list_that_reads_as_decimal_commas_too_is_not_mended(tmp_path: Path) -> None:
    path = tmp_path / "decimal.urdf"
    # "0,5 0,5 1" is three numbers either way: which the author meant cannot be told
    path.write_text(SOUND.read_text().replace('xyz="0 0 0.1"', 'xyz="0,5 0,5 1"'))
    derived = derive(_source(path), {"separators": "spaces"})
    assert [o.status for o in derived.outcomes] == ["stale"]
    assert suggest_mends(_source(path))[0] == {}


def test_new_on_a_description_with_a_stray_comma_writes_the_mend_and_a_spec_that_validates(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS722", folder)
    out = folder / "new.yaml"
    result = invoke_robospec("new", str(folder / "commas.urdf"), "-o", str(out), "--no-sim")
    assert result.exit_code == 0, result.output
    assert "    separators: spaces  # number lists are written with commas" in out.read_text()
    validated = compile_spec(out)
    assert not [d for d in validated.diagnostics if d.is_error]
    assert "RS722" in {d.code for d in validated.diagnostics}


def test_inspect_shows_the_robot_the_mends_leave_with_their_notes(tmp_path: Path) -> None:
    result = invoke_robospec("inspect", str(CODE_EXAMPLES / "RS711" / "ball.urdf"))
    assert result.exit_code == 0, result.output
    assert "shoulder_z" in result.output
    assert "note[RS711]" in result.output


def test_an_inlined_include_keeps_its_file_and_line_for_later_diagnostics() -> None:
    derived = derive(_source(CODE_EXAMPLES / "RS712" / "mounted.xml"), {"includes": "inline"})
    root = etree.fromstring(derived.text.encode())
    body = root.find("worldbody/body")
    assert body is not None and body.get("name") == "upper_arm"
    assert dict(derived.line_map)[body.sourceline] == ("arm_part.xml", 2)


def test_inlined_includes_merge_their_worldbodies_in_the_order_mujoco_reads_them() -> None:
    """A scene's file brings a <worldbody> (a table) before the one the arm is included in:
    written in place, the copy has one <worldbody> holding MuJoCo's bodies in MuJoCo's order
    (ManiSkill's loader reads only the first, which alone holds no robot)."""
    import mujoco

    model = Path(__file__).parent / "data" / "mjcf" / "scene_include" / "robot.xml"
    derived = derive(_source(model), {"includes": "inline"})
    root = etree.fromstring(derived.text.encode())
    (worldbody,) = root.findall("worldbody")
    bodies = [body.get("name") for body in worldbody.iter("body")]
    compiled = mujoco.MjModel.from_xml_path(str(model))
    names = [mujoco.mj_id2name(compiled, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, 4)]
    assert bodies == names == ["table", "arm_base", "upper_arm"]
    assert worldbody.find("light") is not None
    assert "its <worldbody> merged with the model's" in derived.notes[0].message


def test_inspect_finds_the_arm_of_a_scene_whose_table_is_included_first() -> None:
    from robospec.authoring.commands import run_inspect

    result = run_inspect(Path(__file__).parent / "data" / "mjcf" / "scene_include" / "robot.xml")
    assert result.report is not None and not result.failed, result.diagnostics
    assert "upper_arm  <- shoulder (revolute)" in result.report


def test_a_derived_mjcf_is_carried_with_its_files_named_from_where_it_is_carried(
    tmp_path: Path,
) -> None:
    from robospec.derive.mjcf_files import carried_text

    model = tmp_path / "model" / "robot.xml"
    (tmp_path / "model" / "meshes").mkdir(parents=True)
    (tmp_path / "model" / "meshes" / "part.stl").write_bytes(b"solid x\nendsolid x\n")
    (tmp_path / "model" / "assets.xml").write_text(
        '<mujoco><asset><mesh name="part" file="part.stl"/></asset></mujoco>'
    )
    model.write_text(
        '<mujoco><compiler meshdir="meshes" angle="radian"/><include file="assets.xml"/>'
        "<worldbody/></mujoco>"
    )
    text = carried_text(model.read_text(), str(model), lambda path: "copied/" + Path(path).name)
    root = etree.fromstring(text.encode())
    assert root.find("include") is None
    assert root.find("asset/mesh").get("file") == "copied/part.stl"  # type: ignore[union-attr]
    assert root.find("compiler").get("meshdir") is None  # type: ignore[union-attr]


def test_a_mirrored_copy_is_the_mesh_mirrored_with_its_faces_turned_outwards() -> None:
    from robospec.description.mesh_data import read_mesh

    source = CODE_EXAMPLES / "RS714" / "mirrored.urdf"
    derived = derive(_source(source), {"mirrors": "copies"})
    mesh = etree.fromstring(derived.text.encode()).find("link/collision/geometry/mesh")
    assert mesh is not None and mesh.get("scale") == "1 1 1"
    copy, original = (
        read_mesh(mesh.get("filename", "")),
        read_mesh(str(CODE_EXAMPLES / "RS714" / "meshes" / "upper_arm.stl")),
    )
    assert copy is not None and original is not None
    assert copy.triangle_count == original.triangle_count

    def normal(data: typing.Any, triangle: tuple[int, int, int]) -> list[float]:
        a, b, c = (data.vertex(i) for i in triangle)
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]

    for before, after in zip(original.triangles(), copy.triangles(), strict=True):
        # the copy's triangle is the original's mirrored in y, its normal mirrored too
        assert {tuple(round(x, 6) for x in copy.vertex(i)) for i in after} == {
            (
                round(original.vertex(i)[0], 6),
                round(-original.vertex(i)[1], 6),
                round(original.vertex(i)[2], 6),
            )
            for i in before
        }
        n0, n1 = normal(original, before), normal(copy, after)
        assert n1 == pytest.approx([n0[0], -n0[1], n0[2]], abs=1e-9)


def test_a_mend_note_reaches_every_output_format(tmp_path: Path) -> None:
    import json

    from robospec.reporting import render

    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS706", folder)
    diagnostics = compile_spec(folder / "fail.yaml").diagnostics
    report = json.loads(render(diagnostics, 1, "json"))
    assert [d["severity"] for d in report["diagnostics"]] == ["note"]
    assert report["summary"]["notes"] == 1 and report["summary"]["errors"] == 0
    sarif = json.loads(render(diagnostics, 1, "sarif"))
    assert [r["level"] for r in sarif["runs"][0]["results"]] == ["note"]
    assert render(diagnostics, 1, "github").startswith("::notice ")
    assert "note[RS706]" in render(diagnostics, 1, "text")


def test_a_free_joint_below_the_robots_root_is_refused_at_its_element(tmp_path: Path) -> None:
    # a second floating body in the robot's tree: no articulation can hold it, so no mend
    text = (CODE_EXAMPLES / "RS718" / "arm.xml").read_text()
    text = text.replace(
        '<joint name="elbow" axis="0 1 0" range="-90 90"/>', '<joint name="loose" type="free"/>'
    )
    path = tmp_path / "loose.xml"
    path.write_text(text)
    derived = derive(_source(path), {"freejoint": "root"})
    (refusal,) = derived.refusals
    assert refusal.code == "RS727" and refusal.location.line == 10
    assert "body 'lower'" in refusal.message
    assert [o.status for o in derived.outcomes] == ["refused"]


def test_merged_bodies_keep_mujocos_link_poses_mass_and_centre_of_mass(tmp_path: Path) -> None:
    """What MuJoCo compiles of the merged model is the original's: each remaining body where it
    was at a random configuration, and the robot's mass and centre of mass."""
    mujoco = pytest.importorskip("mujoco")
    import numpy as np

    path = CODE_EXAMPLES / "RS720" / "plated.xml"
    derived = derive(_source(path), {"bodies": "merge"})
    merged_path = tmp_path / "merged.xml"
    merged_path.write_text(derived.text)
    original, merged = (mujoco.MjModel.from_xml_path(str(p)) for p in (path, merged_path))
    assert (original.nbody, merged.nbody) == (43, 22)  # the world, and 42 bodies or 21
    data = {m: mujoco.MjData(m) for m in (original, merged)}
    qpos = np.random.default_rng(3).uniform(-0.5, 0.5, original.nq)
    for model, state in data.items():
        state.qpos[:] = qpos
        mujoco.mj_kinematics(model, state)
        mujoco.mj_comPos(model, state)
    for body in range(1, merged.nbody):
        name = mujoco.mj_id2name(merged, mujoco.mjtObj.mjOBJ_BODY, body)
        there = mujoco.mj_name2id(original, mujoco.mjtObj.mjOBJ_BODY, name)
        assert np.allclose(data[merged].xpos[body], data[original].xpos[there], atol=1e-9), name
        assert np.allclose(data[merged].xquat[body], data[original].xquat[there], atol=1e-9)
    assert merged.body_mass.sum() == pytest.approx(original.body_mass.sum(), rel=1e-9)
    assert np.allclose(data[merged].subtree_com[0], data[original].subtree_com[0], atol=1e-9)
