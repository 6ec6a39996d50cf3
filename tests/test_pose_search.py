"""How ``robospec new``'s rest-pose search (:mod:`robospec.authoring.new.pose_search`) moves
joints, on a toy geometry instead of ManiSkill's contacts: the search only sees which pairs of
links touch how deeply, so a function of the pose stands in for the simulator here (the probe's
contacts against SAPIEN are tested with the corpus and tests/test_physics_procedure.py)."""

from __future__ import annotations

from robospec.authoring.new.joint_space import JointSpace
from robospec.authoring.new.pose_search import Contacts, PoseSearch
from robospec.description import Joint
from robospec.kinematics.tree import KinematicTree

# pelvis (the root) -waist- torso -shoulder- upper_arm -elbow- forearm; pelvis -hip- thigh
TREE = KinematicTree.of(
    "pelvis",
    [
        Joint("waist", "revolute", "pelvis", "torso", line=0),
        Joint("shoulder", "revolute", "torso", "upper_arm", line=0),
        Joint("elbow", "revolute", "upper_arm", "forearm", line=0),
        Joint("hip", "revolute", "pelvis", "thigh", line=0),
    ],
)
JOINTS = ["waist", "shoulder", "elbow", "hip"]


def arm_at_side(qpos: list[float]) -> Contacts:
    """A forearm 65 mm inside the pelvis, as iCub's right arm rests: raising the shoulder lifts
    it out, into the thigh (while the shoulder is between 0.2 and 0.7 rad: further, the upper
    arm meets the pelvis), and bending the elbow takes it out of the thigh. No one joint's move
    leaves fewer pairs touching."""
    _, shoulder, elbow, _ = qpos
    found = {("forearm", "pelvis"): 0.065 - 0.2 * shoulder}
    if 0.2 < shoulder < 0.7:
        found[("forearm", "thigh")] = 0.02 - 0.06 * elbow
    if shoulder > 0.7:
        found[("pelvis", "upper_arm")] = 0.02 + 0.1 * (shoulder - 0.7)
    return found


def _search() -> PoseSearch:
    limits = [(-1.0, 1.0), (0.0, 2.8), (0.0, 1.0), (-1.0, 1.0)]
    return PoseSearch(JointSpace(TREE, JOINTS, limits), arm_at_side)


def test_a_contact_no_single_move_undoes_is_undone_by_a_chain_of_moves() -> None:
    search = _search()
    start = [0.0] * 4
    contacts = search.contacts(start)
    assert search._greedy(start, contacts, search.space.movable(contacts)) is None
    moved = search._descend(start, contacts)
    assert moved is not None
    qpos, touching = moved
    assert touching == {}
    # the arm's own joints moved, the waist (which carries everything above it) did not
    assert qpos[0] == 0.0 and qpos[3] == 0.0
    assert qpos[1] > 0.2 and qpos[2] > 0.3


def test_the_rest_pose_search_frees_an_arm_resting_inside_the_body() -> None:
    search = _search()
    qpos, touching = search.search([0.0] * 4)
    assert touching == {}
    assert arm_at_side(qpos)[("forearm", "pelvis")] < -search.clearance


def test_the_joints_between_two_links_go_nearest_first_then_in_qpos_order() -> None:
    # two arms off the pelvis: the wrists are as near their hands, the shoulders next
    arms = KinematicTree.of(
        "pelvis",
        [
            joint
            for side in ("l", "r")
            for joint in (
                Joint(f"{side}_shoulder", "revolute", "pelvis", f"{side}_arm", line=0),
                Joint(f"{side}_wrist", "revolute", f"{side}_arm", f"{side}_hand", line=0),
            )
        ],
    )
    joints = ["r_shoulder", "r_wrist", "l_shoulder", "l_wrist"]
    space = JointSpace(arms, joints, [(-1.0, 1.0)] * 4)
    assert space.nearest_first("l_hand", "r_hand") == [1, 3, 0, 2]
    # a mimic follower moves with its leader, never alone
    coupled = JointSpace(arms, joints, [(-1.0, 1.0)] * 4, [(3, 1, 1.0, 0.0)])
    assert coupled.nearest_first("l_hand", "r_hand") == [1, 0, 2]
    assert coupled.movable([("l_hand", "r_hand")]) == [0, 1, 2]
