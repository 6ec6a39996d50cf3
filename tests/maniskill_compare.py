"""Shared helpers for tests that compare ManiSkill agent classes with each other.

Used by test_equivalence.py (spec-built agent vs ManiSkill's hand-written one) and
test_build_matches_register.py (`robospec build` package vs `robospec.register`). It imports
numpy and torch: only modules marked ``maniskill`` import it (conftest.py).

Every ``assert_same_*`` function raises AssertionError naming the first difference by its path
(``pd_ee_pose.arm.rot_lower``), so a failure says what differs without a debugger.
"""

from __future__ import annotations

import dataclasses
import importlib
import os
import sys
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import torch
from conftest import MANISKILL_SPECS

# ManiSkill's uid -> the uid of the spec that reproduces it: every agent ManiSkill registers
# whose assets ship in the pip package. The spec of ``uid`` is specs/maniskill/<uid>.yaml.
BUNDLED_AGENTS = (
    "panda",
    "fetch",
    "humanoid",
    "allegro_hand_left",
    "allegro_hand_right",
    "allegro_hand_right_touch",
    "dclaw",
    "fixed_inspire_hand_left",
    "fixed_inspire_hand_right",
    "floating_ability_hand_right",
    "floating_inspire_hand_left",
    "floating_inspire_hand_right",
    "floating_panda_gripper",
    "koch-v1.1",
    "panda_stick",
    "panda_wristcam",
    "so100",
    "trifingerpro",
    "unitree_g1",
    "unitree_g1_simplified_legs",
    "unitree_g1_simplified_upper_body",
    "unitree_g1_simplified_upper_body_right_arm",
    "unitree_g1_simplified_upper_body_with_head_camera",
    "xarm7_ability",
)
TWINS: dict[str, str] = {uid: f"rs_{uid}" for uid in BUNDLED_AGENTS}

LOADER_FLAGS = ("fix_root_link", "load_multiple_collisions", "disable_self_collisions")
CAMERA_FIELDS = ("uid", "width", "height", "fov", "near", "far", "intrinsic", "shader_pack")


_cache_dirs: list[Path] = []


def shared_cache_dir(tmp_path_factory: Any) -> Path:
    """One robospec cache folder for every test module of the session (each module's
    session-scoped fixture is its own fixture; this makes them agree), so the specs compile
    once."""
    if not _cache_dirs:
        _cache_dirs.append(tmp_path_factory.mktemp("robospec-cache"))
    return _cache_dirs[0]


@contextmanager
def registered_maniskill_specs(cache_dir: Path) -> Iterator[dict[str, type]]:
    """``robospec.register`` every spec under specs/maniskill; unregister them on exit.

    Yields ``{uid: class}``. The specs compile once per ``cache_dir``; later calls with the same
    folder are warm cache hits. On exit the uids this block added leave ManiSkill's registry
    and their modules leave ``sys.modules``, so tests elsewhere see ManiSkill's registry as they
    would without these tests, and a later block registers afresh.
    """
    import robospec

    registry = importlib.import_module("mani_skill.agents.registration").REGISTERED_AGENTS
    data_groups = importlib.import_module("mani_skill.utils.assets").DATA_GROUPS
    before = set(registry)
    agents = robospec.register(str(MANISKILL_SPECS), cache_dir=cache_dir)
    assert sorted(agents) == sorted(TWINS.values()), sorted(agents)
    try:
        yield agents
    finally:
        for uid, cls in agents.items():
            if uid not in before and uid in registry and registry[uid].agent_cls is cls:
                del registry[uid]
                data_groups.pop(uid, None)
                sys.modules.pop(cls.__module__, None)


def make_env(uid: str, control_mode: str | None = None) -> Any:
    """``Empty-v1`` with robot ``uid`` on the CPU simulator, loadable without a render device."""
    from robospec.maniskill.headless import make_empty_env

    return make_empty_env(uid, control_mode)


def random_actions(action_space: Any, seed: int, steps: int) -> np.ndarray:
    """``steps`` actions drawn uniformly from ``action_space``, as float32.

    A dimension without a bound (fetch's continuous arm joints in pd_joint_pos have infinite
    joint limits, hence infinite action bounds) cannot be sampled uniformly; there it is drawn
    from [-pi, pi] clipped to the bound that does exist.
    """
    low = np.maximum(np.asarray(action_space.low, dtype=np.float64), -np.pi)
    high = np.minimum(np.asarray(action_space.high, dtype=np.float64), np.pi)
    rng = np.random.default_rng(seed)
    return rng.uniform(low, high, size=(steps, *low.shape)).astype(np.float32)


def upstream_start(env: Any, seed: int) -> torch.Tensor:
    """The joint positions ManiSkill's agent has after ``env.reset(seed)``: where the task's
    scene puts it, in ``Empty-v1`` where SAPIEN built it."""
    env.reset(seed=seed)
    return env.unwrapped.agent.robot.get_qpos().clone()


def rollout(
    env: Any, actions: np.ndarray, seed: int, start: torch.Tensor | None = None
) -> tuple[torch.Tensor, torch.Tensor]:
    """Reset with ``seed``, step through ``actions``; qpos and qvel after the reset and after
    every step, stacked: two tensors of shape (len(actions) + 1, num_envs, dof).

    ``start``: the joint positions both twins start from. ``Empty-v1`` resets no robot's
    joints, so ManiSkill's agent starts where SAPIEN built it and robospec's at its reset
    keyframe; the comparison of their controllers starts both where ManiSkill's starts
    (``upstream_start``)."""
    env.reset(seed=seed)
    agent = env.unwrapped.agent
    if start is not None:
        agent.reset(start)
        agent.controller.reset()
    robot = agent.robot
    qpos = [robot.get_qpos().clone()]
    qvel = [robot.get_qvel().clone()]
    for action in actions:
        env.step(torch.from_numpy(action))
        qpos.append(robot.get_qpos().clone())
        qvel.append(robot.get_qvel().clone())
    return torch.stack(qpos), torch.stack(qvel)


# -- values ----------------------------------------------------------------------------------------


def _is_number_like(value: Any) -> bool:
    if isinstance(value, (bool, np.bool_, str)):
        return False
    if isinstance(value, (int, float, np.number, np.ndarray, torch.Tensor)):
        return True
    if isinstance(value, (list, tuple)):
        return all(_is_number_like(item) for item in value)
    return False


def _is_pose(value: Any) -> bool:
    """A ``sapien.Pose`` or a ManiSkill ``Pose``: equal when p and q are (``==`` is identity)."""
    import sapien
    from mani_skill.utils.structs.pose import Pose

    return isinstance(value, (sapien.Pose, Pose))


def assert_same_value(ours: Any, theirs: Any, where: str) -> None:
    """Equal values: None only with None, strings and bools exactly, mappings key by key in
    the same order, numbers and number sequences by ``np.asarray`` equality (shape included:
    a scalar 0.1 is not [0.1, 0.1]), other sequences item by item."""
    if ours is None or theirs is None:
        assert ours is None and theirs is None, f"{where}: {ours!r} != {theirs!r}"
    elif isinstance(ours, Mapping) or isinstance(theirs, Mapping):
        assert isinstance(ours, Mapping) and isinstance(theirs, Mapping), (
            f"{where}: {ours!r} != {theirs!r}"
        )
        assert list(ours) == list(theirs), f"{where}: keys {list(ours)} != {list(theirs)}"
        for key in ours:
            assert_same_value(ours[key], theirs[key], f"{where}.{key}")
    elif isinstance(ours, (bool, np.bool_, str)) or isinstance(theirs, (bool, np.bool_, str)):
        assert type(ours) is type(theirs) and ours == theirs, f"{where}: {ours!r} != {theirs!r}"
    elif _is_number_like(ours) and _is_number_like(theirs):
        a = ours.cpu().numpy() if isinstance(ours, torch.Tensor) else np.asarray(ours)
        b = theirs.cpu().numpy() if isinstance(theirs, torch.Tensor) else np.asarray(theirs)
        assert a.shape == b.shape and np.array_equal(a, b), f"{where}: {ours!r} != {theirs!r}"
    elif isinstance(ours, (list, tuple)) and isinstance(theirs, (list, tuple)):
        assert len(ours) == len(theirs), f"{where}: {ours!r} != {theirs!r}"
        for index, (a, b) in enumerate(zip(ours, theirs, strict=True)):
            assert_same_value(a, b, f"{where}[{index}]")
    elif _is_pose(ours) or _is_pose(theirs):
        assert type(ours) is type(theirs), f"{where}: {ours!r} != {theirs!r}"
        assert_same_value(ours.p, theirs.p, f"{where}.p")
        assert_same_value(ours.q, theirs.q, f"{where}.q")
    elif dataclasses.is_dataclass(ours) and not isinstance(ours, type):
        assert_same_dataclass(ours, theirs, where)
    else:
        assert ours == theirs, f"{where}: {ours!r} != {theirs!r}"


def assert_same_dataclass(ours: Any, theirs: Any, where: str) -> None:
    """The same dataclass, field by field (``dataclasses.fields``)."""
    assert type(ours) is type(theirs), f"{where}: {type(ours).__name__} != {type(theirs).__name__}"
    for field in dataclasses.fields(ours):
        assert_same_value(
            getattr(ours, field.name), getattr(theirs, field.name), f"{where}.{field.name}"
        )


def assert_same_controller_configs(ours: Mapping[str, Any], theirs: Mapping[str, Any]) -> None:
    """``_controller_configs`` of two agents: the same modes in the same order, each with the
    same controllers in the same order (the order makes the action vector), each of the same
    config class with equal fields; non-config entries (``balance_passive_force``) equal."""
    assert list(ours) == list(theirs), f"modes {list(ours)} != {list(theirs)}"
    for mode in ours:
        assert_same_value(ours[mode], theirs[mode], mode)


def assert_same_keyframes(ours: Mapping[str, Any], theirs: Mapping[str, Any]) -> None:
    assert list(ours) == list(theirs), f"keyframes {list(ours)} != {list(theirs)}"
    for name in ours:
        a, b = ours[name], theirs[name]
        assert_same_value(a.pose, b.pose, f"{name}.pose")
        assert_same_value(a.qpos, b.qpos, f"{name}.qpos")
        assert_same_value(a.qvel, b.qvel, f"{name}.qvel")


def assert_same_urdf_config(ours: Any, theirs: Any) -> None:
    """``urdf_config``: an empty config and no config load the same robot.

    The order of the ``_materials`` and ``link`` entries is not compared: ManiSkill only looks
    them up by name (``sapien_utils.parse_urdf_config`` and ``apply_urdf_config``), and robospec
    writes links in the description's order where a hand-written agent may use any.
    """
    assert_same_value(_by_name(ours or None), _by_name(theirs or None), "urdf_config")


def _by_name(config: Mapping[str, Any] | None) -> dict[str, Any] | None:
    if config is None:
        return None
    return {
        key: dict(sorted(value.items())) if key in ("_materials", "link") else value
        for key, value in config.items()
    }


def assert_same_sensor_configs(ours: list[Any], theirs: list[Any]) -> None:
    assert [type(c) for c in ours] == [type(c) for c in theirs], (ours, theirs)
    for a, b in zip(ours, theirs, strict=True):
        where = f"sensor {getattr(b, 'uid', '?')}"
        for name in CAMERA_FIELDS:
            if hasattr(a, name) or hasattr(b, name):
                assert_same_value(getattr(a, name), getattr(b, name), f"{where}.{name}")
        assert_same_value(mount_name(a), mount_name(b), f"{where}.mount")
        assert_same_value(a.pose, b.pose, f"{where}.pose")


def mount_name(camera: Any) -> str | None:
    """The name of the link a camera config mounts on. A config names it either as
    ``entity_uid`` (robospec, fetch) or by passing the link itself as ``mount`` (panda_wristcam,
    the G1 head camera); ``Camera.__init__`` mounts on ``mount`` when it is given and otherwise
    looks ``entity_uid`` up among the robot's links, so both reach the same link."""
    if camera.mount is not None:
        assert camera.entity_uid is None, camera
        return str(camera.mount.name)
    return camera.entity_uid


def description_file(agent_cls: type) -> str:
    """The absolute path of the URDF or MJCF file the class loads (as ManiSkill resolves it)."""
    from mani_skill import format_path

    path = agent_cls.urdf_path if agent_cls.urdf_path is not None else agent_cls.mjcf_path
    assert path is not None, agent_cls
    return os.path.realpath(format_path(str(path)))
