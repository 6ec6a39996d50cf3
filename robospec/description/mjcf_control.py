"""What an MJCF says about holding and driving its robot, which ManiSkill's loader does not read:
``<key>`` keyframes and ``<actuator>`` gains (for ``robospec new``).

Both follow MuJoCo's rules (:mod:`robospec.description.mjcf_mujoco`): a key's ``qpos`` lists
every joint of the model in document order — a free joint 7 numbers (position, wxyz
quaternion), a ball joint 4, hinge and slide joints 1 — bodies that are not the robot included;
``qvel`` the same with 6, 3 and 1. A key shorter than that leaves the rest at ``qpos0`` (the
file's pose) and zero velocity, as MuJoCo 4 does; a longer one MuJoCo refuses, and so it is
left out. Values are radians whatever ``<compiler angle>`` says; a joint's
``ref`` (degrees for hinges in degree mode) is where MuJoCo's qpos has the body as the file
draws it, and ManiSkill's zero, so it is subtracted.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from lxml import etree

from robospec.description.facts import Actuator, FileKeyframe
from robospec.description.mjcf_frames import Unparsable
from robospec.description.mjcf_loaded import LoadedMjcf
from robospec.description.mjcf_mujoco import MAIN_CLASS, Table
from robospec.description.numbers import finite_numbers
from robospec.geometry import Pose, normalized

QPOS_WIDTH = {"free": 7, "ball": 4, "hinge": 1, "slide": 1}
QVEL_WIDTH = {"free": 6, "ball": 3, "hinge": 1, "slide": 1}
ACTUATOR_TAGS = (
    "general",
    "motor",
    "position",
    "velocity",
    "intvelocity",
    "damper",
    "cylinder",
    "muscle",
    "adhesion",
)


def _model_joints(loaded: LoadedMjcf) -> Iterator[tuple[etree._Element, str, float]]:
    """Every joint of the model in MuJoCo's qpos order: (element, type, ref in radians)."""

    def walk(body: etree._Element, childclass: str) -> Iterator[tuple[etree._Element, str, float]]:
        childclass = body.get("childclass", childclass)
        children = list(loaded.includes.children(body))
        for child in children:
            if child.tag == "freejoint":
                yield child, "free", 0.0
            elif child.tag == "joint":
                table = _table(loaded.mujoco_classes, child.get("class", childclass))
                attributes = {**table.get("joint", {}), **child.attrib}
                kind = attributes.get("type", "hinge")
                ref = (finite_numbers(attributes.get("ref")) or (0.0,))[0]
                if kind == "hinge" and loaded.degrees:
                    ref = math.radians(ref)
                yield child, kind, ref
        for child in children:
            if child.tag == "body":
                yield from walk(child, childclass)

    for worldbody in (el for el in loaded.top if el.tag == "worldbody"):
        for body in loaded.includes.find_all(worldbody, "body"):
            yield from walk(body, MAIN_CLASS)


def _table(classes: dict[str, Table], name: str) -> Table:
    return classes.get(name) or classes[MAIN_CLASS]


def file_keyframes(
    loaded: LoadedMjcf, active: tuple[str, ...], root_body_pose: Pose
) -> tuple[FileKeyframe, ...]:
    """The model's ``<key>`` elements, each as the robot's joint values and root pose
    (``root_body_pose`` where a key leaves the free joint at its qpos0)."""
    robot_joints = {joint: joint.get("name", "") for body in loaded.robot for joint in body.joints}
    root_free = loaded.robot_element.find("freejoint")
    layout = list(_model_joints(loaded))
    nq = sum(QPOS_WIDTH.get(kind, 1) for _, kind, _ in layout)
    nv = sum(QVEL_WIDTH.get(kind, 1) for _, kind, _ in layout)
    keys = [
        key
        for section in loaded.sections("keyframe")
        for key in loaded.includes.find_all(section, "key")
    ]
    found = []
    for index, key in enumerate(keys):
        qpos = finite_numbers(key.get("qpos")) if key.get("qpos") is not None else None
        qvel = finite_numbers(key.get("qvel")) if key.get("qvel") is not None else None
        if (key.get("qpos") is not None and (qpos is None or len(qpos) > nq)) or (
            key.get("qvel") is not None and (qvel is None or len(qvel) > nv)
        ):
            continue  # MuJoCo refuses the key: nothing to take from it
        positions: dict[str, float] = {}
        velocities: dict[str, float] = {}
        root_pose: Pose | None = None
        at_q = at_v = 0
        given_q = qpos or ()
        for element, kind, ref in layout:
            name = robot_joints.get(element)
            if name and at_q < len(given_q):
                positions[name] = given_q[at_q] - ref
            if name and qvel is not None and at_v < len(qvel):
                velocities[name] = qvel[at_v]
            if element is root_free:
                given = at_q + 7 <= len(given_q)
                root_pose = _free_pose(given_q[at_q : at_q + 7]) if given else root_body_pose
            at_q += QPOS_WIDTH.get(kind, 1)
            at_v += QVEL_WIDTH.get(kind, 1)
        found.append(
            FileKeyframe(
                name=key.get("name") or f"key{index}",
                line=loaded.where(key).line,
                qpos=tuple((j, positions.get(j, 0.0)) for j in active if j),
                root_pose=root_pose,
                qvel=tuple((j, velocities[j]) for j in active if j in velocities),
            )
        )
    return tuple(found)


def _free_pose(values: tuple[float, ...]) -> Pose | None:
    try:
        q = normalized((values[3], values[4], values[5], values[6]))
    except Unparsable:
        return None
    return ((values[0], values[1], values[2]), q)


def file_actuators(loaded: LoadedMjcf) -> tuple[Actuator, ...]:
    found = []
    for section in loaded.sections("actuator"):
        for element in loaded.includes.children(section):
            if element.tag in ACTUATOR_TAGS:
                found.append(_actuator(loaded, element))
    return tuple(found)


def _actuator(loaded: LoadedMjcf, element: etree._Element) -> Actuator:
    table = _table(loaded.mujoco_classes, element.get("class", MAIN_CLASS))
    # MuJoCo's actuator shortcuts all set one actuator default per class
    attributes: dict[str, str] = {}
    for tag in ACTUATOR_TAGS:
        attributes.update(table.get(tag, {}))
    attributes.update(element.attrib)
    tag = str(element.tag)
    kp: float | None = None
    kv: float | None = None
    if tag in ("position", "intvelocity"):
        kp = _first(attributes.get("kp"), 1.0)
        kv = _first(attributes.get("kv"), 0.0) if tag == "position" else None
    elif tag in ("velocity", "damper"):
        kv = _first(attributes.get("kv"), 1.0)
    elif tag == "general":
        kp, kv = _general_servo(attributes)
    return Actuator(
        name=attributes.get("name", ""),
        line=loaded.where(element).line,
        type=tag,
        joint=attributes.get("joint") or attributes.get("jointinparent"),
        kp=kp,
        kv=kv,
        ctrl_range=_limited_range(attributes, "ctrl"),
        force_range=_limited_range(attributes, "force"),
        gear=_first(attributes.get("gear"), 1.0),
    )


def _first(text: str | None, default: float) -> float:
    values = finite_numbers(text)
    return values[0] if values else default


def _general_servo(attributes: dict[str, str]) -> tuple[float | None, float | None]:
    """A general actuator with fixed gain and affine bias ``(0, -kp, -kv)`` is a position
    servo (Menagerie writes its arms this way)."""
    if attributes.get("gaintype", "fixed") != "fixed" or attributes.get("biastype") != "affine":
        return None, None
    gain = finite_numbers(attributes.get("gainprm", "1")) or (1.0,)
    bias = (*(finite_numbers(attributes.get("biasprm", "0")) or (0.0,)), 0.0, 0.0, 0.0)
    kp = gain[0]
    if bias[0] != 0 or not math.isclose(bias[1], -kp, rel_tol=1e-9, abs_tol=1e-12):
        return None, None
    return kp, -bias[2]


def _limited_range(attributes: dict[str, str], what: str) -> tuple[float, float] | None:
    values = finite_numbers(attributes.get(f"{what}range"))
    limited = attributes.get(f"{what}limited", "auto")
    if values is None or len(values) != 2 or limited == "false":
        return None
    return (values[0], values[1])
