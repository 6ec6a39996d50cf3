"""The rest pose of a scaffold as ManiSkill sees it: free of self-contact and, for a floating
robot, standing on the ground (:mod:`.probe` does the work in a child process; this is the
parent's side: the request, and the answer read back).

Without ManiSkill (the core install), or when ManiSkill cannot load the robot, the pose stays
0 where the limits allow and mid-range elsewhere, and the scaffold says it was not checked.
"""

from __future__ import annotations

import importlib.util
import json
import os
import signal
import subprocess
import sys
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from robospec.authoring.new import exemptions
from robospec.authoring.new.exemptions import ADJACENT_WHY, OVERLAPPING_WHY
from robospec.authoring.new.groups import MimicLink
from robospec.description import RobotDescription
from robospec.geometry import IDENTITY, Quaternion
from robospec.kinematics.tree import KinematicTree
from robospec.model.thresholds import MIN_CONTACT_DEPTH

PROBE_UID = "robospec_new_probe"
REFINE_UID = "robospec_new_refine"  # the scaffold at its rest pose, whose gains are measured
PROBE_MODE = "pd_joint_pos"
PROBE_TIMEOUT = 300.0  # s; loading a big robot on a slow CPU takes tens of seconds


@dataclass(frozen=True)
class RestPose:
    qpos: dict[str, float]  # every active joint
    # m: a floating robot's standing height, or the height a fixed robot is mounted at so that
    # its links clear the ground (None: it stands at the origin)
    root_height: float | None = None
    checked: bool = False  # whether ManiSkill tested it for self-contact
    touching: tuple[tuple[str, str, float], ...] = ()  # pairs still in contact (m deep)
    # pairs among ``touching`` that touched in every pose tried, at most two joints apart: their
    # shapes overlap where they are joined, and the scaffold declares them never_collide
    # (exemptions.overlapping)
    overlapping: tuple[tuple[str, str], ...] = ()
    tried: int = 0  # poses the search tried
    unchecked_because: str | None = None
    # (w, x, y, z): how a floating robot's root stands at rest (RobotAnalysis.upright: turned
    # for a description written y-up)
    upright: Quaternion = IDENTITY
    # pairs joined only through links without collision shapes, nesting round two hinges whose
    # axes meet, welded, or parts of one mechanism (exemptions.physx_exemptions): adjacent as
    # parent and child are, whose collisions PhysX leaves out; declared never_collide as
    # MoveIt's setup assistant disables adjacent links
    adjacent: tuple[tuple[str, str], ...] = ()
    # why each pair of ``overlapping`` and ``adjacent`` is declared never_collide (the texts
    # above); a pair not here reads as overlapping, or joined through shapeless links
    why: Mapping[tuple[str, str], str] = field(default_factory=dict)
    # the ready keyframe (.ready_pose) the probe chose, every active joint: one in which no two
    # links touch (but the pairs declared never_collide) and none reaches below the ground;
    # None with ``ready_checked``: none of the poses found passed
    ready: dict[str, float] | None = None
    ready_checked: bool = False
    ready_refused: str = ""  # what stopped the first pose found, where none passed

    def reason(self, pair: tuple[str, str]) -> str:
        """Why ``pair``, one of :attr:`never_collide`, is declared so, in a few words."""
        if pair in self.why:
            return self.why[pair]
        return OVERLAPPING_WHY if pair in self.overlapping else ADJACENT_WHY["shapeless"]

    @property
    def never_collide(self) -> tuple[tuple[str, str], ...]:
        """What the scaffold declares never_collide: the overlapping pairs, then the adjacent
        ones not among them."""
        return self.overlapping + tuple(p for p in self.adjacent if p not in self.overlapping)


def maniskill_installed() -> bool:
    return all(importlib.util.find_spec(name) is not None for name in ("mani_skill", "sapien"))


@dataclass(frozen=True)
class RefinedGains:
    """The scaffold's gains as measured in ManiSkill (:mod:`.refinement`)."""

    gains: dict[str, tuple[float, float, float]]  # joint -> stiffness, damping, force_limit
    over_rating: dict[str, tuple[float, float]]  # joint -> (force asked for, its rating)
    changed: tuple[str, ...]  # the controllers (groups) whose gains changed, "hold" too
    simulations: int
    # the solver position iterations the closed loops need (None: ManiSkill's default holds them)
    solver_position_iterations: int | None = None


@dataclass(frozen=True)
class Refinement:
    """What the child needs to scaffold the robot again at the rest pose it found and measure
    the scaffold's gains there (:mod:`.refinement`): one child process does both, so ManiSkill is
    imported once."""

    description: str  # the description file (absolute)
    out: str  # the spec's path (for the scaffold's relative references)
    schema: str  # the schema reference the scaffold names


def probe_rest_pose(
    draft: str,
    description: RobotDescription,
    start: dict[str, float],
    mimic: list[MimicLink],
    floating: bool,
    refinement: Refinement | None = None,
    upright: Quaternion = IDENTITY,
    joined: tuple[tuple[str, str], ...] = (),
    mode: str = PROBE_MODE,
) -> tuple[RestPose, RefinedGains | str | None]:
    """Search from ``start`` in ManiSkill; ``draft`` is the text of a valid spec of the robot
    whose uid is :data:`PROBE_UID` and which has ``mode`` (a planar base with nothing else to
    drive has only its base's); ``joined``: the
    pairs of links closed loops join, which may touch. With ``refinement``, the scaffold at the
    pose found is then measured too: its refined gains (a string when they could not be
    measured; None without ``refinement``)."""
    unchecked = RestPose(dict(start))
    if not maniskill_installed():
        return _unchecked(unchecked, "ManiSkill is not installed"), None
    joints = list(description.active_joint_names)
    index = {name: i for i, name in enumerate(joints)}
    request: dict[str, Any] = {
        "uid": PROBE_UID,
        "mode": mode,
        "joints": joints,
        "start": [start[name] for name in joints],
        "limits": [[j.lower, j.upper] for j in description.active_joints],
        "mimic": [
            [index[m.follower], index[m.leader], m.multiplier, m.offset]
            for m in mimic
            if m.follower in index and m.leader in index
        ],
        "root": description.root_link,
        "tree": [[j.name, j.type, j.parent, j.child] for j in description.tree_joints],
        "floating": floating,
        "min_depth": MIN_CONTACT_DEPTH,
        "upright": list(upright),
        "joined": [list(pair) for pair in joined],
    }
    if refinement is not None:
        request["refinement"] = [refinement.description, refinement.out, refinement.schema]
    with tempfile.TemporaryDirectory(prefix="robospec-new-") as folder:
        spec = Path(folder) / "probe.yaml"
        spec.write_text(draft, encoding="utf-8")
        request["spec"] = str(spec)
        answer, problem = _run_child(request)
    if answer is None:
        return _unchecked(unchecked, problem), None
    rest = rest_from_answer(answer, description)
    if refinement is None:
        return rest, None
    if "refine_error" in answer:
        return rest, str(answer["refine_error"])
    return rest, RefinedGains(
        gains={k: (float(v[0]), float(v[1]), float(v[2])) for k, v in answer["gains"].items()},
        over_rating={k: (float(v[0]), float(v[1])) for k, v in answer["over_rating"].items()},
        changed=tuple(answer["refined"]),
        simulations=int(answer["simulations"]),
        solver_position_iterations=answer.get("solver_position_iterations"),
    )


def rest_from_answer(answer: dict[str, Any], description: RobotDescription) -> RestPose:
    """The rest pose the search found (the child's answer): the parent's and the child's alike
    (the child scaffolds the robot at it to measure its gains)."""
    joints = list(description.active_joint_names)
    qpos = {name: _tidy(value) for name, value in zip(joints, answer["qpos"], strict=True)}
    height = answer.get("root_height")
    touching = tuple((a, b, float(d)) for a, b, d in answer["touching"])
    always = {(a, b) for a, b in answer.get("always", [])}
    tried = int(answer["tried"])
    tree = KinematicTree(description)
    overlapping = exemptions.overlapping(touching, always, tried, tree)
    why = {pair: exemptions.overlap_reason(pair, tree) for pair in overlapping}
    adjacent = tuple((str(a), str(b)) for a, b in answer.get("adjacent", []))
    # (the probe's kind of reason for each, in order; an answer without them reads as shapeless)
    for pair, kind in zip(adjacent, answer.get("adjacent_why", []), strict=False):
        why.setdefault(pair, ADJACENT_WHY.get(kind, ADJACENT_WHY["shapeless"]))
    ready = answer.get("ready")
    return RestPose(
        ready=None if ready is None else dict(zip(joints, map(_tidy, ready), strict=True)),
        ready_checked="ready" in answer,
        ready_refused=str(answer.get("ready_refused") or ""),
        qpos=qpos,
        root_height=None if height is None else _tidy(height),
        checked=True,
        touching=touching,
        overlapping=overlapping,
        tried=tried,
        adjacent=adjacent,
        why=why,
        upright=tuple(float(v) for v in answer.get("upright", IDENTITY)),  # type: ignore[arg-type]
    )


def _unchecked(pose: RestPose, why: str) -> RestPose:
    return RestPose(pose.qpos, unchecked_because=why)


def _run_child(request: dict[str, Any]) -> tuple[dict[str, Any] | None, str]:
    command = [sys.executable, "-m", "robospec.authoring.new.probe"]
    try:
        done = subprocess.run(
            command,
            input=json.dumps(request),
            capture_output=True,
            text=True,
            timeout=PROBE_TIMEOUT,
            env={**os.environ, "PYTHONWARNINGS": "ignore"},
        )
    except subprocess.TimeoutExpired:
        return None, f"loading it in ManiSkill took longer than {PROBE_TIMEOUT:.0f} s"
    if done.returncode < 0:
        name = _signal_name(-done.returncode)
        return None, f"the simulator crashed loading it ({name})"
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    try:
        answer = json.loads(lines[-1]) if lines else None
    except json.JSONDecodeError:
        answer = None
    if not isinstance(answer, dict):
        tail = done.stderr.strip().splitlines()[-1:] or [f"exit status {done.returncode}"]
        return None, f"ManiSkill could not load it: {tail[0]}"
    if "error" in answer:
        return None, f"ManiSkill could not load it: {_first_line(str(answer['error']))}"
    return answer, ""


def _signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def _first_line(text: str) -> str:
    return text.strip().splitlines()[0] if text.strip() else text


def _tidy(value: float) -> float:
    return float(round(value, 6)) + 0.0  # +0.0: never write -0.0
