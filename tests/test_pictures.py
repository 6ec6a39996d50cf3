"""``robospec doc --images``: pictures of the robot and of what each camera sees, drawn on the
CPU by MuJoCo (Mesa's EGL), and the camera warnings judged from segmentation pictures.

The proofs draw the real shipped robots: the Panda's hand camera sees its two fingers (the
points of each finger nearest the tcp land on pixels of that finger, either side of the tcp),
the G1's head camera sees both hands at rest (where each palm and tcp project, the picture shows
that hand), a Panda camera turned backwards is warned about and no shipped camera is. Drawing
takes seconds (a MuJoCo scene, an OpenGL context): those tests are ``slow``; the camera model,
the framing and the card's Markdown are checked without drawing.
"""

from __future__ import annotations

import math
import os
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import DOCS, MANISKILL_SPECS, PANDA_SPEC, ROOT, run_robospec

from robospec.authoring.card import CardPicture, robot_card
from robospec.authoring.commands import images_folder, run_doc, run_new
from robospec.diagnostics import has_errors
from robospec.pictures.views import STANDARD_VIEWS, camera_view, standard_view
from robospec.pipeline import compile_spec
from robospec.resolve.resolved import ResolvedCamera

WRISTCAM_SPEC = MANISKILL_SPECS / "panda_wristcam.yaml"
G1_HEAD_SPEC = MANISKILL_SPECS / "unitree_g1_simplified_upper_body_with_head_camera.yaml"
BACKWARDS_SPEC = DOCS / "examples" / "cameras" / "panda_camera_backwards.yaml"
CAMERA_CODES = {"RS560", "RS561", "RS562", "RS563"}


def _camera(**changes: object) -> ResolvedCamera:
    values: dict[str, object] = dict(
        uid="cam", mount="link", p=(0.0, 0.0, 0.0), q=(1.0, 0.0, 0.0, 0.0), width=128,
        height=96, fov=math.pi / 2, intrinsic=None, near=0.01, far=10.0, shader_pack="default",
    )  # fmt: skip
    values.update(changes)
    return ResolvedCamera(**values)  # type: ignore[arg-type]


# -- the camera model, without drawing


def test_a_camera_looks_along_its_x_axis_with_z_up_as_sapien_cameras_do() -> None:
    view = camera_view(_camera(), np.eye(4), "cam")
    u, v, depth = view.project(np.array([2.0, 0.0, 0.0]))
    assert (u, v, depth) == (64.0, 48.0, 2.0)
    left_u, _, _ = view.project(np.array([2.0, 0.5, 0.0]))  # +y is the camera's left
    _, up_v, _ = view.project(np.array([2.0, 0.0, 0.5]))  # +z is up: a smaller row
    assert left_u < 64 and up_v < 48
    assert not view.sees(np.array([-1.0, 0.0, 0.0]))  # behind it


def test_fov_is_vertical_with_square_pixels_and_an_intrinsic_matrix_is_taken_as_written() -> None:
    view = camera_view(_camera(fov=math.pi / 2), np.eye(4), "cam")
    # 45 degrees up from the axis lands on the top row; pixels are square
    assert view.project(np.array([1.0, 0.0, 1.0]))[1] == pytest.approx(0.0)
    assert view.fx == view.fy == pytest.approx(48.0)
    intrinsic = ((100.0, 0.0, 30.0), (0.0, 90.0, 40.0), (0.0, 0.0, 1.0))
    view = camera_view(_camera(fov=None, intrinsic=intrinsic), np.eye(4), "cam")
    assert view.project(np.array([1.0, 0.0, 0.0]))[:2] == (30.0, 40.0)
    assert view.project(np.array([1.0, -0.1, 0.1]))[:2] == pytest.approx((40.0, 31.0))


def test_a_mounted_camera_sits_at_its_pose_on_the_mount_link() -> None:
    mount = np.eye(4)
    mount[:3, 3] = (1.0, 2.0, 3.0)
    turned = _camera(p=(0.1, 0.0, 0.0), q=(math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)))
    view = camera_view(turned, mount, "cam")  # a quarter turn about z: it looks along +y
    assert view.position == pytest.approx((1.1, 2.0, 3.0))
    assert view.forward == pytest.approx((0.0, 1.0, 0.0))
    assert view.project(np.array([1.1, 3.0, 3.0]))[:2] == pytest.approx((64.0, 48.0))


@pytest.mark.parametrize("name", list(STANDARD_VIEWS))
def test_a_standard_view_frames_every_point_of_the_robot_with_little_to_spare(name: str) -> None:
    rng = np.random.default_rng(0)
    points = rng.normal(size=(500, 3)) * (0.1, 0.3, 0.5) + (0.3, 0.0, 0.6)
    view = standard_view(name, points)
    projected = np.array([view.project(p) for p in points])
    assert (projected[:, 2] > 0).all()
    assert (projected[:, 0] >= 0).all() and (projected[:, 0] <= view.width).all()
    assert (projected[:, 1] >= 0).all() and (projected[:, 1] <= view.height).all()
    # tight: the points reach to within 15% of the frame's edge in one direction or the other
    spread_u = (projected[:, 0].max() - projected[:, 0].min()) / view.width
    spread_v = (projected[:, 1].max() - projected[:, 1].min()) / view.height
    assert max(spread_u, spread_v) > 0.85


def test_the_card_leads_with_the_robot_and_shows_each_view_and_each_camera(tmp_path: Path) -> None:
    compiled = compile_spec(WRISTCAM_SPEC)
    assert compiled.robot is not None and compiled.description is not None
    pictures = [
        CardPicture(kind, "rest", name, f"imgs/rest/{name}.{kind}.png")
        for kind, name in [
            ("robot", "three_quarter"),
            ("robot", "front"),
            ("collision", "front"),
            ("camera", "hand_camera"),
            ("table", "hand_camera"),
        ]
    ]
    text = robot_card(compiled.robot, compiled.description, "spec.yaml", (), pictures)
    lines = text.splitlines()
    assert lines[2] == "![rs_panda_wristcam at keyframe rest](<imgs/rest/three_quarter.robot.png>)"
    assert "## Pictures" in lines
    assert (
        "![rest: three_quarter](<imgs/rest/three_quarter.robot.png>) "
        "![rest: front](<imgs/rest/front.robot.png>)"
    ) in lines
    assert "![rest: front (collision shapes)](<imgs/rest/front.collision.png>)" in lines
    assert (
        "| `rest` | ![hand_camera at rest](<imgs/rest/hand_camera.camera.png>) | "
        "![hand_camera at rest](<imgs/rest/hand_camera.table.png>) |"
    ) in lines


def test_without_the_render_extra_doc_images_is_rs660_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco raises ImportError
    out = tmp_path / "panda.md"
    diagnostics = run_doc(PANDA_SPEC, out, images=True).write().diagnostics
    assert [(d.code, d.location.file) for d in diagnostics] == [("RS660", "<command line>")]
    assert "pip install 'robospec[render]'" in (diagnostics[0].hint or "")
    assert not out.exists() and not images_folder(out).exists()


# -- drawing (seconds each)


def _labels_of_camera(spec: Path) -> tuple[object, object, np.ndarray]:
    """The robot at its first keyframe, its first camera's view, and what each of that
    view's pixels shows (the robot alone)."""
    from robospec.pictures.posed import keyframe_poses, posed_robots
    from robospec.pictures.renderer import VISUAL, Renderer
    from robospec.pictures.stage import robot_stage, table_stage

    compiled = compile_spec(spec)
    assert compiled.robot is not None and compiled.description is not None
    robot = compiled.robot
    posed, problems = posed_robots(robot, compiled.description, keyframe_poses(robot), ("visual",))
    assert problems == []
    at_rest = posed[0]
    camera = robot.cameras[0]
    view = camera_view(camera, at_rest.links[camera.mount], camera.uid)
    renderer = Renderer(at_rest, camera.width, camera.height)
    try:
        renderer.place(at_rest, robot_stage(0.0), table_stage(at_rest.root, None, None))
        labels = renderer.labels(view, (VISUAL,))
    finally:
        renderer.close()
    return at_rest, view, labels


def _link_at(at_rest: object, labels: np.ndarray, u: float, v: float, around: int = 0) -> set:
    rows = labels[max(0, int(v) - around) : int(v) + around + 1]
    window = rows[:, max(0, int(u) - around) : int(u) + around + 1]
    return {at_rest.shapes[i].link for i in window.reshape(-1) if i >= 0}  # type: ignore[attr-defined]


@pytest.mark.slow
def test_the_panda_hand_camera_sees_both_fingers_either_side_of_the_tcp() -> None:
    at_rest, view, labels = _labels_of_camera(WRISTCAM_SPEC)
    tcp = at_rest.links["panda_hand_tcp"][:3, 3]  # type: ignore[attr-defined]
    assert view.sees(tcp)  # type: ignore[attr-defined]
    tcp_u, tcp_v, _ = view.project(tcp)  # type: ignore[attr-defined]
    sides = []
    for finger in ("panda_leftfinger", "panda_rightfinger"):
        # the finger's points nearest the tcp: its tip, where it closes on an object
        points = np.concatenate(
            [
                part.vertices @ pose[:3, :3].T + pose[:3, 3]
                for shape, pose in zip(at_rest.shapes, at_rest.poses, strict=True)  # type: ignore[attr-defined]
                if shape.link == finger
                for part in shape.mesh
            ]
        )
        tip = points[np.argsort(np.linalg.norm(points - tcp, axis=1))[:50]].mean(axis=0)
        u, v, depth = view.project(tip)  # type: ignore[attr-defined]
        assert depth > 0 and 0 <= u < view.width and 0 <= v < view.height  # type: ignore[attr-defined]
        assert _link_at(at_rest, labels, u, v) == {finger}, (finger, u, v)
        assert abs(v - tcp_v) < 5  # level with the tcp
        sides.append(u - tcp_u)
    assert sides[0] * sides[1] < 0  # one finger either side of the tcp


@pytest.mark.slow
def test_the_g1_head_camera_sees_both_hands_at_rest() -> None:
    at_rest, view, labels = _labels_of_camera(G1_HEAD_SPEC)
    for side in ("left", "right"):
        arm = {link for link in at_rest.links if link.startswith(f"{side}_")}  # type: ignore[attr-defined]
        # the palm's frame (the wrist) lands on that arm: the hand or the forearm before it
        palm = at_rest.links[f"{side}_palm_link"][:3, 3]  # type: ignore[attr-defined]
        assert view.sees(palm)  # type: ignore[attr-defined]
        seen = _link_at(at_rest, labels, *view.project(palm)[:2])  # type: ignore[attr-defined]
        assert seen and seen <= arm, (side, seen)
        # the tcp is between the fingers: within a few pixels of it, the picture is the hand
        tcp = at_rest.links[f"{side}_tcp_link"][:3, 3]  # type: ignore[attr-defined]
        assert view.sees(tcp)  # type: ignore[attr-defined]
        seen = _link_at(at_rest, labels, *view.project(tcp)[:2], around=3)  # type: ignore[attr-defined]
        fingers = {link for link in arm if link.endswith(_FINGER_LINKS)}
        assert seen & fingers, (side, seen)


_FINGER_LINKS = tuple(
    f"_{n}_link" for n in ("palm", "zero", "one", "two", "three", "four", "five", "six")
)


@pytest.mark.slow
def test_doc_images_draws_the_panda_and_its_hand_camera_and_the_card_embeds_them(
    tmp_path: Path,
) -> None:
    from PIL import Image

    spec = tmp_path / "panda_wristcam.yaml"
    shutil.copy(WRISTCAM_SPEC, spec)
    out = tmp_path / "card" / "panda.md"
    done = run_robospec("doc", str(spec), "-o", str(out), "--images", "--collisions")
    assert done.returncode == 0, done.stderr
    assert "RS56" not in done.stdout + done.stderr  # the shipped camera sees its fingers
    folder = images_folder(out)
    names = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*.png"))
    assert names == sorted(
        [f"rest/{view}.png" for view in STANDARD_VIEWS]
        + [f"rest/{view}.collision.png" for view in STANDARD_VIEWS]
        + ["rest/hand_camera.camera.png", "rest/hand_camera.table.png"]
    )
    card = out.read_text()
    for name in names:
        assert f"(<panda_images/{name}>)" in card
    robot = np.asarray(Image.open(folder / "rest" / "three_quarter.png").convert("RGB"))
    camera = Image.open(folder / "rest" / "hand_camera.table.png")
    assert robot.shape == (240, 320, 3) and camera.size == (128, 128)
    # the Panda is white and near-black on a light ground: dark pixels are the robot's
    assert 0.02 < (robot.max(axis=2) < 60).mean() < 0.5
    table = np.asarray(camera.convert("RGB")).astype(int)
    red = (table[:, :, 0] > 150) & (table[:, :, 1] < 80) & (table[:, :, 2] < 80)
    assert red.sum() > 10  # the cube under the gripper


@pytest.mark.slow
def test_a_panda_camera_mounted_backwards_is_warned_about_with_its_picture(
    tmp_path: Path,
) -> None:
    out = tmp_path / "backwards.md"
    diagnostics = run_doc(BACKWARDS_SPEC, out, images=True).write().diagnostics
    assert not has_errors(diagnostics)
    found = {d.code: d for d in diagnostics if d.code in CAMERA_CODES}
    assert set(found) == {"RS560", "RS563"}
    away = found["RS563"]
    assert (away.location.line, away.location.column) == (31, 3)
    assert "moves with the tcp 'panda_hand_tcp' but looks away from it" in away.message
    picture = images_folder(out).as_posix() + "/rest/hand_camera.camera.png"
    assert away.message.endswith(picture) and Path(picture).is_file()


@pytest.mark.slow
@pytest.mark.parametrize(
    "spec",
    sorted(p.name for p in MANISKILL_SPECS.glob("*.yaml") if "cameras:" in p.read_text()),
)
def test_no_shipped_camera_is_warned_about(spec: str, tmp_path: Path) -> None:
    diagnostics = (
        run_doc(MANISKILL_SPECS / spec, tmp_path / "card.md", images=True).write().diagnostics
    )
    assert not has_errors(diagnostics)
    assert [d.format_text() for d in diagnostics if d.code in CAMERA_CODES] == []


@pytest.mark.slow
@pytest.mark.parametrize(
    ("far", "camera_views", "codes"),
    [
        # 2 cm: nothing is that near (RS562), and the tcp is past far, but not looked for
        ("0.02", "{tcp_in_view: false}", ["RS562"]),
        # the fingers fill some 7% of the picture: more than 1% is too much robot here
        ("100", "{max_robot_fraction: 0.01}", ["RS561"]),
    ],
)
def test_the_thresholds_in_checks_camera_views_are_the_spec_s(
    far: str, camera_views: str, codes: list[str], tmp_path: Path
) -> None:
    text = WRISTCAM_SPEC.read_text().replace("far: 100}", f"far: {far}}}")
    text += f"\nchecks:\n  camera_views: {camera_views}\n"
    spec = tmp_path / "camera.yaml"
    spec.write_text(text.replace("../../schemas", str(ROOT / "schemas")))
    diagnostics = run_doc(spec, tmp_path / "card.md", images=True).write().diagnostics
    found = sorted(d.code for d in diagnostics if d.code in CAMERA_CODES)
    assert found == codes, [d.format_text() for d in diagnostics]


@pytest.mark.slow
def test_an_mjcf_robot_is_drawn_as_mujoco_places_it(tmp_path: Path) -> None:
    from PIL import Image

    out = tmp_path / "humanoid.md"
    diagnostics = run_doc(MANISKILL_SPECS / "humanoid.yaml", out, images=True).write().diagnostics
    assert not has_errors(diagnostics), [d.format_text() for d in diagnostics]
    pictures = sorted(images_folder(out).rglob("*.png"))
    assert len(pictures) == len(STANDARD_VIEWS)
    image = np.asarray(Image.open(pictures[0]).convert("RGB")).astype(int)
    # the humanoid's capsules are MuJoCo's default colour, unlike the grey ground and sky
    coloured = (image.max(axis=2) - image.min(axis=2)) > 40
    assert coloured.mean() > 0.03


@pytest.mark.slow
def test_a_robot_with_nothing_sapien_would_draw_is_pictured_by_its_collision_shapes(
    tmp_path: Path,
) -> None:
    from PIL import Image

    def coloured_share(visual: str) -> float:
        folder = tmp_path / ("with_visual" if visual else "without")
        folder.mkdir()
        (folder / "arm.urdf").write_text(
            f'<robot name="arm"><link name="base">{visual}<collision><geometry>'
            '<sphere radius="0.1"/></geometry></collision></link>'
            '<link name="tip"><collision><geometry><box size="0.05 0.05 0.3"/></geometry>'
            "</collision></link>"
            '<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>'
            '<origin xyz="0 0 0.25"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>\n'
        )
        spec = folder / "arm.yaml"
        assert (
            not run_new(folder / "arm.urdf", spec, None, force=False, simulate=False).write().failed
        )
        diagnostics = run_doc(spec, folder / "arm.md", images=True).write().diagnostics
        assert not has_errors(diagnostics), [d.format_text() for d in diagnostics]
        picture = sorted(images_folder(folder / "arm.md").rglob("*.png"))[0]
        image = np.asarray(Image.open(picture).convert("RGB")).astype(int)
        # collision shapes are drawn one colour per link; the ground, the sky and a visual
        # shape without a colour of its own are grey
        return float(((image.max(axis=2) - image.min(axis=2)) > 40).mean())

    assert coloured_share("") > 0.03  # no visual at all: the collision shapes
    grey_box = '<visual><geometry><box size="0.2 0.2 0.2"/></geometry></visual>'
    assert coloured_share(grey_box) < 0.001  # a visual: it alone


@pytest.mark.slow
def test_a_mesh_that_cannot_be_read_is_left_out_with_rs662(tmp_path: Path) -> None:
    (tmp_path / "broken.stl").write_bytes(b"solid nothing\nendsolid\n")
    (tmp_path / "arm.urdf").write_text(
        '<robot name="arm"><link name="base"><visual><geometry><box size="0.2 0.2 0.1"/>'
        "</geometry></visual></link>"
        '<link name="tip"><visual><geometry><mesh filename="broken.stl"/></geometry></visual>'
        "</link>"
        '<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>'
        '<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>\n'
    )
    spec = tmp_path / "arm.yaml"
    assert (
        not run_new(tmp_path / "arm.urdf", spec, None, force=False, simulate=False).write().failed
    )
    diagnostics = run_doc(spec, tmp_path / "arm.md", images=True).write().diagnostics
    unreadable = [d for d in diagnostics if d.code == "RS662"]
    assert len(unreadable) == 1 and unreadable[0].location.file.endswith("arm.urdf")
    assert "visual mesh 'broken.stl' of link 'tip' cannot be drawn" in unreadable[0].message
    assert (tmp_path / "arm.md").is_file()


@pytest.mark.slow
def test_primitives_of_no_extent_are_left_out_and_flat_ones_drawn_as_sheets(
    tmp_path: Path,
) -> None:
    # pybullet's Laikago has <sphere radius="0.0"/> toes, which MuJoCo refused (RS664)
    (tmp_path / "arm.urdf").write_text(
        '<robot name="arm"><link name="base"><visual><geometry><box size="0.2 0.2 0"/>'
        "</geometry></visual></link>"
        '<link name="tip"><visual><geometry><sphere radius="0.0"/></geometry></visual>'
        '<collision><geometry><cylinder radius="0.03" length="0"/></geometry></collision>'
        "</link>"
        '<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>'
        '<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>\n'
    )
    spec = tmp_path / "arm.yaml"
    assert (
        not run_new(tmp_path / "arm.urdf", spec, None, force=False, simulate=False).write().failed
    )
    diagnostics = (
        run_doc(spec, tmp_path / "arm.md", images=True, collisions=True).write().diagnostics
    )
    assert [d.code for d in diagnostics if d.code.startswith("RS66")] == []
    assert sorted(images_folder(tmp_path / "arm.md").rglob("*.png"))


@pytest.mark.slow
def test_without_opengl_doc_images_is_rs661(tmp_path: Path) -> None:
    # GLFW needs a display, which a test machine has not
    env = {**os.environ, "MUJOCO_GL": "glfw", "DISPLAY": ""}
    out = tmp_path / "panda.md"
    done = run_robospec("doc", str(PANDA_SPEC), "-o", str(out), "--images", env=env)
    assert done.returncode == 1
    assert "error[RS661] no OpenGL to draw with (MUJOCO_GL=glfw)" in done.stdout + done.stderr
    assert not out.exists()
