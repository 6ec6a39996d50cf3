"""`robospec import`: every agent ManiSkill registers becomes a spec that validates (errors only
where upstream is wrong) and builds a class carrying the same data; upstream mistakes are
diagnostics; a bad ``module:Class`` is a located diagnostic, never a traceback.

Agents whose description is not installed (half of them download it on first use) are built
against a stand-in URDF made from the names the spec itself uses, and the upstream class is
read against the same stand-in, so both sides name the same joints.
"""

from __future__ import annotations

import copy
import importlib.util
import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import MANISKILL_VERSION, invoke_robospec
from maniskill_compare import (
    LOADER_FLAGS,
    assert_same_controller_configs,
    assert_same_keyframes,
    assert_same_value,
)

from robospec.maniskill.installed import registered_uids

pytestmark = pytest.mark.maniskill

ALL_AGENTS = sorted(registered_uids())
# import errors that report a mistake in the upstream class (the spec leaves the thing out)
UPSTREAM_ERRORS = {"RS405", "RS406", "RS414"}
PANDA = "mani_skill.agents.robots.panda.panda:Panda"


@pytest.fixture(scope="module")
def registry() -> Iterator[dict[str, Any]]:
    """ManiSkill's agent registry; agents the tests register leave it afterwards."""
    import mani_skill.envs  # noqa: F401  (registers every agent, once per session)
    from mani_skill.agents.registration import REGISTERED_AGENTS
    from mani_skill.utils.assets import DATA_GROUPS

    before = set(REGISTERED_AGENTS)
    modules_before = set(sys.modules)
    yield REGISTERED_AGENTS
    for uid in set(REGISTERED_AGENTS) - before:
        del REGISTERED_AGENTS[uid]
        DATA_GROUPS.pop(uid, None)
    for name in set(sys.modules) - modules_before:
        if name.startswith(("robospec_agents.", "imported_")):
            sys.modules.pop(name, None)


def _import(cls: type, uid: str, out_dir: Path) -> Any:
    from robospec.importer import import_class

    return import_class(cls, uid, out_dir)


def _codes(diagnostics: list[Any], *, errors_only: bool = False) -> set[str]:
    return {d.code for d in diagnostics if d.is_error or not errors_only}


# -- a stand-in description for agents whose files are not installed -----------------------------


def _names(spec: dict[str, Any]) -> tuple[list[str], list[str], int]:
    """Joint names, link names and the keyframe length a spec uses."""
    joints: list[str] = []
    links: list[str] = []

    def add_joints(selection: Any) -> None:
        items = selection if isinstance(selection, list) else [selection]
        for item in items:
            if isinstance(item, str) and item not in spec.get("groups", {}) and item != "*":
                joints.append(item)

    for value in spec.get("groups", {}).values():
        add_joints(value)
    for controller in spec.get("controllers", {}).values():
        add_joints(controller.get("joints", []))
        for follower, leader in (controller.get("mimic") or {}).items():
            add_joints([follower, leader if isinstance(leader, str) else leader["joint"]])
        links.extend(controller[k] for k in ("ee_link", "root_link_name") if controller.get(k))
    add_joints(spec.get("passive_joints") or [])
    links.extend(spec.get("links", {}))
    links.extend(camera["mount"] for camera in spec.get("cameras", {}).values())
    # what _after_init binds or sets bits on (a named link's own name is not a link)
    named = spec.get("named_links", {})
    for value in named.values():
        links.extend(value if isinstance(value, list) else [value])
    for rule in spec.get("collision_rules", []):
        links.extend(rule["links"] if isinstance(rule["links"], list) else [rule["links"]])
    tcp = spec.get("tcp")
    if isinstance(tcp, dict):
        tcp = [tcp.get("link"), *tcp.get("midpoint", []), tcp.get("orientation")]
    links.extend(
        t for t in (tcp if isinstance(tcp, list) else [tcp]) if t and t not in (*named, "midpoint")
    )
    length = max(
        (len(f.get(k) or []) for f in spec.get("keyframes", {}).values() for k in ("qpos", "qvel")),
        default=0,
    )
    return list(dict.fromkeys(joints)), list(dict.fromkeys(links)), length


def stand_in_urdf(spec: dict[str, Any]) -> str:
    joints, links, length = _names(spec)
    joints += [f"stand_in_joint_{i}" for i in range(max(length, 1) - len(joints))]
    parts = ['<robot name="stand_in">', '  <link name="stand_in_base"/>']
    parent = "stand_in_base"
    for index, joint in enumerate(joints):
        child = f"stand_in_link_{index}"
        parts.append(f'  <link name="{child}"/>')
        parts.append(
            f'  <joint name="{joint}" type="continuous"><parent link="{parent}"/>'
            f'<child link="{child}"/><axis xyz="0 0 1"/></joint>'
        )
        parent = child
    for index, link in enumerate(links):
        parts.append(f'  <link name="{link}"/>')
        parts.append(
            f'  <joint name="stand_in_fixed_{index}" type="fixed"><parent link="stand_in_base"/>'
            f'<child link="{link}"/></joint>'
        )
    parts.append("</robot>")
    return "\n".join(parts) + "\n"


def _load_yaml(text: str) -> Any:
    from ruamel.yaml import YAML

    return YAML(typ="safe").load(text)


def _dump_yaml(data: Any) -> str:
    import io

    from ruamel.yaml import YAML

    stream = io.StringIO()
    YAML().dump(data, stream)
    return stream.getvalue()


# -- building the class a spec describes -----------------------------------------------------------


def build_class(spec_file: Path, module_dir: Path) -> type:
    """The agent class of a spec, also when `validate` reports upstream's own errors (a joint
    driven twice, a keyframe outside the limits): resolved and emitted without the checks."""
    from robospec.load.reader import read_spec
    from robospec.model.validate import build_spec
    from robospec.output.modules import module_name_for, robot_files
    from robospec.resolve import resolve

    loaded, diagnostics = read_spec(spec_file)
    assert loaded is not None, diagnostics
    model = build_spec(loaded)
    assert model.spec is not None, model.diagnostics
    robot = resolve(loaded, model, spec_file).robot
    assert robot is not None
    module = "imported_" + module_name_for(robot.uid, set())
    module_dir.mkdir(parents=True, exist_ok=True)
    for name, text in robot_files(robot, module, module_dir).items():
        (module_dir / name).write_text(text, encoding="utf-8")
    spec = importlib.util.spec_from_file_location(module, module_dir / f"{module}.py")
    assert spec is not None and spec.loader is not None
    loaded_module = importlib.util.module_from_spec(spec)
    sys.modules[module] = loaded_module
    spec.loader.exec_module(loaded_module)
    return getattr(loaded_module, robot.class_name)


def _configs(cls: type, description: Any) -> tuple[Any, list[Any]]:
    from robospec.importer.introspect import StandInRobot, instantiate

    agent, failure = instantiate(cls, StandInRobot(description))
    assert failure is None, failure
    return agent._controller_configs, list(agent._sensor_configs)


def _real_path(path: Any) -> str:
    from mani_skill import format_path

    return os.path.realpath(format_path(str(path)))


def _normalized_urdf_paths(configs: dict[str, Any], own: str, upstream_own: str) -> dict:
    """IK configs name the agent's own URDF; ours names the spec's (maybe a stand-in)."""
    out = copy.deepcopy(configs)
    for mode in out.values():
        for config in mode.values() if isinstance(mode, dict) else [mode]:
            if isinstance(getattr(config, "urdf_path", None), str):
                path = _real_path(config.urdf_path)
                config.urdf_path = upstream_own if path == own else path
    return out


def _keyframes(frames: dict[str, Any], names: list[str]) -> dict[str, Any]:
    """Keyframes kept by the spec; a batch-of-one qpos (``[[...]]``) as the list it holds."""
    from mani_skill.agents.base_agent import Keyframe

    out = {}
    for name in names:
        frame = frames[name]
        values = {
            key: None if getattr(frame, key) is None else np.asarray(getattr(frame, key))
            for key in ("qpos", "qvel")
        }
        out[name] = Keyframe(
            pose=frame.pose,
            **{k: v.reshape(-1) if v is not None else None for k, v in values.items()},
        )
    return out


def _camera_fields(config: Any) -> dict[str, Any]:
    mount = config.mount.name if config.mount is not None else config.entity_uid
    fields = ("uid", "width", "height", "fov", "near", "far", "intrinsic", "shader_pack")
    return {
        **{name: getattr(config, name) for name in fields},
        "mount": mount,
        "p": config.pose.p,
        "q": config.pose.q,
    }


# -- the round trip, for all 43 agents -------------------------------------------------------------


@pytest.mark.parametrize("uid", ALL_AGENTS)
def test_every_agent_imports_validates_and_builds_the_same_data(
    uid: str, registry: dict[str, Any], tmp_path: Path
) -> None:
    from robospec.description import load_description
    from robospec.pipeline import compile_spec

    cls = registry[uid].agent_cls
    result = _import(cls, f"rs_imported_{uid}", tmp_path)
    assert result.text is not None, [d.format_text() for d in result.diagnostics]
    found = {d.code for d in result.diagnostics}
    assert _codes(result.diagnostics, errors_only=True) <= UPSTREAM_ERRORS, result.diagnostics
    spec_file = tmp_path / f"{uid}.yaml"
    spec_file.write_text(result.text, encoding="utf-8")

    # validate: errors only where upstream is wrong, or where its files are not installed
    installed = os.path.isfile(_real_path(cls.urdf_path or cls.mjcf_path))
    allowed = set()
    if not installed:
        allowed |= {"RS050", "RS055", "RS207"}  # missing file; "*" needs the real joints
    if "RS414" in found:
        allowed.add("RS304")  # upstream's keyframe outside the limits, kept as upstream has it
    if "RS415" in found:
        allowed.add("RS301")  # upstream drives a joint twice, kept as upstream has it
    errors = [d for d in compile_spec(spec_file).diagnostics if d.is_error]
    assert {d.code for d in errors} <= allowed, [d.format_text() for d in errors]

    spec = _load_yaml(result.text)
    if installed:
        description_file = _real_path(cls.urdf_path or cls.mjcf_path)
        description, _ = load_description(description_file, "urdf" if cls.urdf_path else "mjcf")
    else:  # build and compare against a stand-in made of the names the spec uses
        assert "RS410" in found
        stand_in = tmp_path / "stand_in.urdf"
        stand_in.write_text(stand_in_urdf(spec), encoding="utf-8")
        spec["description"] = {"urdf": stand_in.name}
        spec_file.write_text(_dump_yaml(spec), encoding="utf-8")
        errors = [d for d in compile_spec(spec_file).diagnostics if d.is_error]
        assert {d.code for d in errors} <= allowed - {"RS050", "RS055", "RS207"}, errors
        description_file = os.path.realpath(stand_in)
        description, _ = load_description(description_file, "urdf")
    assert description is not None
    built = build_class(spec_file, tmp_path / "module")

    for flag in LOADER_FLAGS:
        assert getattr(built, flag) == getattr(cls, flag), flag

    ours, our_sensors = _configs(built, description)
    theirs, their_sensors = _configs(cls, description)
    left_out = [m for m in theirs if m not in ours]
    for mode in left_out:  # only modes upstream breaks, each with its diagnostic
        assert any(mode in d.message for d in result.diagnostics if d.is_error), mode
    theirs = {m: c for m, c in theirs.items() if m not in left_out}
    upstream_own = _real_path(cls.urdf_path or cls.mjcf_path)
    assert_same_controller_configs(
        _normalized_urdf_paths(ours, _real_path(built.urdf_path or built.mjcf_path), upstream_own),
        _normalized_urdf_paths(theirs, description_file, upstream_own),
    )

    kept = list(built.keyframes)
    for name in set(cls.keyframes) - set(kept):
        assert any(name in d.message for d in result.diagnostics if d.code == "RS414"), name
    assert_same_keyframes(
        _keyframes(built.keyframes, kept),
        _keyframes(cls.keyframes, [n for n in cls.keyframes if n in kept]),
    )

    their_config = copy.deepcopy(cls.urdf_config) or {}
    our_config = built.urdf_config or {}
    for link in set(their_config.get("link", {})) - set(our_config.get("link", {})):
        assert any(link in d.message for d in result.diagnostics if d.code == "RS406"), link
        del their_config["link"][link]
    for key in ("_materials", "link"):  # ManiSkill looks these up by name: order is free
        assert_same_value(
            dict(sorted(our_config.get(key, {}).items())),
            dict(sorted(their_config.get(key, {}).items())),
            f"urdf_config.{key}",
        )

    assert [c.uid for c in our_sensors] == [c.uid for c in their_sensors]
    for a, b in zip(our_sensors, their_sensors, strict=True):
        assert_same_value(_camera_fields(a), _camera_fields(b), f"camera {b.uid}")


# -- upstream mistakes become diagnostics ---------------------------------------------------------


def _diagnostics_of(uid: str, registry: dict[str, Any], tmp_path: Path) -> tuple[str, list]:
    result = _import(registry[uid].agent_cls, f"rs_{uid}", tmp_path)
    return result.text, result.diagnostics


def test_fetch_ee_align_mode_is_left_out_and_pos_vel_warns(
    registry: dict[str, Any], tmp_path: Path
) -> None:
    text, diagnostics = _diagnostics_of("fetch", registry, tmp_path)
    if MANISKILL_VERSION == "nightly":  # which removed the mode
        assert not [d for d in diagnostics if d.code == "RS405"]
        assert "_align" not in text
        return
    (rejected,) = [d for d in diagnostics if d.code == "RS405"]
    assert rejected.is_error and "ee_align" in rejected.message
    assert "pd_ee_delta_pose_align" in rejected.message
    assert rejected.location.file == "mani_skill/agents/robots/fetch/fetch.py"
    assert "ee_align" in _source_line(rejected)
    assert "pd_ee_delta_pose_align:" not in text
    (nan,) = [d for d in diagnostics if d.code == "RS407"]
    assert not nan.is_error and "pd_joint_pos_vel" in nan.message
    assert "wrist_roll_joint" in nan.message


def test_unknown_urdf_config_link_is_left_out(registry: dict[str, Any], tmp_path: Path) -> None:
    for uid in ("floating_ability_hand_right", "xarm7_ability"):
        text, diagnostics = _diagnostics_of(uid, registry, tmp_path)
        (unknown,) = [d for d in diagnostics if d.code == "RS406"]
        assert unknown.is_error and "thumnb_L2" in unknown.message
        assert unknown.hint == "did you mean 'thumb_L2'?"
        assert "thumnb_L2" in _source_line(unknown)
        assert "thumnb_L2:" not in text and "index_L2:" in text


def test_positional_ee_arguments_are_reproduced_with_a_warning(
    registry: dict[str, Any], tmp_path: Path
) -> None:
    text, diagnostics = _diagnostics_of("xarm7_ability", registry, tmp_path)
    if MANISKILL_VERSION == "nightly":  # which names the arguments: nothing shifted
        assert not [d for d in diagnostics if d.code == "RS408"]
        controller = _load_yaml(text)["controllers"]["arm_ee_delta_pose"]
        assert controller["stiffness"] == 1000.0 and controller["damping"] == 100.0
        return
    (shifted,) = [d for d in diagnostics if d.code == "RS408"]
    assert not shifted.is_error and "pos_upper" in shifted.message
    assert "pd_ee_delta_pose, pd_ee_target_delta_pose" in shifted.message
    controller = _load_yaml(text)["controllers"]["arm_ee_delta_pose"]
    assert controller["stiffness"] == 0.1 and controller["damping"] == 1000.0
    assert "# as upstream: equals pos_upper" in text


def test_other_upstream_mistakes(registry: dict[str, Any], tmp_path: Path) -> None:
    _, diagnostics = _diagnostics_of(
        "unitree_g1_simplified_upper_body_right_arm", registry, tmp_path
    )
    assert any(d.code == "RS414" and d.is_error and "24 qpos" in d.message for d in diagnostics)
    _, diagnostics = _diagnostics_of("allegro_hand_right", registry, tmp_path)
    assert any(
        d.code == "RS414" and not d.is_error and "joint_12.0" in d.message for d in diagnostics
    )
    _, diagnostics = _diagnostics_of("widowxai", registry, tmp_path)
    assert any(d.code == "RS415" and "left_carriage_joint" in d.message for d in diagnostics)


def test_code_the_spec_does_not_reproduce_is_one_warning(
    registry: dict[str, Any], tmp_path: Path
) -> None:
    text, diagnostics = _diagnostics_of("panda", registry, tmp_path)
    (code,) = [d for d in diagnostics if d.code == "RS409"]
    assert not code.is_error
    for member in ("is_static", "build_grasp_pose"):
        assert member in code.message and member in text  # listed in the header comment too
    # reproduced as spec data (named_links, tcp, grasping): not listed
    for member in ("is_grasping", "tcp_pose", "tcp_pos", "_after_init"):
        assert member not in code.message
    assert code.location.file == "mani_skill/agents/robots/panda/panda.py"
    # a hook reproduced in part names what it leaves out
    _, diagnostics = _diagnostics_of("dclaw", registry, tmp_path)
    (code,) = [d for d in diagnostics if d.code == "RS409"]
    assert "_after_init (in part: self.root_joints, self.root_joint_indices)" in code.message


def _source_line(diagnostic: Any) -> str:
    import mani_skill

    root = Path(mani_skill.__file__).resolve().parent.parent
    lines = (root / diagnostic.location.file).read_text().splitlines()
    return lines[diagnostic.location.line - 1][diagnostic.location.column - 1 :]


# -- the shape of the output -------------------------------------------------------------------


def test_idiomatic_panda(registry: dict[str, Any], tmp_path: Path) -> None:
    text, _ = _diagnostics_of("panda", registry, tmp_path)
    assert text.startswith("# yaml-language-server: $schema=")
    spec = _load_yaml(text)
    assert spec["description"] == {"urdf": "{maniskill_assets}/robots/panda/panda_v2.urdf"}
    assert spec["groups"] == {"arm": "panda_joint[1-7]", "gripper": "panda_finger_joint[12]"}
    assert spec["keyframes"]["rest"]["qpos"]["gripper"] == 0.04
    assert "-5*pi/8" in text  # exact: evaluates to upstream's float
    assert spec["controllers"]["arm_target_delta_pos"] == {
        "extends": "arm_delta_pos",
        "use_target": True,
    }
    assert spec["control_modes"]["pd_joint_pos"] == {"arm": "arm_pos", "gripper": "gripper"}
    assert next(iter(spec["control_modes"])) == "pd_joint_delta_pos"  # the default mode stays first


def test_an_imported_spec_registers(registry: dict[str, Any], tmp_path: Path) -> None:
    import robospec

    out = tmp_path / "panda.yaml"
    (tmp_path / "panda.yaml").write_text(
        _import(registry["panda"].agent_cls, "rs_imported_panda_registered", tmp_path).text
    )
    classes = robospec.register(out, cache_dir=tmp_path / "cache")
    assert list(classes) == ["rs_imported_panda_registered"]
    assert (
        registry["rs_imported_panda_registered"].agent_cls
        is classes["rs_imported_panda_registered"]
    )


# -- the command line ------------------------------------------------------------------------------


def _cli(*args: str) -> Any:
    return invoke_robospec("import", *args)


@pytest.mark.parametrize(
    ("target", "code", "column"),
    [
        ("mani_skill.agents.robots.panda.panda", "RS400", 1),  # no colon
        ("a:b:c", "RS400", 1),
        ("mani_skill.agents.robots.panda.panda:", "RS400", 38),
        ("mani_skill.no_such_module:Panda", "RS401", 1),
        ("mani_skill.agents.robots.panda.panda:Pandaa", "RS402", 38),
        ("mani_skill.agents.base_agent:Keyframe", "RS403", 30),
        ("mani_skill.agents.base_agent:BaseAgent", "RS403", 30),
        ("mani_skill.agents.robots.panda.panda:PACKAGE_ASSET_DIR", "RS403", 38),
    ],
)
def test_a_bad_target_is_a_located_diagnostic(
    target: str, code: str, column: int, registry: dict[str, Any]
) -> None:
    result = _cli(target)
    assert result.exit_code == 1, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert "Traceback" not in result.output
    assert f"<module:Class>:1:{column}: error[{code}]" in result.output


def test_cli_writes_the_file_and_does_not_overwrite(
    registry: dict[str, Any], tmp_path: Path
) -> None:
    out = tmp_path / "specs" / "koch.yaml"
    result = _cli("mani_skill.agents.robots.koch.koch:Koch", "--uid", "rs_koch", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert _load_yaml(out.read_text())["uid"] == "rs_koch"
    assert "warning[RS409]" in result.output
    again = _cli("mani_skill.agents.robots.koch.koch:Koch", "-o", str(out))
    assert again.exit_code == 1 and "error[RS412]" in again.output
    forced = _cli("mani_skill.agents.robots.koch.koch:Koch", "-o", str(out), "--force")
    assert forced.exit_code == 0
    assert _load_yaml(out.read_text())["uid"] == "koch-v1.1"  # the class's own uid by default
    assert "warning[RS411]" in forced.output  # ... which is ManiSkill's own


def test_cli_prints_to_stdout_and_exits_one_on_upstream_errors(registry: dict[str, Any]) -> None:
    # upstream gives a material to a link that does not exist (in every ManiSkill)
    target = "mani_skill.agents.robots.xarm.xarm7_ability:XArm7Ability"
    result = _cli(target, "--uid", "rs_xarm2")
    assert result.exit_code == 1
    assert "# yaml-language-server: $schema=" in result.output
    assert "uid: rs_xarm2" in result.output and "error[RS406]" in result.output
    bad_uid = _cli("mani_skill.agents.robots.fetch.fetch:Fetch", "--uid", "no spaces")
    assert bad_uid.exit_code == 1 and "error[RS105]" in bad_uid.output
