"""The task-facing members of every spec-built twin give the numbers of ManiSkill's own.

For each pair in TWINS both agents run the same random actions in ``Empty-v1`` on the CPU; after
the reset and after every step, each member the hand-written class defines beyond BaseAgent —
``tcp_pos``, ``tcp_pose``, ``is_static()``, ``is_standing()``, ``is_fallen()``, ``tip_poses``,
``palm_pose``, ``get_proprioception()``, ``is_grasping(...)`` — must be equal, and every link the
hand-written ``_after_init`` binds (``finger1_link``, ``tcp``, ...) must be bound to the same
link. A member the spec does not reproduce must be listed in NOT_REPRODUCED with the reason, so
a gap is visible, and an entry that no longer applies fails the test.
"""

from __future__ import annotations

from typing import Any

import pytest
import torch
from conftest import MANISKILL_VERSION
from maniskill_compare import (
    TWINS,
    assert_same_value,
    make_env,
    random_actions,
    registered_maniskill_specs,
    shared_cache_dir,
    upstream_start,
)

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
]

SEED = 11
STEPS = 8
# called with no arguments / read as properties
CALLED = ("is_static", "is_standing", "is_fallen", "get_proprioception")
READ = ("tcp_pos", "tcp_pose", "tip_poses", "palm_pose")
# members of hand-written agents that no spec section declares, and why
NOT_REPRODUCED: dict[str, dict[str, str]] = {}


@pytest.fixture(scope="module")
def agents(tmp_path_factory: pytest.TempPathFactory) -> Any:
    with registered_maniskill_specs(shared_cache_dir(tmp_path_factory)) as registered:
        yield registered


def _members(agent: Any) -> dict[str, Any]:
    from mani_skill.agents.base_agent import BaseAgent
    from mani_skill.utils.structs import Link

    values: dict[str, Any] = {}
    cls = type(agent)
    for name in (*CALLED, *READ):
        if getattr(cls, name, None) is getattr(BaseAgent, name, None):
            continue  # BaseAgent's own (or absent): nothing the agent declares
        value = getattr(agent, name)
        value = value() if name in CALLED else value
        values[name] = value.raw_pose if hasattr(value, "raw_pose") else value
    if getattr(cls, "is_grasping", None) is not BaseAgent.is_grasping:
        # no object in Empty-v1: the root link stands in, so the contact arithmetic runs
        values["is_grasping"] = agent.is_grasping(agent.robot.links[0])
    for name, value in vars(agent).items():
        if isinstance(value, Link):
            values["link:" + name] = value.name
        elif isinstance(value, list) and value and all(isinstance(v, Link) for v in value):
            values["link:" + name] = [v.name for v in value]
    return values


def _trace(uid: str, actions: Any, start: Any) -> list[dict[str, Any]]:
    """The members after the reset and every step, from ``start`` (ManiSkill's agent's joint
    positions after the reset: Empty-v1 resets no robot's joints, robospec's agent resets to
    its keyframe)."""
    env = make_env(uid)
    try:
        env.reset(seed=SEED)
        agent = env.unwrapped.agent
        agent.reset(start)
        trace = [_members(agent)]
        for action in actions:
            env.step(torch.from_numpy(action))
            trace.append(_members(agent))
        return trace
    finally:
        env.close()


@pytest.mark.parametrize("upstream", sorted(TWINS))
def test_task_facing_members_equal_the_hand_written_agent(upstream: str, agents: Any) -> None:
    ours = TWINS[upstream]
    env = make_env(upstream)
    try:
        actions = random_actions(env.action_space, SEED, STEPS)
        start = upstream_start(env, SEED)
    finally:
        env.close()
    theirs_trace, ours_trace = _trace(upstream, actions, start), _trace(ours, actions, start)
    expected_missing = NOT_REPRODUCED.get(upstream, {})
    missing = sorted(set(theirs_trace[0]) - set(ours_trace[0]))
    assert missing == sorted(expected_missing), (
        f"{upstream}: members the spec does not reproduce: {missing}; "
        f"NOT_REPRODUCED lists {sorted(expected_missing)}"
    )
    for step, (mine, upstream_values) in enumerate(zip(ours_trace, theirs_trace, strict=True)):
        for name, value in upstream_values.items():
            if name in expected_missing:
                continue
            assert_same_value(mine[name], value, f"{upstream}.{name} at step {step}")


def test_zoo_table_lists_every_registered_agent_and_every_spec() -> None:
    """docs/zoo.md has one row per ManiSkill agent; a 'bundled' row names its spec file."""
    import re
    from pathlib import Path

    from mani_skill.agents.registration import REGISTERED_AGENTS
    from maniskill_compare import MANISKILL_SPECS

    zoo = (Path(__file__).parent.parent / "docs" / "zoo.md").read_text(encoding="utf-8")
    versions_section = zoo.split("## ManiSkill versions", 1)[-1]
    rows = re.findall(
        r"^\| (\S+) \| (bundled|download) \| (\S+?(?:\.yaml`)?|import only) \|",
        zoo,
        re.MULTILINE,
    )
    table = {uid: (assets, spec) for uid, assets, spec in rows}
    if MANISKILL_VERSION == "nightly":  # the table is 3.0.1's; the nightly removed these
        removed = {"stompy"}
        assert removed <= set(table) and all(f"`{uid}`" in versions_section for uid in removed)
        table = {uid: row for uid, row in table.items() if uid not in removed}
    # ManiSkill's own agents: other tests in this process register robospec's robots too
    maniskill = {
        uid
        for uid, entry in REGISTERED_AGENTS.items()
        if entry.agent_cls.__module__.startswith("mani_skill.")
    }
    assert set(table) == maniskill
    specs = {p.stem for p in MANISKILL_SPECS.glob("*.yaml")}
    assert {uid for uid, (assets, _) in table.items() if assets == "bundled"} == specs
    assert set(TWINS) == specs
