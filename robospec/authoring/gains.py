"""The gains an MJCF's actuators were tuned with, as joint drives for a scaffold's controllers
(the actuators themselves are facts of the description: ``RobotDescription.actuators``).

With ``g`` the actuator's gear (a joint feels ``g`` times its force and moves its length ``g``
times as fast):

* a position servo (``<position>``, or a ``<general>`` whose bias makes it one): stiffness
  ``kp·g²``; damping ``kv·g²``, or the joint's own ``damping`` when ``kv`` is 0;
* force limit: ``|g|·max|forcerange|`` when the force is limited; for a ``<motor>``, whose force
  is its control, ``|g|·max|ctrlrange|`` when the control is limited; else the joint's own
  ``actuatorfrcrange``.

An actuator that drives a tendon, site or body says nothing about one joint and is left out.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from robospec.description import RobotDescription


@dataclass(frozen=True)
class Drive:
    """Gains for one joint; None where the actuator does not say."""

    stiffness: float | None = None
    damping: float | None = None
    force_limit: float | None = None


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
        damping = actuator.kv * g * g if actuator.kv else None
        if stiffness is not None and damping is None:
            damping = _number(joint.get("damping")) or None
        force_limit = None
        if actuator.force_range is not None:
            force_limit = abs(g) * max(abs(v) for v in actuator.force_range)
        elif actuator.type == "motor" and actuator.ctrl_range is not None:
            force_limit = abs(g) * max(abs(v) for v in actuator.ctrl_range)
        else:
            force_limit = _largest(joint.get("actuatorfrcrange"))
        drives[actuator.joint] = Drive(stiffness, damping, force_limit)
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
