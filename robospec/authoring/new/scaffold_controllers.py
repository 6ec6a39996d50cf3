"""The controllers and control modes of a scaffold: one controller (or an absolute and a delta
pair) per group, and the two modes ``pd_joint_delta_pos`` and ``pd_joint_pos`` driving every
group.

* position groups (arm, legs, fingers...): ``pd_joint_pos`` and its delta, with each joint's
  gains from :mod:`.joint_gains` (the MJCF actuators' own where it has them, else from the
  joint's effective inertia; force limits from the description's ratings): one number where
  the group's joints agree, by joint where they differ; targets within the joints' limits, or
  one turn about the rest pose for a joint whose limits span more (:func:`target_range`);
* joints that cannot move (equal limits): one ``passive`` controller
  that leaves them be (gravity compensation stays on: they cannot fall);
* a planar base: ``pd_base_forward_vel`` when the robot has wheels (they roll forward, not
  sideways), else ``pd_base_vel``; none where the scaffold's ``mobile_base`` section adds the
  base (:mod:`.mobile_base`): the section's ``pd_base_vel`` joins every mode;
* wheels and a mobile root without planar joints: ``pd_joint_vel`` (±the wheels' velocity limit,
  else ±10 rad/s for wheels, ±1 for a root);
* joints no MJCF actuator drives: ``passive``;
* a closed loop's followers (:mod:`.linkages`): ``passive`` with no damping and no friction,
  the loop's drivers one ``pd_joint_pos_mimic`` (or ``pd_joint_pos``) gripper controller, as
  ManiSkill's Robotiq agents have them;
* a floating robot, or one with passive joints: ``balance_passive_force: false`` in every mode
  (ManiSkill's default cancels gravity on every joint: a free robot would hover, a passive joint
  float).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from robospec.authoring.new.analysis import RobotAnalysis
from robospec.authoring.new.gains import JointGains

# where a joint has no gains of its own (none can be computed: no kinematic model)
GAINS: dict[str, float] = {"stiffness": 1e3, "damping": 1e2, "force_limit": 100}
ROOT_VELOCITY: dict[str, Any] = {"lower": -1.0, "upper": 1.0, "damping": 1e3, "force_limit": 500}
WHEEL_SPEED = 10.0  # rad/s, when the description gives no velocity limit
TURN_RATE = 3.14  # rad/s, a planar base's largest turn rate
DELTA = 0.1
HALF_TURN = 3.141593  # rad (pi, as a scaffold writes it)
FULL_TURN = 2 * HALF_TURN
MODES = ("pd_joint_delta_pos", "pd_joint_pos")


def controllers_and_modes(
    analysis: RobotAnalysis,
    gains: Mapping[str, JointGains],
    rest: Mapping[str, float] | None = None,
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The controllers and the control modes; ``gains`` by joint (:mod:`.joint_gains`),
    ``rest`` the rest keyframe's joint positions (:func:`target_range`)."""
    groups = analysis.groups
    controllers: dict[str, Any] = {}
    absolute: dict[str, Any] = {}
    relative: dict[str, Any] = {}
    for name, kind in groups.kinds.items():
        joints = groups.groups[name]
        if kind == "planar_base" and analysis.source.mobile_base is not None:
            continue  # the mobile_base section drives it (its pd_base_vel joins every mode)
        if kind == "planar_base":
            controllers[f"{name}_vel"] = _planar_base(name, analysis.body.rolls)
            absolute[name] = relative[name] = f"{name}_vel"
        elif kind in ("base", "wheels"):
            controllers[f"{name}_vel"] = _joint_velocity(analysis, name, kind, joints)
            absolute[name] = relative[name] = f"{name}_vel"
        elif kind in ("passive", "immobile"):
            controllers[name] = {"type": "passive", "joints": name, "damping": 0.0}
            absolute[name] = relative[name] = name
        elif (
            kind == "linkage"
        ):  # a closed loop moves them: free, as ManiSkill's Robotiq leaves them
            controllers[name] = {"type": "passive", "joints": name, "damping": 0, "friction": 0}
            absolute[name] = relative[name] = name
        elif kind == "mimic":
            controllers[name] = {
                "type": "pd_joint_pos_mimic",
                "joints": name,
                "lower": None,
                "upper": None,
                **_gains(gains, joints),
                "normalize_action": False,
                "mimic": _mimic_map(analysis, joints),
            }
            absolute[name] = relative[name] = name
        else:
            lower, upper = target_range(analysis, joints, rest or {})
            controllers[f"{name}_pos"] = {
                "type": "pd_joint_pos",
                "joints": name,
                "lower": lower,
                "upper": upper,
                **_gains(gains, joints),
                "normalize_action": False,
            }
            controllers[f"{name}_delta_pos"] = {
                "extends": f"{name}_pos",
                "lower": -DELTA,
                "upper": DELTA,
                "use_delta": True,
                "normalize_action": True,
            }
            absolute[name] = f"{name}_pos"
            relative[name] = f"{name}_delta_pos"
    if not controllers:
        return {}, {}
    if unbalanced(analysis):
        absolute["balance_passive_force"] = relative["balance_passive_force"] = False
    return controllers, dict(zip(MODES, (relative, absolute), strict=True))


def target_range(
    analysis: RobotAnalysis, joints: list[str], rest: Mapping[str, float]
) -> tuple[dict[str, float | int] | None, dict[str, float | int] | None]:
    """The absolute controller's lower and upper targets: null (the joints' own limits),
    except where a joint's limits span more than a full turn: its targets then span one turn
    about its rest position (by joint). One turn reaches every orientation of the joint; a
    wider range only lets a target wind it round again, and a random target across Solo-12's
    ±10 rad (a placeholder range) flung its hip 4 rad past its limit."""
    spans: dict[str, tuple[float | None, float | None] | None] = {}
    for name in joints:
        joint = analysis.description.joint(name)
        if joint is None or joint.type == "prismatic":
            spans[name] = None
            continue
        spans[name] = (joint.lower, joint.upper)
    wide = [
        name
        for name, span in spans.items()
        if span is not None
        and span[0] is not None
        and span[1] is not None
        and span[1] - span[0] > FULL_TURN
    ]
    bounded = all(span is not None and None not in span for span in spans.values())
    if not wide or not bounded:
        return None, None
    lower: dict[str, float | int] = {}
    upper: dict[str, float | int] = {}
    for name, span in spans.items():
        assert span is not None
        low, high = span
        assert low is not None and high is not None
        if name in wide:
            centre = min(max(rest.get(name, 0.0), low + HALF_TURN), high - HALF_TURN)
            low, high = centre - HALF_TURN, centre + HALF_TURN
        lower[name], upper[name] = _tidy(low), _tidy(high)
    return lower, upper


def unbalanced(analysis: RobotAnalysis) -> bool:
    """Whether ManiSkill's gravity compensation must be off for this robot."""
    return analysis.body.floating or analysis.has_passive


def _planar_base(group: str, wheels: bool) -> dict[str, Any]:
    if wheels:
        return {
            "type": "pd_base_forward_vel",
            "joints": group,
            "lower": [-1.0, -TURN_RATE],
            "upper": [1.0, TURN_RATE],
            "damping": 1e3,
            "force_limit": 500,
        }
    return {"type": "pd_base_vel", "joints": group, **ROOT_VELOCITY}


def _joint_velocity(
    analysis: RobotAnalysis, group: str, kind: str, joints: list[str]
) -> dict[str, Any]:
    limits = [analysis.description.joint(j) for j in joints]
    speeds = [j.velocity for j in limits if j is not None and j.velocity]
    if kind == "wheels":
        speed = min(speeds) if speeds and len(speeds) == len(joints) else WHEEL_SPEED
        return {
            "type": "pd_joint_vel",
            "joints": group,
            "lower": -speed,
            "upper": speed,
            "damping": 1e3,
            "force_limit": 500,
        }
    return {"type": "pd_joint_vel", "joints": group, **ROOT_VELOCITY}


def _gains(gains: Mapping[str, JointGains], joints: list[str]) -> dict[str, Any]:
    """stiffness, damping and force_limit for ``joints``: one number when every joint has the
    same, else a value by joint."""
    out: dict[str, Any] = {}
    for key in ("stiffness", "damping", "force_limit"):
        values = {}
        for joint in joints:
            drive = gains.get(joint)
            values[joint] = _tidy(getattr(drive, key)) if drive is not None else GAINS[key]
        distinct = set(values.values())
        out[key] = distinct.pop() if len(distinct) == 1 else values
    return out


def _tidy(value: float) -> float | int:
    rounded = float(f"{value:.6g}")
    return int(rounded) if rounded.is_integer() and abs(rounded) < 1e15 else rounded


def _mimic_map(analysis: RobotAnalysis, joints: list[str]) -> dict[str, Any]:
    links = {m.follower: m for m in analysis.groups.mimic}
    mimic: dict[str, Any] = {}
    for joint in joints:
        link = links.get(joint)
        if link is None:
            continue
        if link.multiplier == 1.0 and link.offset == 0.0:
            mimic[joint] = link.leader
        else:
            mimic[joint] = {
                "joint": link.leader,
                # an MJCF tendon's ratio is computed (0.00805 / 0.00705): written as gains are
                "multiplier": _tidy(link.multiplier),
                "offset": _tidy(link.offset),
            }
    return mimic
