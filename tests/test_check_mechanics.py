"""The arithmetic under ``robospec check`` and ``tune``, without simulation: what counts as past a
joint limit (both sides), which way a step goes (away from the nearer limit), when a robot can
stand (its centre of mass over the support polygon), how a reference's gains are read off an
implicit integrator's samples, and what RS506 says when it fails by never settling."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from robospec.diagnostics import Location, error
from robospec.physics.random_actions import limit_excess
from robospec.physics.statics import MARGIN, convex_hull, inside_distance, support
from robospec.physics.step_response import Response, _finding, step_direction
from robospec.tune.reference.fit import second_order


def test_a_joint_below_its_lower_limit_is_past_it_as_much_as_one_above_its_upper() -> None:
    lower, upper = np.array([-1.0, -1.0, -np.inf]), np.array([1.0, 1.0, np.inf])
    qpos = np.array([[-1.3, 0.5, -50.0], [-1.1, 1.2, 50.0]])  # two environments
    assert np.allclose(limit_excess(qpos, lower, upper), [0.3, 0.2, 0.0])
    assert np.allclose(limit_excess(np.zeros((1, 3)), lower, upper), 0.0)  # inside: 0


def test_a_step_goes_away_from_the_nearer_limit() -> None:
    lower, upper = np.array([-1.0, -1.0, 0.0]), np.array([1.0, 1.0, 2.0])
    start = np.array([0.9, -0.9, 1.0])  # near the upper limit, near the lower, in the middle
    assert step_direction(start, lower, upper).tolist() == [-1.0, 1.0, 1.0]


def test_a_robot_stands_only_with_its_centre_of_mass_inside_its_support() -> None:
    feet = [
        (f"foot{i}", (x, y, 0.0), 0.0)
        for i, (x, y) in enumerate([(0.2, 0.1), (0.2, -0.1), (-0.2, 0.1), (-0.2, -0.1)])
    ]
    centred = support(feet, np.array([0.0, 0.0, 0.5]))
    assert centred.stands and centred.inside == pytest.approx(0.1)
    leaning = support(feet, np.array([0.3, 0.0, 0.5]))
    assert not leaning.stands and leaning.inside == pytest.approx(-0.1)
    # two feet side by side make a segment: no polygon to balance over, however centred
    line = support(feet[:2], np.array([0.2, 0.0, 0.5]))
    assert not line.stands and line.links == ("foot0", "foot1")
    # on the edge (within the margin) is no stance either
    edge = support(feet, np.array([0.2 - MARGIN / 2, 0.0, 0.5]))
    assert not edge.stands
    assert support([], np.zeros(3)).touches is False


def test_a_foot_held_above_the_ground_bears_no_weight() -> None:
    # PhysX reports contacts within its contact offset: one foot on the ground, the other 2 cm
    # above it (a leg swung forward) is a robot on one foot, however wide the two would stand
    left = [("left", (x, y, 0.0), 0.0) for x, y in [(0.1, 0.05), (0.1, 0.1), (-0.1, 0.05)]]
    right = [("right", (x, y, 0.02), -0.02) for x, y in [(0.1, -0.1), (-0.1, -0.1)]]
    one_foot = support(left + right, np.array([0.0, 0.0, 0.5]))
    assert one_foot.links == ("left",) and not one_foot.stands
    assert support(left + [(n, p, -0.001) for n, p, _ in right], np.zeros(3)).stands


def test_a_foot_settling_within_a_centimetre_of_the_ground_bears_weight() -> None:
    # a robot settles by millimetres onto its feet as its drives take its weight (the
    # Minitaur's motor housings, 0 to 9 mm up, all bear it): 9 mm up counts, 11 mm does not
    left = [("left", (x, y, 0.0), 0.0) for x, y in [(0.1, 0.05), (0.1, 0.1), (-0.1, 0.05)]]
    right = [("right", (x, y, 0.009), -0.009) for x, y in [(0.1, -0.1), (-0.1, -0.1)]]
    settling = support(left + right, np.array([0.0, 0.0, 0.5]))
    assert settling.links == ("left", "right") and settling.stands
    lifted = [(n, (p[0], p[1], 0.011), -0.011) for n, p, _ in right]
    assert support(left + lifted, np.array([0.0, 0.0, 0.5])).links == ("left",)


def test_the_support_polygon_is_the_convex_hull_of_the_contacts() -> None:
    points = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [0.5, 0.0]])
    hull = convex_hull(points)
    assert len(hull) == 4 and {tuple(p) for p in hull} == {(0, 0), (1, 0), (1, 1), (0, 1)}
    assert inside_distance(hull, np.array([0.5, 0.25])) == pytest.approx(0.25)
    assert inside_distance(hull, np.array([2.0, 0.5])) == pytest.approx(-1.0)


@pytest.mark.parametrize(("a", "b"), [(400.0, 20.0), (900.0, 12.0), (100.0, 30.0)])
def test_the_reference_fit_reads_stiffness_and_damping_off_implicit_steps(
    a: float, b: float
) -> None:
    # PhysX's drives step implicitly: the new velocity multiplies the damping, and the spring
    # pulls on the new position; integrated here for q'' = a (u - q) - b q'
    dt = 0.01
    t = np.arange(400) * dt
    target = np.where((t // 0.5) % 2 == 0, 0.1, -0.1)
    q, v = np.zeros(t.size), 0.0
    for n in range(1, t.size):
        v = (v + dt * a * (target[n - 1] - q[n - 1])) / (1.0 + dt * b + dt * dt * a)
        q[n] = q[n - 1] + dt * v
    fitted_a, fitted_b = second_order(t, target, q, implicit=True)
    assert fitted_a == pytest.approx(a, rel=0.01)
    assert fitted_b == pytest.approx(b, rel=0.01)


def test_a_controller_that_never_settles_is_said_to_never_settle_not_to_overshoot() -> None:
    # RS506 because the joint never settles; its overshoot (20 %) is within max_overshoot (50 %):
    # the message must not call that an overshoot past the threshold
    settings = SimpleNamespace(
        max_rise_time=0.5,
        max_overshoot=0.5,
        max_steady_state_error=0.2,
        settling_band=0.1,
        duration=1.0,
    )
    checks = SimpleNamespace(step_response=SimpleNamespace(for_controller=lambda name: settings))
    run = SimpleNamespace(
        settings=checks,
        fail=lambda path, code, message, hint=None: error(Location("s.yaml"), code, message, hint),
    )
    sim = SimpleNamespace(mode="pd_joint_vel", backend=SimpleNamespace(gpu=True))
    group = SimpleNamespace(name="wheels", kind="velocity")
    ringing = Response("wheel", 0.05, 0.2, None, 0.05, 1.2)
    finding = _finding(run, sim, group, "wheels_vel", "wheels", [ringing])  # type: ignore[arg-type]
    (diagnostic,) = [d for d in finding.diagnostics if d.code == "RS506"]
    assert "never settled within 10% of a velocity step in 1 s" in diagnostic.message
    assert "overshot" not in diagnostic.message.split("(")[0]
    assert "its overshoot, 20%, is within max_overshoot 50%" in diagnostic.message


def test_an_error_sapien_reports_is_a_finding_at_the_element_naming_its_file() -> None:
    from conftest import PANDA_SPEC

    from robospec.maniskill.upstream_output import UpstreamMessage
    from robospec.physics.upstream_findings import findings
    from robospec.pipeline import compile_spec

    item = compile_spec(PANDA_SPEC)
    assert item.context is not None
    mesh = next(m for m in item.context.description.mesh_files if m.role == "collision")
    said = [
        UpstreamMessage("SAPIEN", "warning", "a warning is no finding", 1, None, None),
        UpstreamMessage(
            "SAPIEN", "error", "failed to build convex hull of <path>", 2, mesh.path, None
        ),
        UpstreamMessage("mani_skill", "critical", "something broke", 1, None, None),
    ]
    hull, other = findings(item.context, said)
    (diagnostic,) = hull.diagnostics
    assert diagnostic.code == "RS522" and diagnostic.is_error and hull.failed
    # located at the <collision> naming the file, in the description, named as validate names
    # the description ({maniskill_assets}/... here)
    assert diagnostic.location.file == item.context.description_file
    assert diagnostic.location.line == mesh.line
    assert "SAPIEN reported an error" in diagnostic.message and "(2 times)" in diagnostic.message
    assert mesh.path is not None and mesh.path in diagnostic.message
    # one it cannot trace: at the spec's description
    assert other.diagnostics[0].location == item.context.key(("description",))
