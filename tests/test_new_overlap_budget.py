"""``robospec new`` declares the pairs the rest-pose search found overlapping in every pose
``never_collide``; when collision-group bits run out for them all, the shallowest overlap is the
one left out (and named as still touching), never a deep one that happened to be found last.
The search itself is replaced by its answer (no simulation): what is tested is what ``new``
does with it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from ruamel.yaml import YAML

from robospec.authoring.commands import run_new
from robospec.authoring.new import rest_pose

pytestmark = pytest.mark.slow  # new compiles the 60-joint spec once per pair left out

PAIRS = 30  # one collision-group bit each, and 29 are free: one pair must go


def _urdf() -> str:
    inertial = (
        '<inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" '
        'izz="1e-4"/></inertial><collision><geometry><box size="0.01 0.01 0.01"/></geometry>'
        "</collision>"
    )
    links = [f'<link name="base">{inertial}</link>']
    for i in range(2 * PAIRS):
        links.append(f'<link name="l{i}">{inertial}</link>')
        links.append(
            f'<joint name="j{i}" type="revolute"><parent link="base"/><child link="l{i}"/>'
            f'<origin xyz="{i * 0.1} 0 0"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    return '<?xml version="1.0"?>\n<robot name="many">\n' + "\n".join(links) + "\n</robot>\n"


def test_when_bits_run_out_the_shallowest_overlap_is_left_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pairs = [(f"l{i}", f"l{i + PAIRS}") for i in range(PAIRS)]
    # found in this order, the last the deepest (20 mm); the shallowest (1 mm) is pair 3
    depths = {pair: 0.002 + 0.0001 * i for i, pair in enumerate(pairs)}
    depths[pairs[3]] = 0.001
    depths[pairs[-1]] = 0.02

    def answer(draft: str, description: Any, start: dict, *args: Any) -> tuple:
        touching = tuple((a, b, depths[(a, b)]) for a, b in pairs)
        found = rest_pose.RestPose(dict(start), None, True, touching, tuple(pairs), tried=200)
        return found, None

    monkeypatch.setattr(rest_pose, "maniskill_installed", lambda: True)
    monkeypatch.setattr(rest_pose, "probe_rest_pose", answer)
    (tmp_path / "many.urdf").write_text(_urdf(), encoding="utf-8")
    out = tmp_path / "many.yaml"
    result = run_new(tmp_path / "many.urdf", out, "many", force=True).write()
    assert not result.failed, [d.format_text() for d in result.diagnostics]
    declared = {tuple(p) for p in YAML(typ="safe").load(out.read_text())["never_collide"]}
    assert pairs[-1] in declared  # the deepest stays
    assert pairs[3] not in declared and len(declared) == PAIRS - 1
    (warning,) = [d for d in result.diagnostics if d.code == "RS605"]
    assert "l3 + l33 (1.0 mm)" in warning.message
