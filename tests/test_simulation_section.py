"""The spec's ``simulation`` section (what ``robospec optimize --profile fast`` writes): checked by
the model, emitted as code that sets the robot's own contact offsets after loading and as the
sim config a built package's ``sim_config_for(uid)`` hands to ``gym.make``, shown on the robot
card; and, in ManiSkill, the offsets on the shapes and the sim config taken."""

from __future__ import annotations

import ast
import copy
from pathlib import Path
from typing import ClassVar

import pytest
from conftest import PANDA_SPEC, ROOT, contact_offsets

from robospec.authoring.commands import run_doc
from robospec.emit.generate import emit_module
from robospec.emit.package import emit_package_init
from robospec.pipeline import compile_spec

FAST = """
simulation:
  profile: fast
  category: manipulation
  contact_offset: 0.002
  solver_position_iterations: 15
  solver_velocity_iterations: 1
"""


def _spec(tmp_path: Path, section: str = FAST, uid: str = "rs_panda_fast") -> Path:
    text = PANDA_SPEC.read_text(encoding="utf-8").replace("uid: rs_panda", f"uid: {uid}", 1)
    # the spec's relative paths stay right: it sits where the Panda's does, by name only
    text = text.replace("../../schemas/", f"{ROOT.as_posix()}/schemas/")
    spec = tmp_path / "panda_fast.yaml"
    spec.write_text(text + section, encoding="utf-8")
    return spec


def _errors(spec: Path) -> list[tuple[str, int]]:
    compiled = compile_spec(spec)
    return [(d.code, d.location.line) for d in compiled.diagnostics if d.is_error]


def test_the_section_compiles_and_resolves_with_its_sim_config(tmp_path: Path) -> None:
    compiled = compile_spec(_spec(tmp_path))
    assert compiled.ok and compiled.robot is not None
    simulation = compiled.robot.simulation
    assert simulation.profile == "fast" and simulation.contact_offset == 0.002
    assert simulation.sim_config == {
        "scene_config": {"solver_position_iterations": 15, "solver_velocity_iterations": 1}
    }
    plain = compile_spec(PANDA_SPEC).robot
    assert plain is not None and plain.simulation.empty and plain.simulation.sim_config == {}


@pytest.mark.parametrize(
    "bad",
    [
        "contact_offset: 0",
        "contact_offset: -0.01",
        "solver_position_iterations: 0",
        "solver_velocity_iterations: 256",
        "profile: slow",
        "category: flying",
        "contact_ofset: 0.002",
    ],
)
def test_bad_values_are_located_errors(tmp_path: Path, bad: str) -> None:
    spec = _spec(tmp_path, f"\nsimulation:\n  {bad}\n")
    line = spec.read_text(encoding="utf-8").splitlines().index(f"  {bad}") + 1
    errors = _errors(spec)
    assert errors and all(code.startswith("RS1") for code, _ in errors), errors
    assert line in {at for _, at in errors}, errors


def test_the_agent_sets_the_offset_on_its_shapes_after_loading(tmp_path: Path) -> None:
    compiled = compile_spec(_spec(tmp_path))
    assert compiled.robot is not None
    source = emit_module(compiled.robot, tmp_path)
    tree = ast.parse(source)
    (agent,) = [node for node in tree.body if isinstance(node, ast.ClassDef)]
    methods = {node.name: node for node in agent.body if isinstance(node, ast.FunctionDef)}
    loading = ast.unparse(methods["_after_loading_articulation"])
    assert "for link in self.robot.links" in loading
    assert "shape.set_contact_offset(0.002)" in loading
    attributes = {
        node.targets[0].id: ast.literal_eval(node.value)
        for node in agent.body
        if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name)
        if node.targets[0].id == "recommended_sim_config"
    }
    assert attributes == {"recommended_sim_config": compiled.robot.simulation.sim_config}
    # without the section: neither
    plain = compile_spec(PANDA_SPEC).robot
    assert plain is not None
    plain_source = emit_module(plain, tmp_path)
    assert "set_contact_offset" not in plain_source
    assert "recommended_sim_config" not in plain_source


def test_the_package_hands_each_robot_its_sim_config_and_a_copy() -> None:
    source = emit_package_init([("fast", "rs_fast", "Fast"), ("plain", "rs_plain", "Plain")])
    tree = ast.parse(source)
    (function,) = [n for n in tree.body if isinstance(n, ast.FunctionDef)]
    assert function.name == "sim_config_for"

    class Fast:
        recommended_sim_config: ClassVar[dict[str, dict[str, int]]] = {
            "scene_config": {"solver_position_iterations": 4}
        }

    class Plain:
        pass

    namespace = {"AGENTS": {"rs_fast": Fast, "rs_plain": Plain}, "deepcopy": copy.deepcopy}
    exec(compile(ast.Module([function], []), "<init>", "exec"), namespace)
    sim_config_for = namespace["sim_config_for"]
    given = sim_config_for("rs_fast")
    assert given == {"scene_config": {"solver_position_iterations": 4}}
    given["scene_config"]["solver_position_iterations"] = 99  # the caller's copy
    assert Fast.recommended_sim_config["scene_config"]["solver_position_iterations"] == 4
    assert sim_config_for("rs_plain") == {}
    with pytest.raises(KeyError):
        sim_config_for("rs_unknown")


def test_the_card_shows_the_section_only_when_the_spec_has_one(tmp_path: Path) -> None:
    out = tmp_path / "card.md"
    assert not run_doc(_spec(tmp_path), out).write().failed
    text = out.read_text(encoding="utf-8")
    assert "## Simulation" in text and "--profile fast" in text
    assert "| contact offset of the robot's shapes | 0.002 m" in text
    assert "| solver position iterations | 15 |" in text
    assert not run_doc(PANDA_SPEC, tmp_path / "plain.md").write().failed
    assert "## Simulation" not in (tmp_path / "plain.md").read_text(encoding="utf-8")


@pytest.mark.maniskill
@pytest.mark.filterwarnings("ignore::UserWarning")
def test_in_maniskill_the_robots_shapes_carry_the_offset_and_gym_make_takes_the_config(
    tmp_path: Path,
) -> None:
    import gymnasium as gym

    import robospec
    from robospec.maniskill.headless import headless_loading

    (uid,) = robospec.register(str(_spec(tmp_path, uid="rs_panda_sim_section")))
    config = robospec.sim_config_for(uid)
    config["scene_config"]["solver_position_iterations"] = 17  # a value unlike the default
    with headless_loading():
        env = gym.make(
            "Empty-v1",
            robot_uids=uid,
            obs_mode="state",
            sim_backend="physx_cpu",
            render_backend="none",
            sim_config=config,
        )
    try:
        base = env.unwrapped
        robot = set(contact_offsets(base.agent.robot.links))
        ground = set(contact_offsets([base.ground]))
        assert sorted(robot) == pytest.approx([0.002])
        assert sorted(ground) == pytest.approx([0.02])  # the scene's own shapes keep ManiSkill's
        assert base.sim_config.scene_config.solver_position_iterations == 17
        env.reset(seed=0)
        env.step(env.action_space.sample())
    finally:
        env.close()
    assert robospec.sim_config_for("panda") == {}  # ManiSkill's own agent: no recommendation
