"""The sanity warnings (robospec.description.sanity) on what the docs' catalogue does not show:
a collision mesh with NaN vertices, which SAPIEN loads while QuickHull logs "critical" (the
issue's case), and many problems of one kind in one file said once, with a count."""

from __future__ import annotations

import struct
from pathlib import Path

from conftest import CODE_EXAMPLES

from robospec.description import load_description


def _stl(path: Path, corners: list[tuple[float, float, float]]) -> None:
    data = struct.pack("<80sI", b"test", len(corners) // 3)
    for i in range(0, len(corners), 3):
        flat = [c for v in corners[i : i + 3] for c in v]
        data += struct.pack("<12fH", 0, 0, 1, *flat, 0)
    path.write_bytes(data)


def test_a_collision_mesh_with_nan_vertices_is_a_located_warning(tmp_path: Path) -> None:
    urdf = (CODE_EXAMPLES / "RS725" / "arm.urdf").read_text()
    (tmp_path / "meshes").mkdir()
    nan = float("nan")
    _stl(
        tmp_path / "meshes" / "upper_arm.stl",
        [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0), (0, 0, 0.1), (nan, 0, 0), (0, 0.1, 0.1)],
    )
    (tmp_path / "arm.urdf").write_text(urdf)
    _, diagnostics = load_description(str(tmp_path / "arm.urdf"), "urdf")
    (found,) = [d for d in diagnostics if d.code == "RS093"]
    assert found.location.line == 11 and "NaN" in found.message
    assert not found.is_error


def test_joints_of_one_unknown_type_are_one_diagnostic_with_a_count(tmp_path: Path) -> None:
    ball = (CODE_EXAMPLES / "RS711" / "ball.urdf").read_text()
    second = ball.replace(
        "</robot>",
        """  <link name="hand"/>
  <joint name="wrist" type="spherical">
    <parent link="upper_arm"/>
    <child link="hand"/>
  </joint>
</robot>""",
    )
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "upper_arm.stl").write_bytes(
        (CODE_EXAMPLES / "RS711" / "meshes" / "upper_arm.stl").read_bytes()
    )
    (tmp_path / "two_balls.urdf").write_text(second)
    _, diagnostics = load_description(str(tmp_path / "two_balls.urdf"), "urdf")
    unknown = [d for d in diagnostics if "unknown type" in d.message]
    assert len(unknown) == 1
    assert "(and 1 more joints of type 'spherical': line 22)" in unknown[0].message
