"""The drive gains of a scaffold, joint by joint, from the description alone: the MJCF
actuators' own servo gains where it has them, else natural-frequency gains about the joint's
effective inertia at the rest keyframe (:func:`.gains.analytic_gains`, :mod:`.joint_loads`);
force limits from the description's ratings (URDF ``<limit effort>``, an MJCF actuator's
``forcerange``, a motor's ``ctrlrange`` times its gear, the joint's ``actuatorfrcrange``).

A joint whose gains would need more force than its rating keeps the rating as its force limit
(the motor cannot give more): :func:`rating_warnings` says so, naming the rating. Joints that
cannot move at all (equal limits) get no drive
(:func:`.analysis.immobile_reason`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from robospec.authoring.new.analysis import RobotAnalysis, immobile_reason
from robospec.authoring.new.gains import (
    NATURAL_FREQUENCY,
    UNBOUNDED_SPAN,
    JointGains,
    analytic_gains,
)
from robospec.authoring.new.joint_loads import JointLoad, joint_loads
from robospec.description import Joint
from robospec.description.ratings import Rating, joint_ratings
from robospec.diagnostics import Diagnostic, Location, warning
from robospec.diagnostics.codes import GAINS_OVER_RATING
from robospec.geometry import matrix_from_quaternion
from robospec.physics.findings import significant
from robospec.physics.rating import GRAVITY_SHARE


def rating(analysis: RobotAnalysis, joint: Joint) -> Rating | None:
    """The largest force the description rates ``joint``'s motor for, and where (an MJCF
    joint's own ``actuatorfrcrange`` too, which the facts leave out)."""
    found = joint_ratings(analysis.description).get(joint.name)
    if found is not None:
        return found
    drive = analysis.drives.get(joint.name)
    if drive is not None and drive.force_limit is not None and drive.force_limit > 0:
        return Rating(drive.force_limit, drive.rated_by or "its actuator", drive.line or joint.line)
    return None


def loads(
    analysis: RobotAnalysis, qpos: Mapping[str, float], gravity: bool
) -> dict[str, JointLoad]:
    """Each joint's effective inertia and, with ``gravity``, the loads it holds at ``qpos``."""
    if analysis.kinematics is None:
        return {}
    feet = analysis.feet() if gravity and analysis.body.floating else ()
    upright = matrix_from_quaternion(analysis.upright(qpos))
    found = joint_loads(
        analysis.kinematics, analysis.inertials, qpos, analysis.armature, feet, upright
    )
    if gravity:
        return found
    return {name: JointLoad(load.inertia, 0.0, None) for name, load in found.items()}


def joint_gains(
    analysis: RobotAnalysis, qpos: Mapping[str, float], gravity: bool
) -> dict[str, JointGains]:
    """Every active joint that moves: its drive at the rest pose ``qpos``. ``gravity``: the
    robot's modes keep gravity (``balance_passive_force: false``), so drives hold its weight."""
    found = loads(analysis, qpos, gravity)
    out: dict[str, JointGains] = {}
    for joint in analysis.description.active_joints:
        if immobile_reason(joint) is not None:
            continue
        load = found.get(joint.name, JointLoad(0.0, 0.0))
        span = (
            joint.upper - joint.lower
            if joint.lower is not None and joint.upper is not None
            else None
        )
        kind = "prismatic" if joint.type == "prismatic" else "revolute"
        computed = analytic_gains(
            kind, load.inertia, load.load, span, rating(analysis, joint), load.topple
        )
        drive = analysis.drives.get(joint.name)
        if drive is not None and drive.stiffness is not None:
            # the model's own servo gains: what it was tuned with
            damping = drive.damping if drive.damping is not None else computed.damping
            force_limit = computed.force_limit
            if computed.rating is None:
                # unrated: what the servo asks for across the joint's whole range (the
                # natural-frequency gains' limit would clip the model's own law: robosuite's
                # Robotiq 2F-85, kp 20, held to 0.07 N m)
                reach = span if span is not None and math.isfinite(span) else UNBOUNDED_SPAN
                force_limit = significant(abs(load.load) + drive.stiffness * reach)
            computed = JointGains(
                significant(drive.stiffness),
                significant(damping),
                force_limit,
                computed.inertia,
                computed.load,
                0.0,  # the model's own gains: robospec claims nothing about them
                computed.rating,
            )
        out[joint.name] = computed
    return out


def rating_warnings(analysis: RobotAnalysis, gains: Mapping[str, JointGains]) -> list[Diagnostic]:
    """RS609 for each joint whose gains need more force than its rating: one warning at the
    rating in the description, naming it."""
    found = []
    path = str(analysis.source.path)
    for name, drive in gains.items():
        if not drive.over_rating or drive.rating is None:
            continue
        unit = "N" if _prismatic(analysis, name) else "N m"
        rating = f"{drive.rating.what} of {drive.rating.value:g} {unit}"
        if drive.measured:
            gravity = (
                f"; gravity alone puts {drive.load:.3g} {unit} of it on the joint at rest: the "
                "robot as rated cannot lift this link far (RS534 in robospec check)"
                if drive.load >= GRAVITY_SHARE * drive.rating.value
                else ""
            )
            message = (
                f"joint '{name}': measured in ManiSkill, its drive asked for {drive.needs:.3g} "
                f"{unit} in robospec check's step, more than {rating}; held at its rating it "
                f"is slower than the scaffold aims for (force_limit {drive.force_limit:g})"
                f"{gravity}"
            )
        elif drive.load >= drive.rating.value:
            message = (
                f"joint '{name}' holds a gravity load of {drive.load:.3g} {unit} at rest, "
                f"more than {rating}: it cannot hold the rest pose"
            )
        else:
            held = f" and its load of {drive.load:.3g} {unit}" if drive.load > 0.001 else ""
            message = (
                f"joint '{name}': at {NATURAL_FREQUENCY:g} rad/s its gains would need "
                f"{drive.needs:.3g} {unit} for robospec check's step{held}, more than {rating}; "
                f"the scaffold softens it to stiffness {drive.stiffness:g}, which the rating "
                "can drive (a slower joint)"
            )
        found.append(
            warning(
                Location(path, drive.rating.line, 1),
                GAINS_OVER_RATING,
                message,
                "check the rating (its units, a placeholder value); or move the rest keyframe "
                "where the load is smaller; the force limit stays at the rating",
            )
        )
    return found


def _prismatic(analysis: RobotAnalysis, name: str) -> bool:
    joint = analysis.description.joint(name)
    return joint is not None and joint.type == "prismatic"


def with_refined(
    gains: Mapping[str, JointGains],
    refined: Mapping[str, tuple[float, float, float]],
    over_rating: Mapping[str, tuple[float, float]],
) -> dict[str, JointGains]:
    """``gains`` with the refined stiffness, damping and force limit where there are some:
    a joint the search found needing more than its rating asks for what the search saw."""
    out = dict(gains)
    for name, (stiffness, damping, force_limit) in refined.items():
        old = gains.get(name)
        if old is None:
            continue
        needs, measured = (over_rating[name][0], True) if name in over_rating else (0.0, True)
        out[name] = JointGains(
            stiffness, damping, force_limit, old.inertia, old.load, needs, old.rating, measured
        )
    return out
