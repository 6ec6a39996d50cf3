"""The closed loops a description shows, for ``robospec new`` to write as ``loops:``.

* **MJCF** states its loops: each ``<equality connect>`` and ``<weld>`` between two of the
  robot's bodies (``RobotDescription.closures``). A connect's anchor is in the first body's
  frame; the second body's point is where that anchor is at the model's initial pose (MuJoCo's
  rule), which the forward kinematics gives.
* **URDF** has no loops: a four-bar is written as a tree whose followers ``<mimic>`` the
  driver, and where the tree was cut the two links overlap at rest (the Robotiq 2F-85's inner
  knuckle over its inner finger). Such a pair is found from the kinematics: two rigid bodies on
  different branches, every joint between them in one mimic family, whose relative motion as
  the leader sweeps its range is a turn about one point fixed in both (the pin the tree left
  out), that point inside both bodies' collision shapes at rest.

Each loop's **driver** is the joint that moves it: an actuated joint or the family's leader
where the loop has one, else the top joint of its longer branch (the crank, as ManiSkill's
Robotiq agents drive both outer knuckles); the loop's other joints are its passive followers.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from robospec.description import RobotDescription
from robospec.geometry import Matrix, rotation_angle
from robospec.resolve.mechanisms import rigid_bodies, tree_path

if TYPE_CHECKING:
    import numpy as np

    from robospec.authoring.description_file import DescriptionFile
    from robospec.authoring.new.gains import Drive
    from robospec.authoring.new.groups import Groups
    from robospec.kinematics.forward import KinematicModel

# a pin: the two bodies' relative motion turns about one point to within this, in m, over the
# leader's range, and turns by at least this, in rad (less is a slide: no pin to find)
PIN_RESIDUAL = 2e-4
PIN_TURN = 0.05
# the pin lies inside (or this near, in m) each body's collision box at rest: they meet there
MEETING_MARGIN = 0.005
SAMPLES = 9  # leader values over its range


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


def find_loops(analysis: Analysed, qpos: Mapping[str, float]) -> tuple[FoundLoop, ...]:
    """The loops of the robot ``analysis`` describes, at the rest joint values ``qpos``."""
    if analysis.kinematics is None:
        return ()
    if analysis.description.closures:
        return _stated(analysis, qpos)
    if analysis.source.kind == "mjcf":
        return ()
    return _cut(analysis, qpos)


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


# -- URDF: cut where the tree was made ---------------------------------------------------------


def _cut(analysis: Analysed, qpos: Mapping[str, float]) -> tuple[FoundLoop, ...]:
    description = analysis.description
    families = _families(analysis)
    if not families:
        return ()
    body = rigid_bodies(description)
    boxes = _boxes(analysis)
    found: list[FoundLoop] = []
    taken: set[frozenset[str]] = set()
    for leader, family in families.items():
        tops = sorted({body[j.child] for j in description.joints if j.name in family})
        for index, first in enumerate(tops):
            for second in tops[index + 1 :]:
                joints = _cycle(description, first, second)
                if len(joints) < 2 or not set(joints) <= set(family) or frozenset(joints) in taken:
                    continue
                pin = _pin(analysis, qpos, leader, family, first, second)
                if pin is None or not _meets(analysis, qpos, pin, first, second, body, boxes):
                    continue
                taken.add(frozenset(joints))
                name = _name(first, [f.name for f in found])
                found.append(
                    FoundLoop(
                        name,
                        (first, second),
                        pin,
                        joints,
                        _driver(analysis, first, second, joints),
                        source=f"the <mimic> linkage of '{leader}'",
                    )
                )
    return tuple(found)


def _families(analysis: Analysed) -> dict[str, dict[str, tuple[float, float]]]:
    """Leader -> {joint: (multiplier, offset)} for every mimic family of three joints or more
    (a four-bar has a crank and two followers), the leader at (1, 0)."""
    families: dict[str, dict[str, tuple[float, float]]] = {}
    for link in analysis.groups.mimic:
        family = families.setdefault(link.leader, {link.leader: (1.0, 0.0)})
        family[link.follower] = (link.multiplier, link.offset)
    return {leader: family for leader, family in families.items() if len(family) >= 3}


def _pin(
    analysis: Analysed,
    qpos: Mapping[str, float],
    leader: str,
    family: Mapping[str, tuple[float, float]],
    first: str,
    second: str,
) -> tuple[tuple[float, float, float], tuple[float, float, float]] | None:
    """The point fixed in both bodies as the leader sweeps its range (in each one's frame),
    or None when their relative motion is no turn about one point."""
    import numpy as np

    joint = analysis.description.joint(leader)
    assert joint is not None and analysis.kinematics is not None
    low = joint.lower if joint.lower is not None else -np.pi / 4
    high = joint.upper if joint.upper is not None else np.pi / 4
    relative = []
    for value in np.linspace(low, high, SAMPLES):
        values = dict(qpos)
        values.update({j: m * value + o for j, (m, o) in family.items()})
        links = analysis.kinematics.at(values).links
        relative.append(np.linalg.inv(links[first]) @ links[second])
    turns = [rotation_angle(_matrix(relative[0][:3, :3].T @ r[:3, :3])) for r in relative]
    if max(turns) < PIN_TURN:
        return None
    # p_first = R_i p_second + t_i for every i: six unknowns, three equations a sample; the pin
    # may slide along the turning axis, so take the point nearest the second body's origin
    rows = np.vstack([np.hstack([np.eye(3), -r[:3, :3]]) for r in relative])
    rhs = np.concatenate([r[:3, 3] for r in relative])
    solution, *_ = np.linalg.lstsq(rows, rhs, rcond=None)
    on_first, on_second = solution[:3], solution[3:]
    residual = np.abs(rows @ solution - rhs).max()
    if residual > PIN_RESIDUAL:
        return None
    return _point(on_first), _point(on_second)


def _meets(
    analysis: Analysed,
    qpos: Mapping[str, float],
    pin: tuple[tuple[float, float, float], tuple[float, float, float]],
    first: str,
    second: str,
    body: Mapping[str, str],
    boxes: Mapping[str, tuple[tuple[float, ...], tuple[float, ...]]],
) -> bool:
    """Whether the pin lies inside both bodies' collision shapes at rest (within the margin):
    where a four-bar's links overlap in its tree."""
    import numpy as np

    assert analysis.kinematics is not None
    links = analysis.kinematics.at(qpos).links
    world = links[first] @ np.array([*pin[0], 1.0])
    for top in (first, second):
        members = [name for name, owner in body.items() if owner == top and name in boxes]
        if not any(_inside(np.linalg.inv(links[m]) @ world, boxes[m]) for m in members):
            return False
    return True


def _inside(point: np.ndarray, box: tuple[tuple[float, ...], tuple[float, ...]]) -> bool:
    low, high = box
    return all(low[i] - MEETING_MARGIN <= point[i] <= high[i] + MEETING_MARGIN for i in range(3))


def _boxes(analysis: Analysed) -> dict[str, tuple[tuple[float, ...], tuple[float, ...]]]:
    """Each link's collision box in its frame (URDF)."""
    from robospec.description.shapes import collision_box
    from robospec.description.urdf import parse_xml

    root, _ = parse_xml(analysis.source.text, str(analysis.source.path))
    if root is None:
        return {}
    out = {}
    for element in root.iterfind("link"):
        box = collision_box(element, str(analysis.source.path))
        if box is not None:
            out[element.get("name", "")] = box
    return out


# -- shared ------------------------------------------------------------------------------------


def _cycle(description: RobotDescription, first: str, second: str) -> tuple[str, ...]:
    on_path = set(tree_path(description, first, second))
    return tuple(j for j in description.active_joint_names if j in on_path)


def _driver(analysis: Analysed, first: str, second: str, joints: Sequence[str]) -> str:
    """The joint that moves the loop: one an actuator drives or a mimic family leads, else one
    the model couples to such a joint (an MJCF equality between the two sides' drivers), else
    the top joint of the longer branch."""
    description = analysis.description
    leaders = {link.leader for link in analysis.groups.mimic}
    coupled = {coupling.follower for coupling in description.couplings}
    for driven in (set(analysis.drives) | leaders, coupled):
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


def _matrix(rotation: np.ndarray) -> Matrix:
    return (_point(rotation[0]), _point(rotation[1]), _point(rotation[2]))


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
