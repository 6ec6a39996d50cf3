"""The closed loops a description shows, for ``robospec new`` to write as ``loops:``.

* **MJCF** states its loops: each ``<equality connect>`` and ``<weld>`` between two of the
  robot's bodies (``RobotDescription.closures``). A connect's anchor is in the first body's
  frame; the second body's point is where that anchor is at the model's initial pose (MuJoCo's
  rule), which the forward kinematics gives.
* **URDF** has no loops: a four-bar is written as a tree whose followers ``<mimic>`` the
  driver. Finding where the tree was cut is not done yet (see :func:`find_loops`); such a
  linkage is declared under ``loops:`` by hand.

Each loop's **driver** is the joint that moves it: an actuated joint or the family's leader
where the loop has one, else the top joint of its longer branch (the crank, as ManiSkill's
Robotiq agents drive both outer knuckles); the loop's other joints are its passive followers.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from robospec.description import RobotDescription
from robospec.resolve.mechanisms import tree_path

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


def find_loops(analysis: Analysed, qpos: Mapping[str, float]) -> tuple[FoundLoop, ...]:
    """The loops of the robot ``analysis`` describes, at the rest joint values ``qpos``."""
    if analysis.kinematics is None:
        return ()
    if analysis.description.closures:
        return _stated(analysis, qpos)
    # A URDF's cut four-bars are not inferred yet: closed by a drive as found, TALOS's grippers
    # opened 1.5 mm under random actions (RS531), where the mimic gripper new wrote before
    # passes check; a URDF linkage is declared under loops: by hand until the inference's
    # drives are measured on more grippers
    return ()


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
