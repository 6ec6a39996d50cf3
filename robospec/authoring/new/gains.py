"""Drive gains for a scaffold's controllers: the gains an MJCF's actuators were tuned with
(:func:`actuator_drives`; the actuators themselves are facts of the description:
``RobotDescription.actuators``), and natural-frequency gains about a joint's effective inertia
(:func:`analytic_gains`; :mod:`.joint_gains` applies both joint by joint).

With ``g`` the actuator's gear (a joint feels ``g`` times its force and moves its length ``g``
times as fast):

* a position servo (``<position>``, or a ``<general>`` whose bias makes it one): stiffness
  ``kp·g²``; damping ``kv·g²`` plus the joint's own ``damping`` (MuJoCo damps the joint with
  both; a ManiSkill joint's one damping is its drive's, which the controller sets);
* force limit: ``|g|·max|forcerange|`` when the force is limited; for a ``<motor>``, whose force
  is its control, ``|g|·max|ctrlrange|`` when the control is limited; else the joint's own
  ``actuatorfrcrange``.

An actuator that drives a tendon, site or body says nothing about one joint and is left out.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from robospec.description import RobotDescription
from robospec.description.ratings import Rating
from robospec.model.thresholds import MAX_JOINT_DRIFT, PRISMATIC_STEP
from robospec.model.thresholds import STEP as CHECK_STEP
from robospec.physics.findings import significant  # as tune writes gains


@dataclass(frozen=True)
class Drive:
    """Gains for one joint; None where the actuator does not say."""

    stiffness: float | None = None
    damping: float | None = None
    force_limit: float | None = None
    rated_by: str | None = None  # what sets force_limit, for messages ("actuator 'a' forcerange")
    line: int | None = None  # where (the actuator's line)


def actuator_drives(
    description: RobotDescription, joint_attributes: Mapping[str, Mapping[str, str]]
) -> tuple[dict[str, Drive], bool]:
    """Joint name -> its drive, and whether some actuator drives through something else than a
    joint (a tendon: then which joints are driven is not known). ``joint_attributes`` are the
    MJCF joints' attributes, defaults merged, by name (for ``damping`` and
    ``actuatorfrcrange``)."""
    drives: dict[str, Drive] = {}
    indirect = False
    for actuator in description.actuators:
        if actuator.joint is None:
            indirect = True
            continue
        joint = joint_attributes.get(actuator.joint, {})
        g = actuator.gear
        stiffness = actuator.kp * g * g if actuator.kp is not None else None
        servo = actuator.kv * g * g if actuator.kv else 0.0
        own = (_number(joint.get("damping")) or 0.0) if stiffness is not None else 0.0
        damping = servo + own or None
        force_limit = None
        named = f"actuator '{actuator.name}'" if actuator.name else "its actuator"
        rated_by: str | None = None
        if actuator.force_range is not None:
            force_limit = abs(g) * max(abs(v) for v in actuator.force_range)
            rated_by = f"{named}'s forcerange"
        elif actuator.type == "motor" and actuator.ctrl_range is not None:
            force_limit = abs(g) * max(abs(v) for v in actuator.ctrl_range)
            rated_by = f"{named}'s ctrlrange times its gear"
        else:
            force_limit = _largest(joint.get("actuatorfrcrange"))
            rated_by = "its actuatorfrcrange" if force_limit is not None else None
        drives[actuator.joint] = Drive(stiffness, damping, force_limit, rated_by, actuator.line)
    return drives, indirect


def _number(text: str | None) -> float | None:
    try:
        return float(text.split()[0]) if text else None
    except (ValueError, IndexError):
        return None


def _largest(text: str | None) -> float | None:
    try:
        values = [abs(float(v)) for v in text.split()] if text else []
    except ValueError:
        return None
    return max(values) if len(values) == 2 else None


# -- gains from the robot's masses ---------------------------------------------------------------

# The scaffold's drives: each joint a second-order system of natural frequency ``w`` and damping
# ratio ``zeta`` about its effective inertia ``I`` at the rest keyframe — stiffness ``I w²``,
# damping ``2 zeta sqrt(stiffness I)`` — as Isaac Lab's URDF importer sets natural-frequency
# gains. At 20 rad/s, critically damped, a step rises (10 % to 90 %) in about 0.17 s and
# settles within 10 % in about 0.2 s: well inside robospec check's defaults.
NATURAL_FREQUENCY = 20.0  # rad/s
DAMPING_RATIO = 1.0
# Where the joint holds a gravity load (a floating robot, or passive joints turning
# ManiSkill's gravity compensation off), stiff enough that the load moves it no further than
# this: a share of robospec check's max_joint_drift (rad), a millimetre (m) for a slide. The
# refinement in ManiSkill (.refine) holds the scaffold to the same share of the spec's.
HOLD_SHARE = 0.2
HOLD_DRIFT = {"revolute": HOLD_SHARE * MAX_JOINT_DRIFT, "prismatic": 0.001}
# robospec check's step sizes (checks.step_response.step, prismatic_step): what a step asks of
# a drive beyond its load
STEP = {"revolute": CHECK_STEP, "prismatic": PRISMATIC_STEP}
# a standing joint softened to its rating stays this many times stiffer than gravity's toppling
# stiffness: a little stiffer than that and the robot stands, leaning a long way first
STANCE_MARGIN = 2.0
MIN_INERTIA = 1e-6  # kg m² (kg): massless links still take a drive that moves them
UNBOUNDED_SPAN = math.pi  # rad: a continuous joint's "range" for its force limit


@dataclass(frozen=True)
class JointGains:
    """A scaffold's drive for one joint, and what it was made from."""

    stiffness: float
    damping: float
    force_limit: float
    inertia: float  # the effective inertia the gains are for (kg m², or kg)
    load: float  # the gravity load the joint holds (N m, or N; 0 under gravity compensation)
    # force the natural-frequency gains ask for: the load plus a check step (N m, or N); for
    # refined gains, what the drive asked for in ManiSkill when its rating held it back
    needs: float
    rating: Rating | None = None  # the description's rating, where it gives one
    measured: bool = False  # ``needs`` was measured in ManiSkill (refined gains)

    @property
    def over_rating(self) -> bool:
        return self.rating is not None and self.needs > self.rating.value * 1.0001


def analytic_gains(
    kind: str,
    inertia: float,
    load: float,
    span: float | None,
    rating: Rating | None,
    topple: float = 0.0,
) -> JointGains:
    """One joint's drive: ``kind`` revolute or prismatic (continuous counts as revolute),
    ``load`` the gravity torque it holds, ``span`` its range (None: unbounded), ``topple`` the
    toppling stiffness it stands against (:class:`.joint_loads.JointLoad`): gravity takes that
    much of its stiffness away, so it comes on top of what the joint needs."""
    slide = "prismatic" if kind == "prismatic" else "revolute"
    inertia = max(inertia, MIN_INERTIA)
    stiffness = topple + max(inertia * NATURAL_FREQUENCY**2, abs(load) / HOLD_DRIFT[slide])
    needs = abs(load) + stiffness * STEP[slide]
    if rating is not None and needs > rating.value:
        # a step would saturate the motor: soften the joint to what its rating gives (slower,
        # but a saturated drive brakes too late and overshoots); never below what holds the
        # load where the rating allows that, nor so soft that the robot topples over its feet
        softened = max((rating.value - abs(load)) / STEP[slide], 0.0) or stiffness
        stiffness = max(softened, STANCE_MARGIN * topple)
    stiffness = significant(stiffness)
    damping = significant(2.0 * DAMPING_RATIO * math.sqrt(stiffness * inertia))
    if rating is not None:
        force_limit = rating.value
    else:
        # unrated: what the drive asks for across the joint's whole range, so the limit never
        # clips its law
        reach = span if span is not None and math.isfinite(span) else UNBOUNDED_SPAN
        force_limit = significant(abs(load) + stiffness * max(reach, STEP[slide]))
    return JointGains(stiffness, damping, force_limit, inertia, abs(load), needs, rating)
