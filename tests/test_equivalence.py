"""Each spec under specs/maniskill builds an agent equal to the ManiSkill class it reproduces.

For every pair (``panda``/``rs_panda``, ... : the 24 agents whose assets ship with ManiSkill, see
``TWINS``) both agents are loaded into ``Empty-v1`` on the CPU simulator and compared: control
modes, controller configs field by field, action spaces, keyframes, loader flags, urdf_config,
sensors, the loaded articulation (links, joints, limits, masses, collision groups, materials)
and finally a random-action rollout per control mode, which must give bit-identical qpos and
qvel.

Upstream's mistakes are reported, not hidden. A mode that is broken upstream is listed in
``KNOWN_UPSTREAM_PROBLEMS`` with the reason, and a test proves that it really is broken
upstream, so the entry has to go when ManiSkill fixes it. The same holds for upstream data that
robospec's validator rightly rejects and the spec therefore leaves out (a keyframe outside the
joint limits, a link rule that names no link): ``LEFT_OUT_DATA``.
"""

from __future__ import annotations

import copy
import dataclasses
import gc
import re
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
from conftest import FETCH_EE_MODES, MANISKILL_VERSION  # noqa: E402
from maniskill_compare import (  # noqa: E402
    LOADER_FLAGS,
    MANISKILL_SPECS,
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
    upstream_start,
)

SEED = 2024
STEPS = 50


@dataclass(frozen=True)
class UpstreamProblem:
    """A control mode of a hand-written ManiSkill agent that does not work.

    ``left_out``: the mode fails upstream, so the spec does not offer it; ``error`` is the
    exception class upstream raises (exactly that class), ``match`` a pattern its message
    matches, ``fails_at`` whether ``gym.make`` or the first step raises it.
    ``nan``: the mode runs, but qpos/qvel become NaN; the spec reproduces it faithfully, and the
    rollouts are compared with NaN equal to NaN. ``cause`` says why, and a test per cause
    proves it: ``infinite_bounds`` (a normalized action scaled to infinite joint limits) or
    ``urdf_mimic`` (URDF ``<mimic>`` joints that PhysX simulates alone, which robospec warns
    about as RS309).
    ``crash``: the spec offers the mode (it works in another ManiSkill), and this ManiSkill's
    controller code crashes building it, upstream's agent and the spec's alike.

    ``versions``: the ManiSkill versions that have the problem (``MANISKILL_VERSION``). Where the
    installed one does not, the test proves the fix instead: ``gone`` says how upstream fixed
    it there (``removed`` the mode, or ``fixed`` it so that it works).
    """

    kind: Literal["left_out", "nan", "crash"]
    reason: str
    error: type[Exception] | None = None
    match: str | None = None
    fails_at: Literal["make", "step"] = "step"
    cause: Literal["infinite_bounds", "urdf_mimic"] | None = None
    versions: frozenset[str] = frozenset({"3.0.1", "nightly"})  # _EVERY
    gone: Literal["removed", "fixed"] | None = None

    @property
    def here(self) -> bool:
        """Whether the installed ManiSkill has the problem."""
        return MANISKILL_VERSION in self.versions


@dataclass(frozen=True)
class UpstreamFix:
    """Controller fields a later ManiSkill corrected, which the spec writes as 3.0.1 has them
    (specs/maniskill reproduce 3.0.1): on ``version`` upstream's config equals the spec's with
    ``fields`` in place, and only so."""

    version: str
    fields: dict[str, Any]
    reason: str


_EE_ALIGN = (
    "sets frame='ee_align' on a PDEEPoseControllerConfig, a frame that "
    "PDEEPoseController.compute_target_pose does not know: neither of its 'p'/'q' branches "
    "runs and the first step raises UnboundLocalError. The spec leaves the mode out."
)
_FLOATING_GRIPPER_EE_POSE = (
    "FloatingPandaGripper's {mode} controller passes pos_lower=pos_upper=None (and "
    "frame='base', which no controller knows): the position bounds of the action space become "
    "NaN and gym.make raises ValueError. {extra}specs/maniskill/floating_panda_gripper.yaml "
    "leaves the mode out."
)
# what the exceptions say: the variable that neither branch sets (in words every Python from
# 3.10 on uses), and the action space's check
_EE_ALIGN_ERROR = "local variable 'p'"
_NAN_BOUNDS_ERROR = "No low value can be equal to `np.nan`"
_URDF_MIMIC = (
    "{robot}'s description has URDF <mimic> joints that no pd_joint_pos_mimic controller "
    "drives in this mode ({how}); SAPIEN makes them PhysX mimic joints, which go NaN on the CPU "
    "within a few steps. The spec reproduces the mode, and robospec warns RS309."
)
_INSPIRE = "upstream leaves them to a passive controller"
_XARM = "upstream drives them with a plain pd_joint_pos controller"


def _mimic_nan(robot: str, how: str) -> UpstreamProblem:
    return UpstreamProblem("nan", _URDF_MIMIC.format(robot=robot, how=how), cause="urdf_mimic")


_EVERY = frozenset({"3.0.1", "nightly"})
_ONLY_3_0_1 = frozenset({"3.0.1"})
_ROOT_LINK = (
    "Fetch's end-effector controllers set root_link_name; the nightly's "
    "PDEEPosController._initialize_joints reads self.root_link before assigning it, so "
    "building the mode raises AttributeError, for ManiSkill's Fetch and the spec's alike "
    "(robospec check reports it as RS516, upstream's code)."
)
KNOWN_UPSTREAM_PROBLEMS: dict[tuple[str, str], UpstreamProblem] = {
    ("fetch", "pd_ee_delta_pose_align"): UpstreamProblem(
        "left_out",
        f"Fetch {_EE_ALIGN}",
        error=UnboundLocalError,
        match=_EE_ALIGN_ERROR,
        versions=_ONLY_3_0_1,
        gone="removed",
    ),
    **{
        ("fetch", mode): UpstreamProblem(
            "crash",
            _ROOT_LINK,
            error=AttributeError,
            match="object has no attribute 'root_link'",
            fails_at="make",
            versions=frozenset({"nightly"}),
        )
        for mode in sorted(FETCH_EE_MODES)
    },
    ("fetch", "pd_joint_pos_vel"): UpstreamProblem(
        "nan",
        "The arm's PDJointPosVelControllerConfig has lower=upper=None (the joint limits) with "
        "normalize_action=True (panda's has False). upperarm_roll, forearm_roll and wrist_roll "
        "are continuous joints with infinite limits, so scaling an action from [-1, 1] to "
        "[-inf, inf] gives NaN targets: qpos and qvel are NaN from the first step on.",
        cause="infinite_bounds",
    ),
    ("panda_stick", "pd_ee_delta_pose_align"): UpstreamProblem(
        "left_out",
        f"PandaStick, like Fetch, {_EE_ALIGN}",
        error=UnboundLocalError,
        match=_EE_ALIGN_ERROR,
        versions=_ONLY_3_0_1,
        gone="removed",
    ),
    ("floating_panda_gripper", "pd_ee_pose"): UpstreamProblem(
        "left_out",
        _FLOATING_GRIPPER_EE_POSE.format(mode="pd_ee_pose", extra=""),
        error=ValueError,
        match=_NAN_BOUNDS_ERROR,
        fails_at="make",
        versions=_ONLY_3_0_1,
        gone="fixed",  # pos_lower=-inf, pos_upper=inf: tests/test_unbounded_limits.py
    ),
    ("floating_panda_gripper", "pd_ee_pose_quat"): UpstreamProblem(
        "left_out",
        _FLOATING_GRIPPER_EE_POSE.format(
            mode="pd_ee_pose_quat",
            extra="(It is a copy of pd_ee_pose with an extra attribute, rotation_convention, "
            "that no controller reads.) ",
        ),
        error=ValueError,
        match=_NAN_BOUNDS_ERROR,
        fails_at="make",
        versions=_ONLY_3_0_1,
        gone="removed",
    ),
    **{
        (robot, mode): _mimic_nan(robot, _INSPIRE)
        for robot in (
            "fixed_inspire_hand_left",
            "fixed_inspire_hand_right",
            "floating_inspire_hand_left",
            "floating_inspire_hand_right",
        )
        for mode in ("pd_joint_pos", "pd_joint_delta_pos")
    },
    **{
        ("xarm7_ability", mode): _mimic_nan("xarm7_ability", _XARM)
        for mode in (
            "pd_joint_delta_pos",
            "pd_joint_pos",
            "pd_ee_delta_pose",
            "pd_ee_target_delta_pose",
        )
    },
}


UPSTREAM_FIXES: dict[tuple[str, str], UpstreamFix] = {
    ("xarm7_ability", mode): UpstreamFix(
        "nightly",
        {
            "rot_lower": -0.1,
            "rot_upper": 0.1,
            "stiffness": 1e3,
            "damping": 1e2,
            "force_limit": 500,
            "friction": 0.0,
        },
        "3.0.1 passes the end-effector controller's arguments by position, one place off "
        "(stiffness 0.1, damping 1e3, ...; the spec reproduces them); the nightly names them",
    )
    for mode in ("pd_ee_delta_pose", "pd_ee_target_delta_pose")
}


def _fix_here(robot: str, mode: str | None) -> UpstreamFix | None:
    fix = UPSTREAM_FIXES.get((robot, mode or ""))
    return fix if fix is not None and fix.version == MANISKILL_VERSION else None


@dataclass(frozen=True)
class LeftOutData:
    """Upstream data that robospec's validator rightly rejects, so the spec leaves it out (and
    says so in a comment): a ``keyframe`` (``name`` is the keyframe) or a ``link_rule``
    (``name`` is the link name in upstream's urdf_config). A test proves each one wrong."""

    kind: Literal["keyframe", "link_rule"]
    name: str
    reason: str


_ALLEGRO_KEYFRAME = (
    "sets every joint to 0, outside joint_12.0's limits [0.263, 1.396] (RS304); the spec has "
    "no keyframe"
)
_THUMNB = (
    "'thumnb_L2' (for thumb_L2) names no link; ManiSkill ignores it silently, so the thumb "
    "keeps the default material, in the spec too (RS202 rejects the rule)"
)
LEFT_OUT_DATA: dict[str, list[LeftOutData]] = {
    **{
        robot: [
            LeftOutData("keyframe", "palm_side", _ALLEGRO_KEYFRAME),
            LeftOutData("keyframe", "palm_up", _ALLEGRO_KEYFRAME),
        ]
        for robot in ("allegro_hand_left", "allegro_hand_right", "allegro_hand_right_touch")
    },
    "unitree_g1_simplified_upper_body_right_arm": [
        LeftOutData(
            "keyframe",
            "standing",
            "has 24 joint positions for the 25 active joints (RS303); set_qpos refuses it",
        )
    ],
    "floating_ability_hand_right": [LeftOutData("link_rule", "thumnb_L2", _THUMNB)],
    "xarm7_ability": [LeftOutData("link_rule", "thumnb_L2", _THUMNB)],
}


def _left_out_data(robot: str, kind: str) -> set[str]:
    return {item.name for item in LEFT_OUT_DATA.get(robot, []) if item.kind == kind}


# The control modes each spec offers, in order; a test checks them against the agents, so this
# list cannot drift from upstream. It is spelled out here because parametrization happens at
# collection time, before any robot can be loaded.
_PANDA_MODES = [  # panda, panda_wristcam and panda_stick (less its broken _align mode)
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
]
_JOINT_POS = ["pd_joint_delta_pos", "pd_joint_pos", "pd_joint_target_delta_pos"]
_POS_FIRST = ["pd_joint_pos", "pd_joint_delta_pos"]
_DELTA_FIRST = ["pd_joint_delta_pos", "pd_joint_pos"]
MODES: dict[str, list[str]] = {
    "panda": _PANDA_MODES,
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
    "humanoid": _POS_FIRST,
    "allegro_hand_left": _JOINT_POS,
    "allegro_hand_right": _JOINT_POS,
    "allegro_hand_right_touch": _JOINT_POS,
    "dclaw": _JOINT_POS,
    "fixed_inspire_hand_left": _POS_FIRST,
    "fixed_inspire_hand_right": _POS_FIRST,
    "floating_ability_hand_right": ["pd_joint_pos"],
    "floating_inspire_hand_left": _POS_FIRST,
    "floating_inspire_hand_right": _POS_FIRST,
    "floating_panda_gripper": ["pd_joint_delta_pos", "pd_joint_pos", "pd_ee_delta_pose"],
    "koch-v1.1": _JOINT_POS,
    "panda_stick": _PANDA_MODES,
    "panda_wristcam": _PANDA_MODES,
    "so100": _JOINT_POS,
    "trifingerpro": [*_JOINT_POS, "pd_joint_vel", "pd_joint_pos_vel", "pd_joint_delta_pos_vel"],
    "unitree_g1": _POS_FIRST,
    "unitree_g1_simplified_legs": _POS_FIRST,
    "unitree_g1_simplified_upper_body": _DELTA_FIRST,
    "unitree_g1_simplified_upper_body_right_arm": _POS_FIRST,
    "unitree_g1_simplified_upper_body_with_head_camera": _DELTA_FIRST,
    "xarm7_ability": [
        "pd_joint_delta_pos",
        "pd_joint_pos",
        "pd_ee_delta_pose",
        "pd_ee_target_delta_pose",
    ],
}
# the cameras each spec-built agent has, in order (not two empty lists where there are some)
CAMERAS: dict[str, list[str]] = {
    "fetch": ["fetch_head", "fetch_hand"],
    "panda_wristcam": ["hand_camera"],
    "unitree_g1_simplified_upper_body_with_head_camera": ["head_camera"],
}
ROBOTS = list(TWINS)
CASES = [(robot, mode) for robot in ROBOTS for mode in MODES[robot]]


def _problems(kind: str) -> list[tuple[str, str]]:
    return [key for key, problem in KNOWN_UPSTREAM_PROBLEMS.items() if problem.kind == kind]


def _left_out(robot: str) -> set[str]:
    """The modes the spec leaves out because they fail upstream in 3.0.1 (or in every version)."""
    return {mode for r, mode in _problems("left_out") if r == robot}


def _missing_here(robot: str, upstream_modes: list[str]) -> set[str]:
    """The modes upstream offers here that the spec does not: those it leaves out, less the ones
    this ManiSkill removed."""
    return _left_out(robot) & set(upstream_modes)


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
    """The 24 spec-built agents (rs_panda, ...), registered for this module's tests only."""
    # Every gym.make and env.close runs gc.collect() (ManiSkill's _clear), which walks every
    # object alive in the test session: freezing the ones that exist now keeps the ~200
    # environments these tests build from paying for them again each time.
    gc.collect()
    gc.freeze()
    try:
        with registered_maniskill_specs(robospec_cache) as agents:
            yield agents
    finally:
        gc.unfreeze()


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
    problem = KNOWN_UPSTREAM_PROBLEMS.get((robot, mode))
    if problem is not None and problem.kind == "crash" and problem.here:
        pytest.skip(f"the mode crashes in this ManiSkill, upstream and ours alike: {problem}")
    with _twins(robot, mode) as pair:
        yield pair


def registered_agent_modes(robot: str) -> list[str]:
    """The control modes ManiSkill's own agent ``robot`` offers here."""
    env = make_env(robot, None)
    try:
        return list(env.unwrapped.agent._controller_configs)
    finally:
        env.close()


def _assert_steps_finite(uid: str, mode: str, steps: int = 5) -> None:
    env = make_env(uid, mode)
    try:
        env.reset(seed=SEED)
        for _ in range(steps):
            env.step(env.action_space.sample())
        qpos = env.unwrapped.agent.robot.get_qpos()
        assert torch.isfinite(qpos).all(), (uid, mode, qpos)
    finally:
        env.close()


# -- control modes ---------------------------------------------------------------------------------


def test_spec_built_agent_offers_upstream_control_modes_in_order_less_the_broken_ones(
    twins: Twins,
) -> None:
    upstream = list(twins.upstream_agent._controller_configs)
    ours = list(twins.our_agent._controller_configs)
    missing = _missing_here(twins.robot, upstream)
    assert ours == [mode for mode in upstream if mode not in missing]
    assert ours == MODES[twins.robot]
    # exactly the modes documented as broken are missing, and nothing else
    assert set(upstream) - set(ours) == missing


def test_exactly_the_documented_modes_are_left_out() -> None:
    left_out = {robot: _left_out(robot) for robot in ROBOTS if _left_out(robot)}
    assert left_out == {
        "fetch": {"pd_ee_delta_pose_align"},
        "panda_stick": {"pd_ee_delta_pose_align"},
        "floating_panda_gripper": {"pd_ee_pose", "pd_ee_pose_quat"},
    }


@pytest.mark.parametrize("case", _problems("left_out"), ids=_case_id)
def test_mode_left_out_of_the_spec_really_fails_upstream(
    case: tuple[str, str], registered: dict[str, type]
) -> None:
    robot, mode = case
    problem = KNOWN_UPSTREAM_PROBLEMS[case]
    assert problem.error is not None and problem.match is not None
    if not problem.here:  # this ManiSkill fixed it: prove the fix
        upstream_modes = registered_agent_modes(robot)
        if problem.gone == "removed":
            assert mode not in upstream_modes, problem.reason
        else:
            assert problem.gone == "fixed" and mode in upstream_modes, problem.reason
            _assert_steps_finite(robot, mode)
        with pytest.raises(AssertionError, match=f"{mode} not in supported modes"):
            make_env(TWINS[robot], mode)  # the spec still leaves it out, as 3.0.1 needs
        return
    if problem.fails_at == "make":
        # upstream offers the mode but cannot build it
        with pytest.raises(problem.error, match=re.escape(problem.match)) as failure:
            make_env(robot, mode)
    else:
        env = make_env(robot, mode)  # upstream accepts the mode ...
        try:
            env.reset(seed=SEED)
            # ... and fails on the first step
            with pytest.raises(problem.error, match=re.escape(problem.match)) as failure:
                env.step(env.action_space.sample())
        finally:
            env.close()
    assert type(failure.value) is problem.error, problem.reason  # that class, not a subclass
    # the spec-built agent refuses the mode up front instead
    with pytest.raises(AssertionError, match=f"{mode} not in supported modes"):
        make_env(TWINS[robot], mode)


@pytest.mark.parametrize("case", _problems("crash"), ids=_case_id)
def test_mode_that_crashes_in_this_maniskill_crashes_upstream_and_ours_alike(
    case: tuple[str, str], registered: dict[str, type]
) -> None:
    robot, mode = case
    problem = KNOWN_UPSTREAM_PROBLEMS[case]
    assert problem.error is not None and problem.match is not None
    for uid in (robot, TWINS[robot]):
        if not problem.here:  # a ManiSkill without the bug builds and steps the mode
            _assert_steps_finite(uid, mode)
            continue
        with pytest.raises(problem.error, match=re.escape(problem.match)):
            make_env(uid, mode)


# -- configuration ---------------------------------------------------------------------------------


def test_controller_configs_are_equal_field_by_field_in_every_mode(twins: Twins) -> None:
    left_out = _left_out(twins.robot)
    upstream = {
        mode: configs
        for mode, configs in twins.upstream_agent._controller_configs.items()
        if mode not in left_out
    }
    ours = dict(twins.our_agent._controller_configs)
    for mode in list(ours):
        fix = _fix_here(twins.robot, mode)
        if fix is not None:  # upstream's config is the spec's with the fix in place, only so
            arm = copy.deepcopy(ours[mode])
            for name, value in fix.fields.items():
                setattr(arm["arm"], name, value)
            ours[mode] = arm
    assert_same_controller_configs(ours, upstream)


def test_action_space_is_equal(twins_in_mode: Twins) -> None:
    ours, upstream = twins_in_mode.ours.action_space, twins_in_mode.upstream.action_space
    assert type(ours) is type(upstream)
    assert ours.shape == upstream.shape
    assert ours.dtype == upstream.dtype
    np.testing.assert_array_equal(ours.low, upstream.low)
    np.testing.assert_array_equal(ours.high, upstream.high)


def test_keyframes_are_equal(twins: Twins) -> None:
    left_out = _left_out_data(twins.robot, "keyframe")
    upstream = {
        name: _unbatched(keyframe, twins.upstream_agent.robot.dof)
        for name, keyframe in twins.upstream_agent.keyframes.items()
        if name not in left_out
    }
    assert_same_keyframes(twins.our_agent.keyframes, upstream)


def _unbatched(keyframe: Any, dof: torch.Tensor) -> Any:
    """The inspire hands write qpos as a batch of one, ``[[...]]``; ``set_qpos`` takes it as it
    takes the flat list a spec gives, so that one shape is compared as the flat one."""
    qpos = keyframe.qpos
    if qpos is not None and np.asarray(qpos).shape == (1, int(dof[0])):
        return dataclasses.replace(keyframe, qpos=np.asarray(qpos)[0])
    return keyframe


_WRONG_LENGTH_QPOS = "input vector size does not match articulation DOFs"


@pytest.mark.parametrize("robot", [r for r in ROBOTS if _left_out_data(r, "keyframe")], ids=str)
def test_keyframes_left_out_of_the_spec_are_invalid_upstream(
    robot: str, registered: dict[str, type]
) -> None:
    env = make_env(robot)  # upstream's robot only: the spec's keyframes are its class's
    try:
        upstream = env.unwrapped.agent
        low, high = upstream.robot.get_qlimits()[0].T.numpy()
        for name in _left_out_data(robot, "keyframe"):
            assert name not in registered[TWINS[robot]].keyframes
            qpos = np.asarray(upstream.keyframes[name].qpos, dtype=np.float64)
            if qpos.shape != low.shape:  # one value too few (or many): SAPIEN refuses it ...
                with pytest.raises(RuntimeError, match=_WRONG_LENGTH_QPOS) as refused:
                    upstream.robot.set_qpos(qpos)
                assert type(refused.value) is RuntimeError
            else:  # ... or outside the joint limits
                assert ((qpos < low - 1e-6) | (qpos > high + 1e-6)).any(), (robot, name)
    finally:
        env.close()


def test_loader_flags_and_description_file_are_equal(twins: Twins) -> None:
    ours, upstream = type(twins.our_agent), type(twins.upstream_agent)
    for flag in LOADER_FLAGS:
        assert_same_value(getattr(ours, flag), getattr(upstream, flag), flag)
    assert (ours.urdf_path is None) == (upstream.urdf_path is None)
    assert description_file(ours) == description_file(upstream)


def test_urdf_config_materials_and_link_settings_are_equal(twins: Twins) -> None:
    upstream = type(twins.upstream_agent).urdf_config
    left_out = _left_out_data(twins.robot, "link_rule")
    if left_out:
        upstream = {
            **upstream,
            "link": {k: v for k, v in upstream["link"].items() if k not in left_out},
        }
    assert_same_urdf_config(type(twins.our_agent).urdf_config, upstream)


@pytest.mark.parametrize("robot", [r for r in ROBOTS if _left_out_data(r, "link_rule")], ids=str)
def test_link_rules_left_out_of_the_spec_name_no_link_upstream(
    robot: str, registered: dict[str, type]
) -> None:
    env = make_env(robot)
    try:
        agent = env.unwrapped.agent
        links = {link.name for link in agent.robot.get_links()}
        for name in _left_out_data(robot, "link_rule"):
            assert name in type(agent).urdf_config["link"], name  # upstream configures it ...
            assert name not in links, name  # ... for a link the loaded robot does not have
    finally:
        env.close()


def test_sensor_configs_are_equal(twins: Twins) -> None:
    ours, upstream = twins.our_agent._sensor_configs, twins.upstream_agent._sensor_configs
    assert_same_sensor_configs(ours, upstream)
    assert [camera.uid for camera in ours] == CAMERAS.get(twins.robot, [])


# -- the loaded robot ------------------------------------------------------------------------------


def _collision_groups(agent: Any) -> dict[str, list[list[int]]]:
    return {
        link.name: [shape.get_collision_groups() for shape in link._objs[0].collision_shapes]
        for link in agent.robot.get_links()
    }


def _contact_settings(agent: Any) -> dict[str, list[tuple[float, ...]]]:
    """Per link and collision shape what urdf_config sets: friction, restitution, patch radii,
    density (so a link rule the spec leaves out must leave the loaded robot as upstream's)."""
    settings = {}
    for link in agent.robot.get_links():
        shapes = []
        for shape in link._objs[0].collision_shapes:
            material = shape.get_physical_material()
            shapes.append(
                (
                    material.static_friction,
                    material.dynamic_friction,
                    material.restitution,
                    shape.patch_radius,
                    shape.min_patch_radius,
                    shape.density,
                )
            )
        settings[link.name] = shapes
    return settings


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
    assert _contact_settings(twins.our_agent) == _contact_settings(twins.upstream_agent)
    our_tcp = getattr(twins.our_agent, "tcp", None)
    upstream_tcp = getattr(twins.upstream_agent, "tcp", None)
    assert getattr(our_tcp, "name", None) == getattr(upstream_tcp, "name", None)


# the maniskill specs that set collision bits: fetch's wheels and base ignore the ground, the
# G1 upper bodies' hand links ignore each other
WITH_COLLISION_RULES = {
    "fetch",
    "unitree_g1_simplified_upper_body",
    "unitree_g1_simplified_upper_body_right_arm",
    "unitree_g1_simplified_upper_body_with_head_camera",
}


def test_every_collision_rule_of_the_spec_sets_its_bit_on_both_loaded_robots(
    twins: Twins,
) -> None:
    from robospec.pipeline import compile_spec

    compiled = compile_spec(MANISKILL_SPECS / f"{twins.robot}.yaml").robot
    assert compiled is not None
    assert bool(compiled.collision_rules) == (twins.robot in WITH_COLLISION_RULES)
    loaded = {
        "ours": _collision_groups(twins.our_agent),
        "upstream": _collision_groups(twins.upstream_agent),
    }
    for rule in compiled.collision_rules:
        for link in rule.links:
            for side, groups in loaded.items():
                shapes = groups[link]
                assert shapes, (side, link)  # a link without collision shapes proves nothing
                bits = [shape[rule.group] >> rule.bit & 1 for shape in shapes]
                assert bits == [rule.value] * len(shapes), (side, link, rule)


# -- rollouts --------------------------------------------------------------------------------------


def _rollouts(twins: Twins) -> tuple[tuple[torch.Tensor, ...], tuple[torch.Tensor, ...]]:
    # both agents get the same actions: drawn from upstream's space, equal to ours (tested)
    actions = random_actions(twins.upstream.action_space, SEED, STEPS)
    start = upstream_start(twins.upstream, SEED)
    return rollout(twins.upstream, actions, SEED, start), rollout(twins.ours, actions, SEED, start)


def test_rollout_is_bit_identical(twins_in_mode: Twins) -> None:
    robot, mode = twins_in_mode.robot, twins_in_mode.mode
    fix = _fix_here(robot, mode)
    if fix is not None:
        pytest.skip(f"upstream fixed this mode's config here (compared field by field): {fix}")
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


def _nan_problems(cause: str) -> list[tuple[str, str]]:
    return [key for key, problem in KNOWN_UPSTREAM_PROBLEMS.items() if problem.cause == cause]


@pytest.mark.parametrize("case", _nan_problems("infinite_bounds"), ids=_case_id)
def test_nan_mode_from_infinite_bounds_is_nan_from_the_first_step_in_both(
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


_RS309_MODES = re.compile(r"in mode\(s\) ([\w, ]+):")


def test_rs309_warns_for_exactly_the_modes_that_go_nan_from_urdf_mimic_joints() -> None:
    """The inspire hands and xarm7_ability go NaN in every mode (test_rollout_is_bit_identical
    proves it, upstream and ours); robospec's RS309 warning (a URDF <mimic> joint no
    pd_joint_pos_mimic controller drives) names exactly those modes, and no other mode of any
    of the 24 robots: the warning is right about the cause, and panda's, fetch's and the
    ability hand's mimic controllers are what keeps their <mimic> joints stable."""
    from robospec.pipeline import compile_spec

    warned: set[tuple[str, str]] = set()
    for robot in ROBOTS:
        for diagnostic in compile_spec(MANISKILL_SPECS / f"{robot}.yaml").diagnostics:
            if diagnostic.code == "RS309":
                match = _RS309_MODES.search(diagnostic.message)
                assert match, diagnostic.message
                warned |= {(robot, mode) for mode in match.group(1).split(", ")}
    assert warned == set(_nan_problems("urdf_mimic"))


def test_every_known_upstream_problem_names_a_real_robot_and_mode() -> None:
    for (robot, mode), problem in KNOWN_UPSTREAM_PROBLEMS.items():
        assert robot in TWINS
        # the spec offers a mode that goes NaN or crashes in some ManiSkill, not one left out
        assert (mode in MODES[robot]) == (problem.kind in ("nan", "crash")), (robot, mode)
        assert (problem.cause is not None) == (problem.kind == "nan"), (robot, mode)
        raises = problem.kind in ("left_out", "crash")  # an exception, exactly named, proves it
        assert (problem.error is not None) == (problem.match is not None) == raises
        assert problem.versions <= _EVERY and problem.versions
        if problem.kind == "left_out" and problem.versions != _EVERY:
            assert problem.gone is not None, (robot, mode)  # how the other version fixed it
        assert problem.reason
    for robot, items in LEFT_OUT_DATA.items():
        assert robot in TWINS
        assert all(item.reason for item in items)
