"""The ``ready`` keyframe of an arm with a gripper: the pose ManiSkill's solutions start from.

ManiSkill's pick, push and stack solutions (``robospec solve``) move the tcp to each grasp along
a straight screw from wherever the episode starts. From a rest pose that points the gripper up
(an arm straight up at 0: pybullet's Panda, the Interbotix arms) the first grasp is a half turn
away and no screw reaches it within the joint limits. ManiSkill's own Panda starts bent over the
table with its fingers pointing down; ``ready`` is that pose for any arm: the fingers pointing
straight down, their middle half the arm's length in front of the first arm joint (the root
frame's +x, where ManiSkill's tasks face a robot) at that joint's height, and never lower than
:data:`LOWEST` of the arm's length above the root (the table the tasks mount it on); and, where
the arm can turn its wrist so, the fingers closing along the root frame's y, as the Panda's do.
The push and pull solutions hold the gripper as the episode starts it and push along x: closing
along y, the two closed fingers meet the cube's face side by side; turned 45° (pybullet's
Panda, whose hand is turned so on its flange), one finger's corner slid every cube off sideways
(0 of 20 pushed home).

The pose is found by damped least squares over the arm's joints (those between the root and
the link the fingers hang from), on the description's forward kinematics, from the rest pose,
within the joints' limits and from the middle of their ranges and a few poses drawn from a
fixed seed (a start may stall at a limit); of the poses found, the one whose joints keep
farthest from their limits, which the solutions' first moves need room to leave. An arm
that cannot point its fingers down there (too few joints, a wrist that cannot turn so) gets
no ``ready`` keyframe, and its episodes start at ``rest``. Where ManiSkill is installed, ``new``'s
probe (:mod:`.probe`) keeps the first pose found in which no two links touch and none reaches
below the ground, as ``robospec check`` tests a keyframe; none passing, there is no ``ready``.
"""

from __future__ import annotations

import itertools
import math
import random
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from robospec.authoring.new.analysis import RobotAnalysis
from robospec.authoring.new.task_members import (
    GRIPPING_KINDS,
    Fingers,
    finger_centre,
    finger_joint,
)

if TYPE_CHECKING:
    import numpy as np

FORWARD = 0.5  # of the arm's length: how far in front of its first joint the fingers wait
LOWEST = 0.3  # of the arm's length: the least height of the fingers above the root
ITERATIONS = 200
DAMPING = 0.05  # damped least squares' lambda (m)
STEP = 0.2  # rad (or m) a joint moves at most per iteration
ROTATION_WEIGHT = 0.3  # m per rad: how much a pointing error counts against a position error
POSITION_TOLERANCE = 0.002  # m
ANGLE_TOLERANCE = 0.02  # rad between the fingers' direction and straight down
FINITE_DIFFERENCE = 1e-5
HALVINGS = 6  # a step that does not help is halved this often before the descent gives up
RANDOM_STARTS = 6
SEED = 0
PARTING = 0.05  # of the stroke: how far the fingers open from closed to see which way they part


@dataclass(frozen=True)
class Grip:
    """Where a gripper closes and the way its fingers point, fixed in its hand's frame."""

    hand: str  # the link the fingers hang from
    middle: np.ndarray
    pointing: np.ndarray  # a unit vector
    across: np.ndarray  # the way the fingers part: a unit vector normal to pointing


def ready_pose(
    analysis: RobotAnalysis, rest: Mapping[str, float], fingers: Fingers
) -> dict[str, float] | None:
    """Joint values (every joint of ``rest``, the arm's changed) with the fingers pointing down
    in front of the arm, or None where the arm cannot: the first of :func:`ready_poses`."""
    return next(iter(ready_poses(analysis, rest, fingers)), None)


def ready_poses(
    analysis: RobotAnalysis, rest: Mapping[str, float], fingers: Fingers
) -> list[dict[str, float]]:
    """Every ready pose the descents found, those farthest from their joints' limits first
    (``new``'s probe takes the first in which no two links touch and none is below the
    ground)."""
    import numpy as np

    model = analysis.kinematics
    # a robot on a free root (a humanoid, a legged manipulator) starts where it stands: the
    # tasks that pick a cube mount a fixed arm, and an arm thrown forward tips a standing body
    if model is None or analysis.body.floating:
        return []
    arm = _arm_joints(analysis, fingers.parent)
    if len(arm) < 2:
        return []
    start = dict(rest)
    placed = model.at(start)
    anchors = [placed.axes[name].anchor for name in arm if name in placed.axes]
    if len(anchors) != len(arm):
        return []
    jaws = _grip(analysis, start, fingers)
    if jaws is None:
        return []
    grip = Grip(fingers.parent, *jaws)
    hand = placed.links[fingers.parent]
    points = [*anchors, hand[:3, :3] @ grip.middle + hand[:3, 3]]
    length = sum(float(np.linalg.norm(b - a)) for a, b in itertools.pairwise(points))
    if length <= 0:
        return []
    first = anchors[0]
    target = np.array(
        [first[0] + FORWARD * length, first[1], max(first[2], LOWEST * length)], dtype=float
    )
    limits = [_limits(analysis, name) for name in arm]
    found: list[dict[str, float]] = []
    for square in (True, False):  # closing along y where the wrist can turn so, else anyhow
        found = [
            pose
            for begin in _starts(start, arm, limits)
            if (pose := _descend(analysis, grip, target, arm, limits, begin, square)) is not None
        ]
        if found:
            break
    # farthest from its joints' limits first: the solutions' first moves start from it
    return sorted(found, key=lambda pose: -_margin(pose, arm, limits))


def _margin(pose: Mapping[str, float], arm: list[str], limits: list[tuple[float, float]]) -> float:
    """How near its nearest limit the arm is, as a fraction of that joint's range (a joint
    without limits: a full turn)."""
    margins = []
    for name, (low, high) in zip(arm, limits, strict=True):
        span = high - low if math.isfinite(high - low) else 2 * math.pi
        margins.append(min(pose[name] - low, high - pose[name]) / span)
    return min(margins)


def _starts(
    rest: dict[str, float], arm: list[str], limits: list[tuple[float, float]]
) -> list[dict[str, float]]:
    """Where the descent starts: the rest pose, the middle of the arm's ranges, then poses
    drawn over them from a fixed seed (a descent held at a joint limit goes nowhere)."""
    rng = random.Random(SEED)
    starts = [dict(rest)]
    for draw in range(RANDOM_STARTS + 1):
        pose = dict(rest)
        for name, (low, high) in zip(arm, limits, strict=True):
            low, high = max(low, -math.pi), min(high, math.pi)
            pose[name] = (low + high) / 2 if draw == 0 else rng.uniform(low, high)
        starts.append(pose)
    return starts


def _descend(
    analysis: RobotAnalysis,
    grip: Grip,
    target: np.ndarray,
    arm: list[str],
    limits: list[tuple[float, float]],
    qpos: dict[str, float],
    square: bool,
) -> dict[str, float] | None:
    """Damped least squares from ``qpos``, each step halved until it helps
    (:func:`robospec.kinematics.descent.damped_descent`, on the grip's offset from the
    target; ``square``: the fingers closing along y too)."""
    import numpy as np

    from robospec.kinematics.descent import damped_descent

    model = analysis.kinematics
    assert model is not None

    def placed(joints: np.ndarray) -> dict[str, float]:
        return {**qpos, **{name: float(v) for name, v in zip(arm, joints, strict=True)}}

    def offset(joints: np.ndarray) -> np.ndarray:
        return -_error(model.link(placed(joints), grip.hand), grip, target, square)

    found = damped_descent(
        offset,
        np.array([qpos[name] for name in arm], dtype=float),
        np.array([low for low, _ in limits], dtype=float),
        np.array([high for _, high in limits], dtype=float),
        _converged,
        iterations=ITERATIONS,
        damping=DAMPING,
        step=STEP,
        halvings=HALVINGS,
        difference=FINITE_DIFFERENCE,
    )
    return placed(found.joints) if found.converged else None


def _arm_joints(analysis: RobotAnalysis, hand: str) -> list[str]:
    """The moving joints from the root down to ``hand``, in that order: the arm's, and a
    trunk's or a torso's they hang from (a two-armed robot's arms are groups of their own);
    a gripper's or a mimic group's never."""
    model = analysis.kinematics
    assert model is not None
    in_arm = {
        joint
        for name, kind in analysis.groups.kinds.items()
        if kind not in GRIPPING_KINDS
        for joint in analysis.groups.groups[name]
    }
    above = {joint.child: joint for joint in model.joints}
    chain = []
    link = hand
    while link in above:
        joint = above[link]
        if joint.name in in_arm:
            chain.append(joint.name)
        link = joint.parent
    return chain[::-1]


def _limits(analysis: RobotAnalysis, name: str) -> tuple[float, float]:
    joint = analysis.description.joint(name)
    low = joint.lower if joint is not None and joint.lower is not None else -math.inf
    high = joint.upper if joint is not None and joint.upper is not None else math.inf
    return low, high


def _grip(
    analysis: RobotAnalysis, rest: Mapping[str, float], fingers: Fingers
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Where the fingers close, the way they point and the way they part, in the frame of the
    link they hang from, as ``robospec solve`` reads them (robospec.solve.gripper): the middle
    of the moving fingers' centres at both ends of their joints; from that link toward it, how
    the fingers part as they start to open from closed left out (a jaw that turns opens across
    the jaws); that parting."""
    import numpy as np

    model = analysis.kinematics
    assert model is not None
    ends = {}  # finger joint -> (closed, open)
    for link in fingers.links:
        joint = finger_joint(analysis, link)
        if joint is None or joint in ends:
            continue
        low, high = _limits(analysis, joint)
        if not (math.isfinite(low) and math.isfinite(high)) or high <= low:
            continue
        apart = []
        for end in (low, high):
            poses = model.at({**rest, joint: end}).links
            a, b = (finger_centre(analysis, poses, f) for f in fingers.links)
            apart.append(float(np.linalg.norm(a - b)))
        ends[joint] = (low, high) if apart[1] > apart[0] else (high, low)
    if not ends:
        return None

    def at(fraction: float) -> list[np.ndarray]:
        qpos = dict(rest)
        for joint, (shut, wide) in ends.items():
            qpos[joint] = shut + fraction * (wide - shut)
        poses = model.at(qpos).links
        hand = np.linalg.inv(poses[fingers.parent])
        return [
            hand[:3, :3] @ finger_centre(analysis, poses, f) + hand[:3, 3] for f in fingers.links
        ]

    shut, wide, parting = at(0.0), at(1.0), at(PARTING)
    across = (parting[0] - shut[0]) - (parting[1] - shut[1])
    moving = [i for i in range(2) if np.linalg.norm(wide[i] - shut[i]) > 1e-6]
    if not moving or np.linalg.norm(across) < 1e-9:
        return None
    across /= np.linalg.norm(across)
    middle = np.mean([(wide[i] + shut[i]) / 2 for i in moving], axis=0)
    pointing = middle - (middle @ across) * across
    if np.linalg.norm(pointing) < 1e-6:
        return None
    return middle, pointing / np.linalg.norm(pointing), across


def _error(hand: np.ndarray, grip: Grip, target: np.ndarray, square: bool) -> np.ndarray:
    """How far the grip is from the target, with the hand at pose ``hand``: the position's
    difference, and the turn (axis times angle, weighted) that takes the fingers' pointing to
    straight down; ``square``: and the parting's x component (the sine of its turn off the y
    axis, either way along it, once pointing down), weighted alike."""
    import numpy as np

    middle = hand[:3, :3] @ grip.middle + hand[:3, 3]
    pointing = hand[:3, :3] @ grip.pointing
    down = np.array([0.0, 0.0, -1.0])
    axis = np.cross(pointing, down)
    if np.linalg.norm(axis) < 1e-9:  # straight down, or straight up: a half turn about y
        axis = np.array([0.0, 1.0, 0.0])
    angle = math.acos(max(-1.0, min(1.0, float(pointing @ down))))
    turn = axis / np.linalg.norm(axis) * angle
    error = np.concatenate([target - middle, ROTATION_WEIGHT * turn])
    if not square:
        return error
    across = hand[:3, :3] @ grip.across
    return np.append(error, ROTATION_WEIGHT * float(across[0]))


def _converged(error: np.ndarray) -> bool:
    import numpy as np

    return bool(
        np.linalg.norm(error[:3]) < POSITION_TOLERANCE
        and np.linalg.norm(error[3:]) < ROTATION_WEIGHT * ANGLE_TOLERANCE
    )
