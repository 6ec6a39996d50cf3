"""How much force each joint's motor is rated for, as the description says: a URDF joint's
``<limit effort>`` (``effort="0"`` means "not rated": descriptions write it for that, ManiSkill's
so100 among them), an MJCF actuator's ``forcerange`` times its gear, or a ``<motor>``'s
``ctrlrange`` times its gear (its control is its force). ``robospec new`` makes these its force
limits, and neither ``new`` nor ``robospec tune`` raises a force limit past them.
"""

from __future__ import annotations

from dataclasses import dataclass

from robospec.description.facts import RobotDescription


@dataclass(frozen=True)
class Rating:
    """The largest force the description says a joint's motor gives, and where it says so."""

    value: float  # N m, or N for a prismatic joint
    what: str  # e.g. "its <limit effort>", "actuator 'a1''s forcerange"
    line: int  # in the description file


def joint_ratings(description: RobotDescription) -> dict[str, Rating]:
    """Joint name -> its rating, for the joints the description rates."""
    found: dict[str, Rating] = {}
    for actuator in description.actuators:
        if actuator.joint is None:
            continue
        named = f"actuator '{actuator.name}'" if actuator.name else "its actuator"
        gear = abs(actuator.gear)
        if actuator.force_range is not None:
            value = gear * max(abs(v) for v in actuator.force_range)
            what = f"{named}'s forcerange"
        elif actuator.type == "motor" and actuator.ctrl_range is not None:
            value = gear * max(abs(v) for v in actuator.ctrl_range)
            what = f"{named}'s ctrlrange times its gear"
        else:
            continue
        if value > 0:
            found[actuator.joint] = Rating(value, what, actuator.line)
    for joint in description.active_joints:
        if joint.name not in found and joint.effort is not None and joint.effort > 0:
            found[joint.name] = Rating(joint.effort, "its <limit effort>", joint.line)
    return found
