"""The closed loops a description shows, for ``robospec new`` to write as ``loops:``.

* **MJCF** states its loops: each ``<equality connect>`` and ``<weld>`` between two of the
  robot's bodies (``RobotDescription.closures``). A connect's anchor is in the first body's
  frame; the second body's point is where that anchor is at the model's initial pose (MuJoCo's
  rule), which the forward kinematics gives.
* **Cut parallelograms** (a URDF, or an MJCF that states no loop: robosuite's Robotiq
  grippers couple their linkages with tendons): a four-bar written as a tree leaves one pin
  out. Where three hinges on parallel axes make a parallelogram's three pins — a crank and a
  follower on one body, the coupler hanging from the crank — the fourth pin is the follower's
  pivot moved as far as the coupler's pivot is from the crank's, and a loop is written where
  that point lies inside both the follower's and the coupler's collision boxes at rest (where
  the tree left the two links overlapping; ManiSkill's Robotiq agents close their 2F-85 at
  exactly that point). The parallelogram also says how the followers turn with the driver
  (the follower as the crank, the coupler back, so that it keeps its orientation: a parallel
  gripper's pads): those rules replace what the description couples them by. General
  four-bars, whose fourth pin the tree alone does not say, are declared under ``loops:`` by
  hand.

Each loop's **driver** is the joint that moves it: an actuated joint or the family's leader
where the loop has one, else the top joint of its longer branch (the crank, as ManiSkill's
Robotiq agents drive both outer knuckles); the loop's other joints are its passive followers.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from robospec.description import RobotDescription
from robospec.resolve.mechanisms import rigid_bodies, tree_path

if TYPE_CHECKING:
    import numpy as np

    from robospec.authoring.description_file import DescriptionFile
    from robospec.authoring.new.gains import Drive
    from robospec.authoring.new.groups import Groups
    from robospec.kinematics.forward import KinematicModel


class Analysed(Protocol):
    """What the search reads of ``new``'s analysis (:class:`.analysis.RobotAnalysis`, which
    imports this module to find its loops)."""

    @property
    def source(self) -> DescriptionFile: ...
    @property
    def description(self) -> RobotDescription: ...
    @property
    def groups(self) -> Groups: ...
    @property
    def drives(self) -> Mapping[str, Drive]: ...
    @property
    def kinematics(self) -> KinematicModel | None: ...


@dataclass(frozen=True)
class FoundLoop:
    name: str
    links: tuple[str, str]
    at: tuple[tuple[float, float, float], tuple[float, float, float]]
    joints: tuple[str, ...]  # the cycle's active joints
    driver: str
    weld: bool = False
    source: str = ""  # what shows the loop, for the scaffold's header
    # how each follower turns with the driver where the shape of the linkage says it (a
    # parallelogram): (follower, multiplier, offset), the driver's value times the multiplier
    # plus the offset
    follows: tuple[tuple[str, float, float], ...] = ()


def find_loops(analysis: Analysed, qpos: Mapping[str, float]) -> tuple[FoundLoop, ...]:
    """The loops of the robot ``analysis`` describes, at the rest joint values ``qpos``."""
    if analysis.kinematics is None:
        return ()
    if analysis.description.closures:
        return _stated(analysis, qpos)
    # A general four-bar cut out of a URDF is not inferred: closed by a drive where a pin
    # search over its <mimic> family found it, TALOS's grippers opened 1.5 mm under random
    # actions (RS531). A parallelogram is closed even where a <mimic> family already turns
    # its joints at its rates: each follower's drive then holds its share of a grasp alone,
    # and the xArm6's fingers, pressed on a cube, squeezed it out of 4 grasps in 20 (1 in 20
    # closed)
    return _parallelograms(analysis)


# -- MJCF: stated -------------------------------------------------------------------------------


def _stated(analysis: Analysed, qpos: Mapping[str, float]) -> tuple[FoundLoop, ...]:
    import numpy as np

    description = analysis.description
    assert analysis.kinematics is not None
    links = analysis.kinematics.at(qpos).links
    found: list[FoundLoop] = []
    for closure in description.closures:
        first, second = closure.first, closure.second
        if first not in links or second not in links:
            continue
        anchor = np.array([*closure.anchor, 1.0])
        if closure.kind == "weld":  # MuJoCo: a weld's anchor is in the second body's frame
            on_second = anchor
            on_first = np.linalg.inv(links[first]) @ links[second] @ anchor
        else:
            on_first = anchor
            on_second = np.linalg.inv(links[second]) @ links[first] @ anchor
        joints = _cycle(description, first, second)
        if len(joints) < 2:
            continue
        name = _name(first, [f.name for f in found])
        found.append(
            FoundLoop(
                name,
                (first, second),
                (_point(on_first), _point(on_second)),
                joints,
                _driver(analysis, first, second, joints),
                closure.kind == "weld",
                f"<{closure.kind}> on line {closure.line}",
            )
        )
    return tuple(found)


# -- cut parallelograms ------------------------------------------------------------------------

PARALLEL = 1e-3  # rad: hinge axes this near parallel are a planar linkage's
SHORTEST_BAR = 0.005  # m: a bar shorter than this is no four-bar's (two pins in one)
MEETING_MARGIN = 0.002  # m: the missing pin lies inside (or this near) each link's collision box


@dataclass(frozen=True)
class _Hinge:
    name: str
    parent: str  # the rigid bodies it joins (their top links)
    child: str
    direction: np.ndarray
    anchor: np.ndarray


def _parallelograms(analysis: Analysed) -> tuple[FoundLoop, ...]:
    """The parallelograms the tree was cut out of: a crank and a follower hinged on one body,
    a coupler hinged on the crank, all on parallel axes, the follower's missing pin (its pivot
    moved by the crank's bar) inside both the follower's and the coupler's collision boxes —
    in the pose as written (every joint at 0), where the description assembles its linkage."""
    description = analysis.description
    assert analysis.kinematics is not None
    placed = analysis.kinematics.at({})
    body = rigid_bodies(description)
    hinges = [
        _Hinge(j.name, body[j.parent], body[j.child], axis.direction, axis.anchor)
        for j in description.active_joints
        if j.type in ("revolute", "continuous") and (axis := placed.axes.get(j.name)) is not None
    ]
    boxes = _boxes(analysis)
    found: list[FoundLoop] = []
    taken: set[frozenset[str]] = set()
    for crank in hinges:
        for coupler in (h for h in hinges if h.parent == crank.child):
            for follower in (h for h in hinges if h.parent == crank.parent and h is not crank):
                names = frozenset((crank.name, coupler.name, follower.name))
                if names in taken or follower.child in (crank.child, coupler.child):
                    continue
                pin = _missing_pin(placed.links, boxes, crank, coupler, follower)
                first, second = follower.child, coupler.child
                joints = _cycle(description, first, second)
                if pin is None or set(joints) != names:
                    continue
                taken.add(names)
                driver = _driver(analysis, first, second, joints)
                found.append(
                    FoundLoop(
                        _name(first, [f.name for f in found]),
                        (first, second),
                        pin,
                        joints,
                        driver,
                        source=f"the parallelogram of '{crank.name}', '{coupler.name}' and "
                        f"'{follower.name}'",
                        follows=_parallelogram_rules(crank, coupler, follower, driver),
                    )
                )
    return tuple(found)


def _missing_pin(
    links: Mapping[str, np.ndarray],
    boxes: Mapping[str, tuple[tuple[float, ...], tuple[float, ...]]],
    crank: _Hinge,
    coupler: _Hinge,
    follower: _Hinge,
) -> tuple[tuple[float, float, float], tuple[float, float, float]] | None:
    """Where the parallelogram's fourth pin is, in the follower's frame and the coupler's:
    the follower's pivot moved as far as the coupler's pivot is from the crank's; None unless
    the three hinges are parallel, its bars have a length, and the pin lies inside both links'
    collision boxes."""
    import numpy as np

    if not _parallel(crank, coupler, follower):
        return None
    bar = coupler.anchor - crank.anchor
    if min(np.linalg.norm(bar), np.linalg.norm(follower.anchor - crank.anchor)) < SHORTEST_BAR:
        return None
    pin = np.array([*(follower.anchor + bar), 1.0])
    on_first = (np.linalg.inv(links[follower.child]) @ pin)[:3]
    on_second = (np.linalg.inv(links[coupler.child]) @ pin)[:3]
    inside = _inside(on_first, boxes.get(follower.child))
    if not inside or not _inside(on_second, boxes.get(coupler.child)):
        return None
    return _point(on_first), _point(on_second)


def _parallel(*hinges: _Hinge) -> bool:
    import numpy as np

    first = hinges[0].direction
    return all(float(np.linalg.norm(np.cross(first, h.direction))) < PARALLEL for h in hinges[1:])


def _rates(crank: _Hinge, coupler: _Hinge, follower: _Hinge) -> dict[str, float]:
    """Each hinge's turn per turn of the crank, about its own axis: the follower turns as the
    crank does, the coupler back by as much (it keeps its orientation)."""
    import numpy as np

    return {
        crank.name: 1.0,
        follower.name: float(np.sign(np.dot(follower.direction, crank.direction))),
        coupler.name: -float(np.sign(np.dot(coupler.direction, crank.direction))),
    }


def _parallelogram_rules(
    crank: _Hinge, coupler: _Hinge, follower: _Hinge, driver: str
) -> tuple[tuple[str, float, float], ...]:
    """How the parallelogram's followers turn with ``driver``, from the pose as written (all
    at 0)."""
    rate = _rates(crank, coupler, follower)
    return tuple((name, rate[name] / rate[driver], 0.0) for name in rate if name != driver)


def _inside(point: np.ndarray, box: tuple[tuple[float, ...], tuple[float, ...]] | None) -> bool:
    if box is None:
        return False
    low, high = box
    return all(low[i] - MEETING_MARGIN <= point[i] <= high[i] + MEETING_MARGIN for i in range(3))


def _boxes(analysis: Analysed) -> dict[str, tuple[tuple[float, ...], tuple[float, ...]]]:
    """Each rigid body's collision box in its top link's frame: a URDF's (the file's, or the
    one written from MuJoCo's model); none for an MJCF on ManiSkill's loader."""
    import numpy as np

    from robospec.description.shapes import collision_box
    from robospec.description.urdf import parse_xml

    source = analysis.source
    if source.description.kind != "urdf" and source.loader != "mujoco":
        return {}
    root, _ = parse_xml(source.text, str(source.path))
    if root is None or analysis.kinematics is None:
        return {}
    body = rigid_bodies(source.description)
    links = analysis.kinematics.at({}).links
    corners: dict[str, list[np.ndarray]] = {}
    for element in root.iterfind("link"):
        name = element.get("name", "")
        box = collision_box(element, str(source.path))
        if box is None or name not in body or name not in links:
            continue
        top = body[name]
        into_top = np.linalg.inv(links[top]) @ links[name]
        for corner in _box_corners(box):
            corners.setdefault(top, []).append((into_top @ np.array([*corner, 1.0]))[:3])
    return {
        top: (tuple(np.min(points, axis=0)), tuple(np.max(points, axis=0)))
        for top, points in corners.items()
    }


def _box_corners(box: tuple[tuple[float, ...], tuple[float, ...]]) -> list[tuple[float, ...]]:
    low, high = box
    return [
        (x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])
    ]


# -- shared ------------------------------------------------------------------------------------


def _cycle(description: RobotDescription, first: str, second: str) -> tuple[str, ...]:
    on_path = set(tree_path(description, first, second))
    return tuple(j for j in description.active_joint_names if j in on_path)


def _driver(analysis: Analysed, first: str, second: str, joints: Sequence[str]) -> str:
    """The joint that moves the loop: one an actuator drives, else one a mimic family leads,
    else one the model couples to such a joint (an MJCF equality between the two sides'
    drivers), else the top joint of the longer branch."""
    description = analysis.description
    leaders = {link.leader for link in analysis.groups.mimic}
    coupled = {coupling.follower for coupling in description.couplings}
    for driven in (set(analysis.drives), leaders, coupled):
        for joint in joints:
            if joint in driven:
                return joint
    path = tree_path(description, first, second)
    branches = _branches(description, path)
    longest = max(branches, key=len)
    return longest[-1]  # the path runs up from each link: the top joint is last


def _branches(description: RobotDescription, path: Iterable[str]) -> list[list[str]]:
    """The path's joints split into its two branches (each from a link up to the meeting)."""
    joints = list(path)
    by_name = {j.name: j for j in description.joints}
    branches: list[list[str]] = [[]]
    for index, name in enumerate(joints):
        branches[-1].append(name)
        following = joints[index + 1] if index + 1 < len(joints) else None
        if following is not None and by_name[following].child != by_name[name].parent:
            branches.append([])
    moving = [[j for j in b if by_name[j].is_active] for b in branches]
    return [b for b in moving if b] or [joints]


def _point(vector: Sequence[float] | np.ndarray) -> tuple[float, float, float]:
    return (float(vector[0]), float(vector[1]), float(vector[2]))


def _name(link: str, taken: Sequence[str]) -> str:
    """``left``/``right`` from the link's name where it says a side, else the link's."""
    lowered = link.lower()
    side = next((s for s in ("left", "right") if s in lowered), None)
    base = side or link
    name, n = base, 1
    while name in taken:
        n += 1
        name = f"{base}{n}"
    return name
