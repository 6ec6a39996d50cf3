"""How ``robospec new``'s rest-pose search (:mod:`robospec.authoring.new.probe`) moves joints,
on a toy geometry instead of ManiSkill's contacts: the search only sees which pairs of links
touch how deeply, so a function of the pose stands in for the simulator here (the probe's
contacts against SAPIEN are tested with the corpus and tests/test_physics_procedure.py)."""

from __future__ import annotations

from robospec.authoring.new.probe import Contacts, Probe, Request

# pelvis (the root) -waist- torso -shoulder- upper_arm -elbow- forearm; pelvis -hip- thigh
JOINTS = ["waist", "shoulder", "elbow", "hip"]
PARENTS = {
    "torso": ("pelvis", "waist"),
    "upper_arm": ("torso", "shoulder"),
    "forearm": ("upper_arm", "elbow"),
    "thigh": ("pelvis", "hip"),
}


class ToyProbe(Probe):
    """The search of :class:`Probe` over :func:`arm_at_side` (no simulator)."""

    def __init__(self, request: Request) -> None:
        self.request = request
        self.index = {name: i for i, name in enumerate(request.joints)}
        self.followers = set()
        self.tried = 0
        self.always = None
        self._adjacent = None

    def contacts(self, qpos: list[float]) -> Contacts:
        self.tried += 1
        return {
            pair: depth
            for pair, depth in arm_at_side(qpos).items()
            if depth >= -self.request.clearance
        }


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


def _probe() -> ToyProbe:
    return ToyProbe(
        Request(
            spec="",
            uid="toy",
            mode="pd_joint_pos",
            joints=JOINTS,
            start=[0.0] * 4,
            limits=[(-1.0, 1.0), (0.0, 2.8), (0.0, 1.0), (-1.0, 1.0)],
            parents=PARENTS,
        )
    )


def test_a_contact_no_single_move_undoes_is_undone_by_a_chain_of_moves() -> None:
    probe = _probe()
    start = [0.0] * 4
    contacts = probe.contacts(start)
    assert probe._greedy(start, contacts, probe.movable(contacts)) is None
    moved = probe._descend(start, contacts)
    assert moved is not None
    qpos, touching = moved
    assert touching == {}
    # the arm's own joints moved, the waist (which carries everything above it) did not
    assert qpos[0] == 0.0 and qpos[3] == 0.0
    assert qpos[1] > 0.2 and qpos[2] > 0.3


def test_the_rest_pose_search_frees_an_arm_resting_inside_the_body() -> None:
    probe = _probe()
    qpos, touching = probe.search()
    assert touching == {}
    assert arm_at_side(qpos)[("forearm", "pelvis")] < -probe.request.clearance
