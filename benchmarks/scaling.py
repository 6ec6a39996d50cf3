"""Validate time and peak memory on synthetic robots of 100, 1,000 and 10,000 links.

The robot is a tree: a base link with branches of ``BRANCH`` revolute joints each (a deep
chain alone would measure recursion depth, not size). Its spec names joints both ways: groups
and controllers by glob (``b*_joint*``, ``*``), a keyframe and a link rule by exact name, so
the glob matching, the name lookups and the per-joint checks all scale with the robot. Growth
must be linear: the cost above a tiny robot's is fitted as ``a * links ** k``.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

from measure import PYTHON, child_env, sample
from section import Section

TITLE = "Validate time and memory against robot size"
BRANCH = 10
BASELINE_LINKS = 20  # the tiny robot whose cost is the fixed start-up cost
MAX_EXPONENT = 1.15  # above this, something grows faster than linearly


def synthetic_urdf(links: int) -> str:
    """A URDF of ``links`` links: ``base`` plus branches of ``BRANCH`` links."""
    parts = ['<?xml version="1.0"?>', '<robot name="synthetic">', _link("base")]
    for index in range(links - 1):
        branch, depth = divmod(index, BRANCH)
        name = f"b{branch}_link{depth}"
        parent = "base" if depth == 0 else f"b{branch}_link{depth - 1}"
        parts.append(_link(name))
        parts.append(
            f'  <joint name="b{branch}_joint{depth}" type="revolute">\n'
            f'    <parent link="{parent}"/><child link="{name}"/>\n'
            '    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 1 0"/>\n'
            '    <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>\n'
            "  </joint>"
        )
    parts.append("</robot>\n")
    return "\n".join(parts)


def _link(name: str) -> str:
    return (
        f'  <link name="{name}">\n'
        '    <inertial><mass value="0.1"/>'
        '<inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>\n'
        '    <collision><geometry><box size="0.02 0.02 0.1"/></geometry></collision>\n'
        "  </link>"
    )


SPEC = """\
robospec: 1
uid: synthetic_{links}
description: {{urdf: synthetic.urdf}}
materials:
  pad: {{static_friction: 1.0, dynamic_friction: 1.0, restitution: 0.0}}
links:
  "b0_link*": {{material: pad}}
  b1_link2: {{material: pad}}
groups:
  first: "b0_joint*"
  rest: {{all_but: [first, b1_joint3]}}
keyframes:
  rest:
    qpos: {{first: 0.1, b1_joint3: -0.2, rest: 0}}
controllers:
  first_pos: {{type: pd_joint_pos, joints: first, lower: -1, upper: 1, stiffness: 100, damping: 10}}
  rest_pos: {{extends: first_pos, joints: rest}}
  one_pos: {{extends: first_pos, joints: b1_joint3, stiffness: 50}}
  all_delta: {{type: pd_joint_pos, joints: "*", lower: -0.1, upper: 0.1, use_delta: true,
              stiffness: 100, damping: 10}}
control_modes:
  pd_joint_pos: {{first: first_pos, one: one_pos, rest: rest_pos}}
  pd_joint_delta_pos: {{all: all_delta}}
"""


def write_robot(folder: Path, links: int) -> Path:
    """Write the synthetic URDF and its spec into ``folder``; the spec's path."""
    (folder / "synthetic.urdf").write_text(synthetic_urdf(links), encoding="utf-8")
    spec = folder / "synthetic.yaml"
    spec.write_text(SPEC.format(links=links), encoding="utf-8")
    return spec


def measure(sizes: list[int], repeat: int) -> Section:
    rows = []
    for links in [BASELINE_LINKS, *sizes]:
        with tempfile.TemporaryDirectory(prefix="robospec-bench-size-") as folder:
            spec = write_robot(Path(folder), links)
            result = sample(
                [PYTHON, "-m", "robospec.cli", "validate", str(spec)], child_env(), repeat
            )
        if result.returncode != 0:
            raise RuntimeError(
                f"the {links}-link synthetic spec does not validate:\n{result.output[-3000:]}"
            )
        rows.append((links, result.median, result.spread, result.peak_rss_kib))
    (_, base_s, _, base_kib), measured = rows[0], rows[1:]
    lines = [
        "| links | median s | spread s | peak memory MiB | time / link above the "
        f"{BASELINE_LINKS}-link robot | KiB / link above it |",
        "| ---: | ---: | ---: | ---: | ---: | ---: |",
        f"| {BASELINE_LINKS} | {base_s:.3f} | {rows[0][2]} | {base_kib / 1024:.0f} | — | — |",
    ]
    for links, seconds, spread, kib in measured:
        extra = links - BASELINE_LINKS
        lines.append(
            f"| {links:,} | {seconds:.3f} | {spread} | {kib / 1024:.0f} | "
            f"{(seconds - base_s) / extra * 1e6:.0f} µs | {(kib - base_kib) / extra:.1f} |"
        )
    time_k = _exponent([(n, s - base_s) for n, s, _, _ in measured])
    memory_k = _exponent([(n, kib - base_kib) for n, _, _, kib in measured])
    linear = all(k is None or k <= MAX_EXPONENT for k in (time_k, memory_k))
    lines += [
        "",
        f"Fitted growth of the cost above the {BASELINE_LINKS}-link robot, `a * links ** k`: "
        f"time k = {_shown(time_k)}, memory k = {_shown(memory_k)} (linear: k ≈ 1; the target "
        f"is k ≤ {MAX_EXPONENT}). Each figure is one `robospec validate` process: parsing the "
        "URDF, resolving the globs, every check, the report. The robot is a tree of "
        f"{BRANCH}-link branches; its spec selects joints by glob, by group and by name.",
    ]
    return Section(TITLE, "\n".join(lines), linear)


def _exponent(points: list[tuple[int, float]]) -> float | None:
    """Least-squares slope of log(cost) over log(links); None with fewer than two sizes."""
    usable = [(math.log(n), math.log(cost)) for n, cost in points if cost > 0]
    if len(usable) < 2:
        return None
    mean_x = sum(x for x, _ in usable) / len(usable)
    mean_y = sum(y for _, y in usable) / len(usable)
    numerator = sum((x - mean_x) * (y - mean_y) for x, y in usable)
    return numerator / sum((x - mean_x) ** 2 for x, _ in usable)


def _shown(exponent: float | None) -> str:
    return "n/a (one size)" if exponent is None else f"{exponent:.2f}"
