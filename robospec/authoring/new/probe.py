"""The child process of ``robospec new`` that loads the scaffolded robot in ManiSkill: it finds
a rest pose in which no two links touch (:mod:`.pose_search`, over ManiSkill's contacts), the
pairs of links to exempt from collisions there (:mod:`.exemptions`), how high a floating robot's
root must stand for its lowest collision point to touch the ground (or a fixed one be mounted
for its links to clear it) and, when asked, the scaffold's gains at that pose
(:mod:`.refinement`).

Run as ``python -m robospec.authoring.new.probe`` with a JSON request on stdin (see
:class:`Request`); prints one JSON answer on stdout. A child, because loading a description
nobody checked can crash SAPIEN outright (a segfault takes the process with it): ``new`` then
writes the scaffold without the check and says why.

The contact test is ``robospec check``'s (:mod:`robospec.physics.self_contact`): set the pose,
hold the drives there, one physics step, and every pair of the robot's links deeper in contact
than ``min_depth`` (:meth:`LoadedRobot.posed`).
"""

from __future__ import annotations

import gc
import json
import math
import sys
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

from robospec.authoring.new.exemptions import Bodies, Sweep, bodies, physx_exemptions
from robospec.authoring.new.joint_space import JointSpace, Limits, MimicIndex
from robospec.authoring.new.pose_search import BUDGET, CLEARANCE, Pair, PoseSearch
from robospec.description import Joint
from robospec.description.facts import JointType
from robospec.geometry import IDENTITY, ZERO
from robospec.kinematics.tree import KinematicTree
from robospec.model.thresholds import MIN_CONTACT_DEPTH

if TYPE_CHECKING:
    from robospec.authoring.new.refinement import Refined
    from robospec.physics.sim import Sim

FLOATING_LIFT = 10.0  # m: a floating robot is held well above the ground while contacts count
# m: how far a contact's depth wanders between two loads of the same pose (float32 positions,
# the settling step): a pair this close to ``min_depth`` counts as touching
DEPTH_NOISE = 1e-5


@dataclass
class Request:
    spec: str  # a spec of the robot to register (the draft scaffold)
    uid: str
    mode: str  # a control mode of that spec whose controllers take joint positions
    joints: list[str]  # the active joints, in qpos order
    start: list[float]
    limits: list[Limits]
    # the kinematic tree: its root link, and each joint (name, type, parent, child) below it,
    # parents before children (the description's tree_joints)
    root: str = ""
    tree: list[tuple[str, str, str, str]] = field(default_factory=list)
    # (follower, leader, multiplier, offset) by index into ``joints``
    mimic: list[MimicIndex] = field(default_factory=list)
    floating: bool = False
    min_depth: float = MIN_CONTACT_DEPTH
    clearance: float = CLEARANCE  # the search keeps links this far apart (m)
    budget: int = BUDGET  # poses tried at most
    # (w, x, y, z): how a floating robot stands (its root turned so, for a y-up description)
    upright: list[float] = field(default_factory=lambda: list(IDENTITY))
    # pairs of links a closed loop joins: they meet where the loop closes, and no pose parts them
    joined: list[tuple[str, str]] = field(default_factory=list)
    # then scaffold the robot at the rest pose found and measure its gains there
    # (robospec.authoring.new.refinement): (the description file, the spec's path, the schema
    # reference)
    refinement: tuple[str, str, str] | None = None

    def joint_space(self) -> JointSpace:
        """The joints the search moves, in the tree the request names."""
        joints = (
            Joint(name, cast(JointType, kind), parent, child, line=0)
            for name, kind, parent, child in self.tree
        )
        tree = KinematicTree.of(self.root, joints)
        return JointSpace(tree, self.joints, self.limits, self.mimic)


class LoadedRobot:
    """The robot ManiSkill loaded (``sim``, in a mode whose controllers take joint positions),
    as the probe asks about it: the contacts at a pose, and where it stands on the ground."""

    def __init__(self, sim: Sim, floating: bool = False, upright: list[float] | None = None):
        self.sim = sim
        self.floating = floating
        self.upright = list(upright or IDENTITY)

    def posed(self, qpos: list[float]) -> dict[Pair, float]:
        """Every pair PhysX reports in contact (within its contact offset) with the robot at
        ``qpos``, its drives holding it there for one physics step: pair -> depth."""
        from robospec.resolve.resolved import ResolvedKeyframe

        lift = FLOATING_LIFT if self.floating else 0.0
        self.sim.start(ResolvedKeyframe("rest", (0.0, 0.0, lift), IDENTITY, tuple(qpos), None))
        self.sim.hold_drive_targets()
        self.sim.sim_step()
        return dict(self.sim.self_contacts())

    def sweep(self, min_depth: float = MIN_CONTACT_DEPTH) -> Sweep:
        """Sweeps of a joint over its range, over this robot's contacts, a pair touching when
        ``min_depth`` deep as robospec check counts it (less the depth's float noise)."""
        return Sweep(self.posed, min_depth - DEPTH_NOISE)

    def bodies(self, tree: KinematicTree) -> Bodies:
        """``tree``'s welded bodies, with the links SAPIEN gave collision shapes."""
        return bodies(tree, self.sim.shaped_links())

    def mount_height(self, qpos: list[float]) -> float | None:
        """For a fixed robot whose moving links reach below the ground at ``qpos`` (its root at
        the origin, where ManiSkill's scenes put it), the height to mount it at so they clear
        the ground; None when nothing reaches below."""
        from robospec.physics.ground import DEPTH, LIFT_MARGIN
        from robospec.resolve.resolved import ResolvedKeyframe

        self.sim.start(ResolvedKeyframe("rest", ZERO, IDENTITY, tuple(qpos), None))
        mounted = self.sim.mounted_links()
        lowest = [z for name, z in self.sim.lowest_points().items() if name not in mounted]
        if not lowest or min(lowest) >= -DEPTH:
            return None
        return -min(lowest) + LIFT_MARGIN

    def standing_height(self, qpos: list[float]) -> float | None:
        """How far above the ground the root must be for the lowest collision point of the
        robot, at ``qpos`` and upright (its root turned as ``upright`` says), to touch it."""
        import torch
        from mani_skill.utils.structs.pose import Pose

        robot = self.sim.robot
        turn = torch.tensor([self.upright], dtype=torch.float32)
        robot.set_pose(Pose.create_from_pq(torch.zeros(1, 3), turn))
        robot.set_qpos(torch.tensor([qpos], dtype=torch.float32))
        lowest = math.inf
        for link in robot.links:
            body = link._objs[0]
            if body.collision_shapes:
                lowest = min(lowest, float(body.compute_global_aabb_tight()[0][2]))
        return None if math.isinf(lowest) else -lowest


def load(request: Request) -> LoadedRobot:
    """Register the draft and load it (in this process, where nothing else runs)."""
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    from robospec.output.register import register
    from robospec.physics.sim import Sim

    # ManiSkill collects garbage each time it builds a scene (Sim builds one per pose tried):
    # with torch's and ManiSkill's objects in view that costs 0.15 s a pose, out of view
    # (frozen, as robospec check's worker does) 30 ms
    gc.collect()
    gc.freeze()
    register(request.spec)
    return LoadedRobot(Sim(request.uid, request.mode), request.floating, request.upright)


def run(request: Request) -> dict[str, Any]:
    robot = load(request)
    try:
        answer = _search(request, robot)
        if request.refinement is not None:  # the description is at hand: new's own run
            answer["ready"], answer["ready_refused"] = _ready(request, robot, answer)
    finally:
        robot.sim.close()
    if request.refinement is not None:
        try:
            found = refine_scaffold(request, answer)
        except Exception as exc:  # the scaffold's gains could not be measured: the parent says
            answer["refine_error"] = f"{type(exc).__name__}: {exc}"
        else:
            answer.update(
                gains=found.gains,
                over_rating=found.over_rating,
                refined=found.changed,
                simulations=found.simulations,
                solver_position_iterations=found.solver_position_iterations,
            )
    return answer


def _search(request: Request, robot: LoadedRobot) -> dict[str, Any]:
    """The rest pose, its height, and the pairs to exempt there."""
    space = request.joint_space()
    joined = {frozenset(pair) for pair in request.joined}

    def apart_at(qpos: list[float]) -> dict[Pair, float]:
        """The contacts at ``qpos`` but those of links a loop joins."""
        return {p: d for p, d in robot.posed(qpos).items() if frozenset(p) not in joined}

    search = PoseSearch(space, apart_at, request.clearance, request.budget)
    qpos, contacts = search.search(request.start)
    height = robot.standing_height(qpos) if request.floating else robot.mount_height(qpos)
    near = robot.posed(qpos)  # the rest pose, within PhysX's contact offset
    found = robot.bodies(space.tree)
    sweep = robot.sweep(request.min_depth)
    exempt = physx_exemptions(found, robot.sim.hinge_axes(), space, qpos, near, sweep)
    return {
        "qpos": qpos,
        # in contact as robospec check counts it (the search kept a clearance besides), with a
        # margin: a depth at the threshold itself (TIAGo's 1 mm spheres centred on its hand's
        # safety box: 0.99999 mm here, 1.00003 mm in check) is on either side by float noise
        "touching": [
            [a, b, depth]
            for (a, b), depth in contacts.items()
            if depth >= request.min_depth - DEPTH_NOISE
        ],
        "tried": search.tried,
        # (one pose tried: no joint lies between the pairs touching there, so they always do)
        "always": sorted(search.always or ()),
        "root_height": height,
        "upright": list(request.upright),
        "adjacent": list(exempt),
        # why each adjacent pair is (exemptions.ADJACENT_WHY's keys), for the scaffold's header
        "adjacent_why": list(exempt.values()),
    }


def _ready(
    request: Request, robot: LoadedRobot, answer: dict[str, Any]
) -> tuple[list[float] | None, str]:
    """The ready keyframe of an arm with a gripper (:mod:`.ready_pose`): the first pose found
    in which no two links touch deeper than robospec check counts (but the pairs that touch at
    rest, which the scaffold declares never_collide) and none reaches below the ground farther
    than at rest; None when there is none, with what stopped the first pose found (the one
    farthest from its joints' limits): Baxter's every pose pressed its shoulder on its torso."""
    from pathlib import Path

    from robospec.authoring.new.analysis import analyse
    from robospec.authoring.new.exemptions import filtered_cliques
    from robospec.authoring.new.mobile_base import read_for_new
    from robospec.authoring.new.ready_pose import ready_poses
    from robospec.authoring.new.rest_pose import rest_from_answer
    from robospec.authoring.new.task_members import gripper_fingers
    from robospec.resolve.collision_packing import clique_pairs

    assert request.refinement is not None
    source, _ = read_for_new(Path(request.refinement[0]))  # as new read it (a mobile base)
    if source is None:
        return None, ""
    analysis = analyse(source)
    rest = rest_from_answer(answer, analysis.description)
    fingers = gripper_fingers(analysis, rest.qpos)
    if fingers is None:
        return None, ""
    exempt = {frozenset(pair) for pair in request.joined}
    exempt |= {frozenset((a, b)) for a, b, _ in rest.touching}
    exempt |= {frozenset(pair) for pair in rest.never_collide}
    # the pairs the MJCF keeps apart, which the scaffold declares never_collide
    exempt |= {
        frozenset(pair)
        for links in filtered_cliques(analysis.source.description)
        for pair in clique_pairs(links)
    }
    rest_qpos = [rest.qpos[name] for name in request.joints]
    floor = robot.mount_height(rest_qpos) or 0.0
    refused = ""
    for pose in ready_poses(analysis, rest.qpos, fingers):
        qpos = [pose[name] for name in request.joints]
        touching = [
            (pair, depth)
            for pair, depth in robot.posed(qpos).items()
            if depth >= request.min_depth - DEPTH_NOISE and frozenset(pair) not in exempt
        ]
        below = (robot.mount_height(qpos) or 0.0) > floor
        if not touching and not below:
            return qpos, ""
        if not refused:
            deepest = sorted(touching, key=lambda found: -found[1])[:2]
            refused = ", ".join(f"{a} + {b} touch ({d * 1000:.0f} mm)" for (a, b), d in deepest)
            refused = refused or "it reaches below the ground"
    return None, refused


def refine_scaffold(request: Request, answer: dict[str, Any]) -> Refined:
    """Scaffold the robot at the rest pose found (as the parent will: the same functions on
    the same answer), register it, and measure and refine its gains
    (:mod:`robospec.authoring.new.refinement`)."""
    import tempfile
    from pathlib import Path

    from robospec.authoring.new.analysis import analyse
    from robospec.authoring.new.joint_gains import joint_gains
    from robospec.authoring.new.refinement import loop_iterations, refine
    from robospec.authoring.new.rest_pose import REFINE_UID, rest_from_answer
    from robospec.authoring.new.scaffold import scaffold
    from robospec.authoring.new.scaffold_controllers import unbalanced
    from robospec.description.ratings import joint_ratings
    from robospec.importer.yamlout import to_yaml
    from robospec.output.register import register
    from robospec.physics.sim import Sim
    from robospec.pipeline import compile_spec

    assert request.refinement is not None
    description, out, schema = request.refinement
    from robospec.authoring.new.mobile_base import read_for_new

    source, _ = read_for_new(Path(description))
    if source is None:
        raise ValueError(f"cannot read {description} again")
    analysis = analyse(source)
    rest = rest_from_answer(answer, analysis.description)
    gains = joint_gains(analysis, rest.qpos, unbalanced(analysis))
    draft = scaffold(analysis, Path(out), rest, REFINE_UID, absolute_paths=True, gains=gains)
    with tempfile.TemporaryDirectory(prefix="robospec-new-refine-") as folder:
        spec = Path(folder) / "refine.yaml"
        spec.write_text(to_yaml(draft, schema), encoding="utf-8")
        item = compile_spec(spec)
        if not item.ok or item.context is None or item.robot is None:
            raise ValueError("the scaffold does not compile")
        register(spec)
        ratings = {k: r.value for k, r in joint_ratings(item.context.description).items()}
        # the rest keyframe as the draft resolves it, so as robospec check will hold it: its
        # root where the description places the robot (an MJCF wrapper body's turn included:
        # the Shadow hand's mount turns its wrist across gravity, which sagged 0.073 rad there
        # and 0.002 rad upright at the origin)
        keyframe = next(k for k in item.robot.keyframes if k.name == "rest")
        checks = item.context.spec.checks
        sim = Sim(REFINE_UID, request.mode)
        try:
            found = refine(sim, checks, ratings, keyframe)
            if item.robot.loops:  # in check's first mode, as check tests the loops
                with Sim(REFINE_UID, item.robot.modes[0].name) as first:
                    loop_iterations(first, sim, checks, keyframe, item.robot.loops, found)
        finally:
            sim.close()
        return found


def main() -> int:
    raw = json.loads(sys.stdin.read())
    raw["limits"] = [tuple(pair) for pair in raw["limits"]]
    raw["mimic"] = [tuple(item) for item in raw.get("mimic", [])]
    raw["tree"] = [tuple(joint) for joint in raw.get("tree", [])]
    raw["joined"] = [tuple(pair) for pair in raw.get("joined", [])]
    if raw.get("refinement") is not None:
        raw["refinement"] = tuple(raw["refinement"])
    try:
        answer = run(Request(**raw))
    except Exception as exc:  # the robot could not be loaded: the parent says so and goes on
        answer = {"error": f"{type(exc).__name__}: {exc}"}
    sys.stdout.write("\n" + json.dumps(answer) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
