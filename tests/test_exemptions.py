"""Which pairs of links ``robospec new`` exempts from collisions (:mod:`robospec.authoring.new.
exemptions`), over made-up kinematic trees: what the simulation would say (which links have
shapes, where hinges turn, which pairs touch at a pose) is given here as data and functions, so
each reason is tested without ManiSkill (tests/test_physics_procedure.py asks SAPIEN itself)."""

from __future__ import annotations

from robospec.authoring.new.exemptions import (
    MEET,
    THOROUGH,
    Sweep,
    bodies,
    mechanism_pairs,
    nesting_yokes,
    overlapping,
    physx_exemptions,
    pinned_pairs,
    shapeless_neighbours,
    welded_neighbours,
)
from robospec.authoring.new.joint_space import JointSpace
from robospec.authoring.new.pose_search import Pair
from robospec.description import Joint
from robospec.description.facts import JointType
from robospec.kinematics.tree import KinematicTree

TOUCH = 0.001  # m: how deep a pair must be to touch


def _tree(root: str, *joints: tuple[str, JointType, str, str]) -> KinematicTree:
    """A tree of (name, type, parent, child) joints."""
    return KinematicTree.of(root, [Joint(n, t, p, c, line=0) for n, t, p, c in joints])


# base (a flange welded to it) -hip- h1 -ab- h2 -twist- foot: the hip's two links have no shapes
FOOT = _tree(
    "base",
    ("weld", "fixed", "base", "flange"),
    ("hip", "revolute", "base", "h1"),
    ("ab", "revolute", "h1", "h2"),
    ("twist", "revolute", "h2", "foot"),
)


def test_links_joined_only_through_shapeless_links_and_what_is_welded_to_them_are_neighbours() -> (
    None
):
    found = bodies(FOOT, {"base", "flange", "foot"})
    assert shapeless_neighbours(found) == [("base", "foot"), ("flange", "foot")]
    # with shapes on the links between, each link is its parent's neighbour: PhysX leaves
    # them out itself
    assert shapeless_neighbours(bodies(FOOT, {"base", "flange", "h1", "h2", "foot"})) == []


# base -pitch (about z)- cross -roll (about x)- yoke: the cross's two hinges
YOKE = _tree(
    "base",
    ("pitch", "revolute", "base", "cross"),
    ("roll", "continuous", "cross", "yoke"),
)


def test_the_ends_of_a_universal_joint_near_each_other_are_exempt_where_its_axes_meet() -> None:
    found = bodies(YOKE, {"base", "cross", "yoke"})
    near = {("base", "yoke"): -0.003}
    meeting = {
        "cross": ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
        "yoke": ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
    }
    assert nesting_yokes(found, meeting, near) == [("base", "yoke")]
    # apart at rest, they keep colliding
    assert nesting_yokes(found, meeting, {}) == []
    # axes that pass apart (by more than MEET) make no universal joint; parallel ones neither
    passing = {**meeting, "yoke": ((0.0, 2 * MEET, 0.0), (1.0, 0.0, 0.0))}
    assert nesting_yokes(found, passing, near) == []
    parallel = {**meeting, "yoke": ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))}
    assert nesting_yokes(found, parallel, near) == []
    # a slide is no hinge
    sliding = _tree(
        "base", ("pitch", "prismatic", "base", "cross"), ("roll", "revolute", "cross", "yoke")
    )
    assert nesting_yokes(bodies(sliding, {"base", "cross", "yoke"}), meeting, near) == []


# base -swing- arm; a pedestal and a plate welded to the base
WELDED = _tree(
    "base",
    ("pedestal_weld", "fixed", "base", "pedestal"),
    ("plate_weld", "fixed", "base", "plate"),
    ("swing", "revolute", "base", "arm"),
)
SPACE = JointSpace(WELDED, ["swing"], [(-1.0, 1.0)])


def test_welded_links_and_links_across_a_joint_that_never_touch_over_its_range_are_exempt() -> None:
    found = bodies(WELDED, {"base", "pedestal", "plate", "arm"})
    near = {("base", "plate"): -0.01, ("arm", "pedestal"): -0.004, ("arm", "base"): -0.002}

    def apart(qpos: list[float]) -> dict[Pair, float]:
        return {("arm", "pedestal"): -0.004 + 0.003 * qpos[0]}  # closest at swing = 1: 1 mm

    # the plate is the base; the arm swings near the pedestal, never touching it; the arm and
    # the base PhysX leaves out itself
    exempt = welded_neighbours(found, SPACE, [0.0], near, Sweep(apart, TOUCH))
    assert exempt == [("arm", "pedestal"), ("base", "plate")]

    def reaching(qpos: list[float]) -> dict[Pair, float]:
        return {("arm", "pedestal"): -0.004 + 0.006 * qpos[0]}  # at swing = 1: 2 mm deep

    # an arm that can swing into the pedestal keeps colliding with it
    exempt = welded_neighbours(found, SPACE, [0.0], near, Sweep(reaching, TOUCH))
    assert exempt == [("base", "plate")]


# base -left- left jaw, -right- right jaw (the right a mimic follower of the left)
PINCER = _tree("base", ("left", "prismatic", "base", "lj"), ("right", "prismatic", "base", "rj"))


def _jaws(qpos: list[float]) -> dict[Pair, float]:
    """Jaws 3 mm apart closed, further apart as the pincer opens when the right follows the
    left; the left opening alone presses into the right."""
    left, right = qpos
    return {("lj", "rj"): -0.003 - left + (0.02 if right < 0.5 * left else 0.0)}


def test_the_parts_of_a_mechanism_its_coupling_keeps_apart_are_exempt() -> None:
    coupled = JointSpace(PINCER, ["left", "right"], [(0.0, 0.05)] * 2, [(1, 0, 1.0, 0.0)])
    assert mechanism_pairs(coupled, [0.0, 0.0], Sweep(_jaws, TOUCH)) == [("lj", "rj")]
    # without the coupling, nothing says the jaws stay apart
    loose = JointSpace(PINCER, ["left", "right"], [(0.0, 0.05)] * 2)
    assert mechanism_pairs(loose, [0.0, 0.0], Sweep(_jaws, TOUCH)) == []
    # an unbounded leader is never swept
    unbounded = JointSpace(PINCER, ["left", "right"], [(0.0, None)] * 2, [(1, 0, 1.0, 0.0)])
    assert mechanism_pairs(unbounded, [0.0, 0.0], Sweep(_jaws, TOUCH)) == []


# the xArm gripper's side, cut open: base -knuckle- k -finger- f, and base -inner- i, whose
# far end is pinned to the finger where the description leaves the loop's last joint out
LINKAGE = _tree(
    "base",
    ("knuckle", "revolute", "base", "k"),
    ("finger", "revolute", "k", "f"),
    ("inner", "revolute", "base", "i"),
)


def _cut(qpos: list[float]) -> dict[Pair, float]:
    """The finger and the inner knuckle 12 mm into each other wherever the coupling holds them
    (at the pin); apart once the inner knuckle turns away from the finger's knuckle; the
    knuckle against its finger (its child) and the inner knuckle touching at the open end."""
    knuckle, _, inner = qpos
    return {
        ("f", "i"): 0.012 if abs(knuckle - inner) < 1e-9 else -0.01,
        ("f", "k"): 0.005,
        ("i", "k"): 0.003 if knuckle < 0.1 else -0.002,
    }


def test_the_ends_of_a_closed_linkage_the_description_cuts_open_are_exempt() -> None:
    coupled = JointSpace(
        LINKAGE,
        ["knuckle", "finger", "inner"],
        [(0.0, 0.85)] * 3,
        [(1, 0, 1.0, 0.0), (2, 0, 1.0, 0.0)],
    )
    # touching in every pose of the coupling, and not parent and child (PhysX leaves those out)
    assert pinned_pairs(coupled, [0.0] * 3, Sweep(_cut, TOUCH)) == [("f", "i")]
    # without the coupling nothing pins them: a pose of one joint alone pulls them apart
    loose = JointSpace(LINKAGE, ["knuckle", "finger", "inner"], [(0.0, 0.85)] * 3)
    assert pinned_pairs(loose, [0.0] * 3, Sweep(_cut, TOUCH)) == []


def test_the_physx_exemptions_come_shapeless_first_then_each_reason_once() -> None:
    # the yoke's cross has no shape: the yoke and the base are neighbours through it, and the
    # ends of a universal joint; the flange is welded to the base
    tree = _tree(
        "base",
        ("weld", "fixed", "base", "flange"),
        ("pitch", "revolute", "base", "cross"),
        ("roll", "revolute", "cross", "yoke"),
    )
    found = bodies(tree, {"base", "flange", "yoke"})
    axes = {"cross": ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), "yoke": ((0.0, 0.0, 0.0), (1.0, 0, 0))}
    near = {("base", "flange"): 0.0, ("base", "yoke"): -0.001}
    space = JointSpace(tree, ["pitch", "roll"], [(-1.0, 1.0)] * 2)
    exempt = physx_exemptions(found, axes, space, [0.0] * 2, near, Sweep(lambda _: near, TOUCH))
    assert list(exempt) == [("base", "yoke"), ("flange", "yoke"), ("base", "flange")]
    # each under the first reason found (the header's words for it)
    assert list(exempt.values()) == ["shapeless", "shapeless", "welded"]
    # a cross with a shape: the yoke and the base nest round it, no longer shapeless neighbours
    found = bodies(tree, {"base", "flange", "cross", "yoke"})
    exempt = physx_exemptions(found, axes, space, [0.0] * 2, near, Sweep(lambda _: near, TOUCH))
    assert exempt == {("base", "yoke"): "yoke", ("base", "flange"): "welded"}


def test_pairs_touching_in_every_pose_are_exempt_as_neighbours_or_after_a_thorough_search() -> None:
    # pelvis -waist- torso -neck- head -nod- face: head and pelvis two joints apart (as near as
    # neighbours go), face and pelvis three
    tree = _tree(
        "pelvis",
        ("waist", "revolute", "pelvis", "torso"),
        ("neck", "revolute", "torso", "head"),
        ("nod", "revolute", "head", "face"),
    )
    touching = [("head", "pelvis", 0.01), ("face", "pelvis", 0.02), ("head", "torso", 0.01)]
    always = {("head", "pelvis"), ("face", "pelvis")}
    # neighbours that touched in every pose; a pair that did not stays touching
    assert overlapping(touching, always, THOROUGH - 1, tree) == (("head", "pelvis"),)
    # after a thorough search, far-apart pairs that always touched are coarse shapes
    assert overlapping(touching, always, THOROUGH, tree) == (
        ("head", "pelvis"),
        ("face", "pelvis"),
    )
