"""Which joints ``robospec check``'s step response steps the other way when a self-contact
blocks a controller group's step (:func:`robospec.physics.step_response._blocked_joints`), and
what tune makes of a joint the step left alone for want of room.

The selection reads only the step's trace and where the links are; a leg's links and contacts
stand in for the simulator here (the reversed step itself runs in SAPIEN in
tests/test_physics_procedure.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from robospec.physics.step_response import Response, StepTrace, _blocked_joints

# a right leg stepped as one group: the hip turned it into the left foot; the ankle, below,
# came up short, pressed against it
LEG = ("right_hip", "right_knee", "right_ankle")
BELOW = {
    "right_hip": {"right_thigh", "right_shin", "right_foot"},
    "right_knee": {"right_shin", "right_foot"},
    "right_ankle": {"right_foot"},
}


class Leg:
    """The few things of :class:`robospec.physics.sim.Sim` the selection reads."""

    joint_names = (*LEG, "left_hip")
    limits = np.array([[-np.inf, np.inf]] * 4)

    def moved_by(self, joint: str) -> set[str]:
        return BELOW.get(joint, {"left_foot"})

    def self_contacts(self) -> dict[tuple[str, str], float]:
        return {("left_foot", "right_foot"): 0.004}


def _trace(reached: dict[str, float]) -> StepTrace:
    empty = np.zeros((1, len(LEG)))
    return StepTrace(
        kind="position",
        joints=LEG,
        dt=0.01,
        fraction=empty,
        size=np.full(len(LEG), 0.1),
        target=np.full(len(LEG), 0.1),
        position=empty,
        velocity=empty,
        responses=tuple(Response(name, None, 0.0, None, 0.0, reached[name]) for name in LEG),
    )


def test_a_blocked_step_turns_back_every_joint_that_drove_the_link_into_the_contact() -> None:
    trace = _trace({"right_hip": 1.0, "right_knee": 1.0, "right_ankle": 0.76})
    blocked = _blocked_joints(Leg(), trace, np.zeros(len(LEG)), np.full(len(LEG), 0.1))  # type: ignore[arg-type]
    # the ankle alone turned back would leave the hip pressing the foot into the other
    assert blocked.tolist() == [True, True, True]


def test_a_step_no_contact_holds_back_is_not_turned_back() -> None:
    trace = _trace({"right_hip": 1.0, "right_knee": 1.0, "right_ankle": 1.0})
    blocked = _blocked_joints(Leg(), trace, np.zeros(len(LEG)), np.full(len(LEG), 0.1))  # type: ignore[arg-type]
    assert not blocked.any()


def test_tune_finds_nothing_to_miss_in_a_joint_whose_range_left_no_room_for_a_step() -> None:
    from robospec.tune.results import Targets
    from robospec.tune.search import failures

    unstepped = Response("nub", None, 0.0, None, 0.0, 0.0, no_room=True)
    # measured, the same numbers miss the settling target: never settled
    assert failures(unstepped, Targets(0.05, 0.5, 0.02)) == set()
    assert failures(replace(unstepped, no_room=False), Targets(0.05, 0.5, 0.02)) == {"settling"}
