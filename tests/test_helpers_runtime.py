"""The generated task-facing helpers, hooks and ``extends`` work in a real ManiSkill scene.

tests/test_tasks.py proves the panda's helpers equal ManiSkill's own; the zoo equivalence tests
do the same for the other robots. Here every helper section and escape hatch is loaded in
``Empty-v1`` on the CPU and checked against what it declares.
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
import torch
from conftest import POSITIVE_SPECS

import robospec
from robospec.maniskill.headless import make_empty_env
from robospec.pipeline import compile_spec

pytestmark = [
    pytest.mark.maniskill,
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
]


@pytest.fixture(scope="module")
def agents(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, type]]:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    paths = [POSITIVE_SPECS / "helpers_all.yaml", POSITIVE_SPECS / "hooks_extends.yaml"]
    registered = robospec.register(paths, cache_dir=tmp_path_factory.mktemp("cache"))
    try:
        yield registered
    finally:
        for uid in registered:
            REGISTERED_AGENTS.pop(uid, None)
        for name in [m for m in sys.modules if m.startswith("robospec_agents.")]:
            del sys.modules[name]


def test_every_helper_section_gives_what_it_declares(agents: dict[str, type]) -> None:
    env = make_empty_env("rs_test_helpers")
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        links = agent.robot.links_map
        assert agent.finger1_link is links["panda_leftfinger"]
        assert agent.tip_links == [links["panda_leftfinger_pad"], links["panda_rightfinger_pad"]]
        assert agent.tcp is links["panda_hand_tcp"]
        left, right = links["panda_leftfinger"].pose, links["panda_rightfinger"].pose
        assert torch.equal(agent.tcp_pos, (left.p + right.p) / 2)
        assert torch.equal(agent.tcp_pose.q, (left.q + right.q) / 2)
        assert agent.is_static().tolist() == [True]
        qvel = torch.zeros_like(agent.robot.get_qvel())
        qvel[0, 0] = -1.0  # signed comparison (absolute: false): a negative speed is "static"
        agent.robot.set_qvel(qvel)
        assert agent.is_static().tolist() == [True]
        qvel[0, 0] = 1.0
        agent.robot.set_qvel(qvel)
        assert agent.is_static().tolist() == [False]
        # ANYmal's upright test, reproduced as written upstream: arccos(2<q,1>^2 - 1) is NaN
        # for a root exactly upright in float32, so tilt the root a little (0.1 rad)
        import math

        import sapien

        agent.robot.set_pose(sapien.Pose(q=[math.cos(0.05), math.sin(0.05), 0, 0]))
        assert agent.is_standing().tolist() == [True]
        assert agent.is_standing(ground_height=0.5).tolist() == [False]
        agent.robot.set_pose(sapien.Pose(q=[math.cos(0.2), math.sin(0.2), 0, 0]))
        assert agent.is_standing().tolist() == [False]  # 0.4 rad > upright_within
        assert agent.is_fallen().tolist() == [False]
        assert agent.is_grasping(links["panda_hand"]).tolist() == [False]
        assert agent.tip_poses.shape == (1, 2, 7)
        assert agent.hand_pose.shape == (1, 7)
        assert agent.tip_velocities().shape == (1, 3, 2)  # a method, stacked on the last dim
        proprioception = agent.get_proprioception()
        assert list(proprioception)[-3:] == ["hand_pose", "tip_poses", "tip_velocities"]
        assert proprioception["tip_poses"].shape == (1, 14)
        assert proprioception["tip_velocities"].shape == (1, 6)
        gravity = {name: link._bodies[0].disable_gravity for name, link in links.items()}
        assert gravity.pop("panda_link0") is False and all(gravity.values())
        # the closed-loop drive lives on its child link's entity, x within ±0.1
        (drive,) = [
            c
            for c in links["panda_rightfinger"]._bodies[0].entity.components
            if type(c).__name__ == "PhysxDriveComponent"
        ]
        assert drive.parent is links["panda_leftfinger"]._bodies[0]
        assert tuple(drive.get_limit_x())[:2] == pytest.approx((-0.1, 0.1))
        assert drive.get_limit_y()[0] < -1e30  # an axis the limit does not name stays free
    finally:
        env.close()


def test_extends_subclasses_the_python_agent_and_overrides_only_declared_data(
    agents: dict[str, type],
) -> None:
    from mani_skill.agents.robots.panda.panda import Panda

    sys.path.insert(0, str(Path(__file__).parent))
    from hookmods import panda_hooks

    cls = agents["rs_test_extends"]
    assert issubclass(cls, Panda) and cls.__bases__ == (Panda,)
    assert cls.urdf_path == Panda.urdf_path and "urdf_path" not in vars(cls)
    assert list(cls.keyframes) == ["ready"]
    assert "_controller_configs" not in vars(cls)  # inherited
    assert cls.build_grasp_pose is Panda.build_grasp_pose  # a staticmethod stays static
    panda_hooks.CALLS.clear()
    env = make_empty_env("rs_test_extends")
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        assert panda_hooks.CALLS == [
            ("after_loading_articulation", "rs_test_extends"),
            ("after_init", "rs_test_extends"),
        ]
        assert agent.hooked is True
        assert agent.tcp is agent.robot.links_map["panda_hand_tcp"]  # Panda's own _after_init
        assert agent.gripper_opening().shape == (1,)
        assert [c.uid for c in agent._sensor_configs] == ["wrist"]
        # Panda's eleven control modes, inherited, default first
        assert len(agent.supported_control_modes) == 11
        assert agent.control_mode == "pd_joint_delta_pos"
    finally:
        env.close()


def test_a_robot_not_downloaded_yet_registers_with_its_download_ids(tmp_path: Path) -> None:
    from mani_skill.agents.registration import REGISTERED_AGENTS

    agents = robospec.register(POSITIVE_SPECS / "not_downloaded.yaml", cache_dir=tmp_path)
    try:
        cls = agents["rs_test_anymal"]
        assert REGISTERED_AGENTS["rs_test_anymal"].asset_download_ids == ["anymal_c"]
        assert cls.urdf_path.endswith("/robots/anymal_c/urdf/anymal.urdf")
        assert cls.fix_root_link is False and cls.disable_self_collisions is True
        assert cls.keyframes["standing"].qpos.tolist()[4] == 0.4
    finally:
        REGISTERED_AGENTS.pop("rs_test_anymal", None)


def test_extends_naming_a_value_that_is_no_agent_class_is_rs220_at_the_reference(
    tmp_path: Path,
) -> None:
    # checking that a base is an agent class imports ManiSkill's BaseAgent (seconds), so this
    # case lives here rather than in the example catalogue that the fast loop runs
    spec = tmp_path / "extends_not_agent.yaml"
    spec.write_text('robospec: 1\nuid: rs_test\nextends: "hookmods.panda_hooks:LIMIT"\n')
    found = compile_spec(spec).diagnostics
    assert [(d.code, d.location.line, d.location.column) for d in found] == [("RS220", 3, 10)]
    assert found[0].message == "'float' is not a ManiSkill agent class"
