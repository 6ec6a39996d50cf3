"""Each spec under specs/maniskill builds an agent equal to the ManiSkill class it reproduces.

For every pair (panda/rs_panda, fetch/rs_fetch, humanoid/rs_humanoid) both agents are loaded
into ``Empty-v1`` on the CPU simulator and compared: control modes, controller configs field by
field, action spaces, keyframes, loader flags, urdf_config, sensors, the loaded articulation
(links, joints, limits, masses, collision groups) and finally a 50-step random-action rollout
per control mode, which must give bit-identical qpos and qvel.

A mode that is broken upstream is reported, not hidden: it is listed in
``KNOWN_UPSTREAM_PROBLEMS`` with the reason, and a test proves that it really is broken
upstream, so the entry has to go when ManiSkill fixes it.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import pytest

pytestmark = [
    pytest.mark.maniskill,
    # ManiSkill 3.0.1 calls np.isnan on a torch tensor at every step: one warning per step
    pytest.mark.filterwarnings("ignore:__array_wrap__ must accept context:DeprecationWarning"),
]
pytest.importorskip("mani_skill")

import numpy as np  # noqa: E402
import torch  # noqa: E402
from maniskill_compare import (  # noqa: E402
    LOADER_FLAGS,
    TWINS,
    assert_same_controller_configs,
    assert_same_keyframes,
    assert_same_sensor_configs,
    assert_same_urdf_config,
    assert_same_value,
    description_file,
    make_env,
    random_actions,
    registered_maniskill_specs,
    rollout,
    shared_cache_dir,
)

SEED = 2024
STEPS = 50


@dataclass(frozen=True)
class UpstreamProblem:
    """A control mode of a hand-written ManiSkill agent that does not work.

    ``left_out``: the mode fails upstream, so the spec does not offer it; ``error`` names the
    exception upstream raises. ``nan``: the mode runs, but qpos/qvel become NaN; the spec
    reproduces it faithfully, and the rollouts are compared with NaN equal to NaN.
    """

    kind: Literal["left_out", "nan"]
    reason: str
    error: str | None = None


KNOWN_UPSTREAM_PROBLEMS: dict[tuple[str, str], UpstreamProblem] = {
    ("fetch", "pd_ee_delta_pose_align"): UpstreamProblem(
        "left_out",
        "Fetch sets frame='ee_align' on a PDEEPoseControllerConfig, a frame that "
        "PDEEPoseController.compute_target_pose does not know: neither of its 'p'/'q' branches "
        "runs and the first step raises UnboundLocalError. specs/maniskill/fetch.yaml leaves the "
        "mode out.",
        error="UnboundLocalError",
    ),
    ("fetch", "pd_joint_pos_vel"): UpstreamProblem(
        "nan",
        "The arm's PDJointPosVelControllerConfig has lower=upper=None (the joint limits) with "
        "normalize_action=True (panda's has False). upperarm_roll, forearm_roll and wrist_roll "
        "are continuous joints with infinite limits, so scaling an action from [-1, 1] to "
        "[-inf, inf] gives NaN targets: qpos and qvel are NaN from the first step on.",
    ),
}

# The control modes each spec offers, in order; a test checks them against the agents, so this
# list cannot drift from upstream. It is spelled out here because parametrization happens at
# collection time, before any robot can be loaded.
MODES: dict[str, list[str]] = {
    "panda": [
        "pd_joint_delta_pos",
        "pd_joint_pos",
        "pd_ee_delta_pos",
        "pd_ee_delta_pose",
        "pd_ee_pose",
        "pd_joint_target_delta_pos",
        "pd_ee_target_delta_pos",
        "pd_ee_target_delta_pose",
        "pd_joint_vel",
        "pd_joint_pos_vel",
        "pd_joint_delta_pos_vel",
    ],
    "fetch": [
        "pd_joint_delta_pos",
        "pd_joint_pos",
        "pd_ee_delta_pos",
        "pd_ee_delta_pose",
        "pd_joint_target_delta_pos",
        "pd_ee_target_delta_pos",
        "pd_ee_target_delta_pose",
        "pd_joint_vel",
        "pd_joint_pos_vel",
        "pd_joint_delta_pos_vel",
        "pd_joint_delta_pos_stiff_body",
    ],
    "humanoid": ["pd_joint_pos", "pd_joint_delta_pos"],
}
ROBOTS = list(TWINS)
CASES = [(robot, mode) for robot in ROBOTS for mode in MODES[robot]]


def _problems(kind: str) -> list[tuple[str, str]]:
    return [key for key, problem in KNOWN_UPSTREAM_PROBLEMS.items() if problem.kind == kind]


def _left_out(robot: str) -> set[str]:
    return {mode for r, mode in _problems("left_out") if r == robot}


def _case_id(case: tuple[str, str]) -> str:
    return "-".join(case)


@dataclass
class Twins:
    """ManiSkill's robot and the spec-built one, each in its own environment."""

    robot: str
    mode: str | None  # None: the default mode
    upstream: Any
    ours: Any

    @property
    def upstream_agent(self) -> Any:
        return self.upstream.unwrapped.agent

    @property
    def our_agent(self) -> Any:
        return self.ours.unwrapped.agent


@pytest.fixture(scope="session")
def robospec_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One cache for the session: the specs compile once."""
    return shared_cache_dir(tmp_path_factory)


@pytest.fixture(scope="module")
def registered(robospec_cache: Path) -> Iterator[dict[str, type]]:
    """rs_panda, rs_fetch and rs_humanoid, registered for this module's tests only."""
    with registered_maniskill_specs(robospec_cache) as agents:
        yield agents


@contextmanager
def _twins(robot: str, mode: str | None) -> Iterator[Twins]:
    upstream = make_env(robot, mode)
    try:
        ours = make_env(TWINS[robot], mode)
    except BaseException:
        upstream.close()
        raise
    try:
        yield Twins(robot, mode, upstream, ours)
    finally:
        upstream.close()
        ours.close()


@pytest.fixture(scope="module", params=ROBOTS)
def twins(request: pytest.FixtureRequest, registered: dict[str, type]) -> Iterator[Twins]:
    """Both agents of one pair, in their default control mode."""
    with _twins(request.param, None) as pair:
        yield pair


@pytest.fixture(scope="module", params=CASES, ids=_case_id)
def twins_in_mode(request: pytest.FixtureRequest, registered: dict[str, type]) -> Iterator[Twins]:
    """Both agents of one pair in one control mode; built once for all the tests of the mode
    (module scope makes pytest run those tests together and close the environments after)."""
    robot, mode = request.param
    with _twins(robot, mode) as pair:
        yield pair


# -- control modes ---------------------------------------------------------------------------------


def test_spec_built_agent_offers_upstream_control_modes_in_order_less_the_broken_ones(
    twins: Twins,
) -> None:
    upstream = list(twins.upstream_agent._controller_configs)
    ours = list(twins.our_agent._controller_configs)
    assert ours == [mode for mode in upstream if mode not in _left_out(twins.robot)]
    assert ours == MODES[twins.robot]
    # exactly the modes documented as broken are missing, and nothing else
    assert set(upstream) - set(ours) == _left_out(twins.robot)


def test_fetch_leaves_out_exactly_pd_ee_delta_pose_align() -> None:
    assert _left_out("fetch") == {"pd_ee_delta_pose_align"}
    assert _left_out("panda") == _left_out("humanoid") == set()


@pytest.mark.parametrize("case", _problems("left_out"), ids=_case_id)
def test_mode_left_out_of_the_spec_really_fails_upstream(
    case: tuple[str, str], registered: dict[str, type]
) -> None:
    robot, mode = case
    problem = KNOWN_UPSTREAM_PROBLEMS[case]
    env = make_env(robot, mode)  # upstream accepts the mode ...
    try:
        env.reset(seed=SEED)
        with pytest.raises(Exception) as failure:  # ... and fails on the first step
            env.step(env.action_space.sample())
        assert type(failure.value).__name__ == problem.error, problem.reason
    finally:
        env.close()
    # the spec-built agent refuses the mode up front instead
    with pytest.raises(AssertionError, match=f"{mode} not in supported modes"):
        make_env(TWINS[robot], mode)


# -- configuration ---------------------------------------------------------------------------------


def test_controller_configs_are_equal_field_by_field_in_every_mode(twins: Twins) -> None:
    left_out = _left_out(twins.robot)
    upstream = {
        mode: configs
        for mode, configs in twins.upstream_agent._controller_configs.items()
        if mode not in left_out
    }
    assert_same_controller_configs(twins.our_agent._controller_configs, upstream)


def test_action_space_is_equal(twins_in_mode: Twins) -> None:
    ours, upstream = twins_in_mode.ours.action_space, twins_in_mode.upstream.action_space
    assert type(ours) is type(upstream)
    assert ours.shape == upstream.shape
    assert ours.dtype == upstream.dtype
    np.testing.assert_array_equal(ours.low, upstream.low)
    np.testing.assert_array_equal(ours.high, upstream.high)


def test_keyframes_are_equal(twins: Twins) -> None:
    assert_same_keyframes(twins.our_agent.keyframes, twins.upstream_agent.keyframes)


def test_loader_flags_and_description_file_are_equal(twins: Twins) -> None:
    ours, upstream = type(twins.our_agent), type(twins.upstream_agent)
    for flag in LOADER_FLAGS:
        assert_same_value(getattr(ours, flag), getattr(upstream, flag), flag)
    assert (ours.urdf_path is None) == (upstream.urdf_path is None)
    assert description_file(ours) == description_file(upstream)


def test_urdf_config_materials_and_link_settings_are_equal(twins: Twins) -> None:
    assert_same_urdf_config(
        type(twins.our_agent).urdf_config, type(twins.upstream_agent).urdf_config
    )


def test_sensor_configs_are_equal(twins: Twins) -> None:
    ours, upstream = twins.our_agent._sensor_configs, twins.upstream_agent._sensor_configs
    assert_same_sensor_configs(ours, upstream)
    # not two empty lists where there are cameras to compare
    expected = {"fetch": ["fetch_head", "fetch_hand"], "panda": [], "humanoid": []}
    assert [camera.uid for camera in ours] == expected[twins.robot]


# -- the loaded robot ------------------------------------------------------------------------------


def _collision_groups(agent: Any) -> dict[str, list[list[int]]]:
    return {
        link.name: [shape.get_collision_groups() for shape in link._objs[0].collision_shapes]
        for link in agent.robot.get_links()
    }


def test_loaded_articulations_are_identical(twins: Twins) -> None:
    ours, upstream = twins.our_agent.robot, twins.upstream_agent.robot
    assert [link.name for link in ours.get_links()] == [link.name for link in upstream.get_links()]
    assert [j.name for j in ours.get_active_joints()] == [
        j.name for j in upstream.get_active_joints()
    ]
    assert torch.equal(ours.get_qlimits(), upstream.get_qlimits())
    for a, b in zip(ours.get_links(), upstream.get_links(), strict=True):
        assert a._objs[0].mass == b._objs[0].mass, a.name
        assert np.array_equal(a._objs[0].inertia, b._objs[0].inertia), a.name
    assert _collision_groups(twins.our_agent) == _collision_groups(twins.upstream_agent)
    our_tcp = getattr(twins.our_agent, "tcp", None)
    upstream_tcp = getattr(twins.upstream_agent, "tcp", None)
    assert getattr(our_tcp, "name", None) == getattr(upstream_tcp, "name", None)


def test_fetch_wheels_and_base_have_upstream_collision_bits(registered: dict[str, type]) -> None:
    with _twins("fetch", None) as twins:
        ours = _collision_groups(twins.our_agent)
        upstream = _collision_groups(twins.upstream_agent)
        for link in ("l_wheel_link", "r_wheel_link", "base_link"):
            assert ours[link], link
            assert ours[link] == upstream[link], link
        bit = {"l_wheel_link": 30, "r_wheel_link": 30, "base_link": 31}
        for link, index in bit.items():
            assert all(groups[2] >> index & 1 for groups in ours[link]), (link, ours[link])


# -- rollouts --------------------------------------------------------------------------------------


def _rollouts(twins: Twins) -> tuple[tuple[torch.Tensor, ...], tuple[torch.Tensor, ...]]:
    # both agents get the same actions: drawn from upstream's space, equal to ours (tested)
    actions = random_actions(twins.upstream.action_space, SEED, STEPS)
    return rollout(twins.upstream, actions, SEED), rollout(twins.ours, actions, SEED)


def test_rollout_is_bit_identical(twins_in_mode: Twins) -> None:
    robot, mode = twins_in_mode.robot, twins_in_mode.mode
    (qpos_up, qvel_up), (qpos, qvel) = _rollouts(twins_in_mode)
    assert qpos.shape == qpos_up.shape == (STEPS + 1, 1, qpos.shape[-1])
    problem = KNOWN_UPSTREAM_PROBLEMS.get((robot, mode))
    if problem is not None and problem.kind == "nan":
        assert torch.isnan(qpos_up).any(), f"upstream no longer NaN: drop the entry? {problem}"
        torch.testing.assert_close(qpos, qpos_up, rtol=0, atol=0, equal_nan=True)
        torch.testing.assert_close(qvel, qvel_up, rtol=0, atol=0, equal_nan=True)
        return
    assert not torch.isnan(qpos_up).any() and not torch.isnan(qvel_up).any()
    assert torch.equal(qpos, qpos_up), _first_difference(qpos, qpos_up)
    assert torch.equal(qvel, qvel_up), _first_difference(qvel, qvel_up)
    assert not torch.equal(qpos_up[0], qpos_up[-1]), "the robot did not move: a vacuous check"


def _first_difference(ours: torch.Tensor, upstream: torch.Tensor) -> str:
    step = int((ours != upstream).flatten(1).any(1).nonzero()[0])
    return f"first differs after step {step}: {ours[step]} != {upstream[step]}"


@pytest.mark.parametrize("case", _problems("nan"), ids=_case_id)
def test_nan_mode_is_nan_upstream_and_in_the_spec_built_twin(
    case: tuple[str, str], registered: dict[str, type]
) -> None:
    """fetch pd_joint_pos_vel: NaN from the first step, upstream and ours alike, for the
    documented reason (infinite joint limits scaled by a normalized action)."""
    robot, mode = case
    with _twins(robot, mode) as twins:
        (qpos_up, qvel_up), (qpos, qvel) = _rollouts(twins)
        for q, v in ((qpos_up, qvel_up), (qpos, qvel)):
            assert not torch.isnan(q[0]).any()  # fine after the reset ...
            assert torch.isnan(q[1:]).all() and torch.isnan(v[1:]).all()  # ... NaN after a step
        for agent in (twins.upstream_agent, twins.our_agent):
            arm = agent.controller.controllers["arm"]
            assert arm.config.normalize_action
            assert torch.isinf(arm.action_space_low).any()
            assert torch.isinf(arm.action_space_high).any()


def test_every_known_upstream_problem_names_a_real_robot_and_mode() -> None:
    for (robot, mode), problem in KNOWN_UPSTREAM_PROBLEMS.items():
        assert robot in TWINS
        assert (mode in MODES[robot]) == (problem.kind == "nan"), (robot, mode)
        assert problem.reason
