"""No text from a spec or a robot description can become code in a generated module."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from ast_names import identifiers

from robospec.emit.generate import RESERVED_NAMES, emit_module
from robospec.pipeline import compile_spec

HOSTILE = 'a"\'"""; import os; os.system("touch CANARY") #{x}\\'

URDF = """<?xml version="1.0"?>
<robot name="hostile">
  <link name="base"/>
  <link name="{link}"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
    </inertial></link>
  <joint name="{joint}" type="revolute"><parent link="base"/><child link="{link}"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""

SPEC = """robospec: 1
uid: rs_hostile
description: {{urdf: {urdf}}}
materials: {{m: {{static_friction: 1, dynamic_friction: 1}}}}
links: {{{link}: {{material: m}}}}
keyframes: {{rest: {{qpos: [0.5]}}}}
controllers:
  c: {{type: pd_joint_pos, joints: "*", lower: -1, upper: 1, stiffness: 10, damping: 1}}
control_modes: {{mode: {{g: c}}}}
cameras: {{cam: {{mount: {link}, width: 8, height: 8, fov: 1}}}}
tcp: {link}
"""


def _quoted(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def test_hostile_names_reach_the_module_only_as_string_constants(tmp_path: Path) -> None:
    link, joint = "L" + HOSTILE.replace("{x}", "1"), "J" + HOSTILE.replace("{x}", "2")
    folder = tmp_path / 'dir"""x'
    folder.mkdir()
    urdf_text = URDF.format(link=link.replace('"', "&quot;"), joint=joint.replace('"', "&quot;"))
    (folder / "robot.urdf").write_text(urdf_text)
    spec_path = folder / 'spec"""; import os #.yaml'
    spec_path.write_text(SPEC.format(urdf=_quoted("robot.urdf"), link=_quoted(link)))
    result = compile_spec(spec_path)
    assert result.robot is not None, [d.format_text() for d in result.diagnostics]
    source = emit_module(result.robot, tmp_path / "out")
    tree = ast.parse(source)
    strings = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)}
    assert link in strings and joint in strings
    allowed = RESERVED_NAMES | {
        "RsHostile",
        "c",
        "np",
        "array",
        "Pose",
        "create_from_pq",
        "path",
        "join",
        "dirname",
        "abspath",
        "__file__",
        "robot",
        "links_map",
        "tcp",
        "tcp_pos",
        "tcp_pose",
        "property",
        "numpy",
        "mani_skill",
        "mani_skill.agents.base_agent",
        # the parts of the modules the generated code imports from
        "agents",
        "base_agent",
        "camera",
        "controllers",
        "registration",
        "sensors",
        "structs",
        "utils",
        "uid",
        "urdf_path",
        "fix_root_link",
        "load_multiple_collisions",
        "disable_self_collisions",
        "urdf_config",
        "keyframes",
        # the reset to a keyframe (robospec.emit.reset)
        "reset",
        "init_qpos",
        "super",
        "_controller_configs",
        "_sensor_configs",
        "_after_init",
        "pose",
        "qpos",
        "p",
        "q",
        "joint_names",
        "lower",
        "upper",
        "stiffness",
        "damping",
        "width",
        "height",
        "fov",
        "near",
        "far",
        "entity_uid",
        "PDJointPosControllerConfig",
    }
    assert identifiers(tree) <= allowed, identifiers(tree) - allowed
    assert "CANARY" not in "".join(identifiers(tree))
    namespace: dict[str, object] = {}
    exec(compile(source.split("import numpy")[0], "<docstring>", "exec"), namespace)
    assert not (tmp_path / "CANARY").exists()


KEYWORD_MEMBER_SPEC = """robospec: 1
uid: rs_keyword_member
description: {urdf: "{maniskill_assets}/robots/panda/panda_v2.urdf"}
controllers:
  arm: {type: pd_joint_pos, joints: "*", lower: null, upper: null, stiffness: 1e3, damping: 1e2}
control_modes: {pd_joint_pos: {all: arm}}
named_links: {class: panda_hand}
link_states: {None: {link: panda_hand}}
proprioception: [None]
"""


def test_a_member_named_like_a_python_keyword_is_rs105_not_a_traceback(tmp_path: Path) -> None:
    # 'class' and 'None' match the name pattern, but no class can define them
    import subprocess
    import sys

    spec = tmp_path / "keyword.yaml"
    spec.write_text(KEYWORD_MEMBER_SPEC)
    result = subprocess.run(
        [sys.executable, "-m", "robospec.cli", "build", str(spec), "-o", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 1
    assert f"{spec}:7:15: error[RS105] 'class' is a Python keyword" in result.stderr
    assert f"{spec}:8:15: error[RS105] 'None' is a Python keyword" in result.stderr
    assert "Traceback" not in result.stdout + result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.maniskill
def test_register_reports_a_keyword_member_as_rs105(tmp_path: Path) -> None:
    pytest.importorskip("mani_skill")
    import robospec

    spec = tmp_path / "keyword.yaml"
    spec.write_text(KEYWORD_MEMBER_SPEC)
    with pytest.raises(robospec.SpecError) as caught:
        robospec.register(spec, cache_dir=tmp_path / "cache")
    found = [(d.code, d.location.line) for d in caught.value.diagnostics]
    assert found == [("RS105", 7), ("RS105", 8)]
