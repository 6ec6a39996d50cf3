"""URDF facts: SAPIEN's joint order, limits, mimic, and a located diagnostic for every defect."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from robospec.description import load_description
from robospec.description.facts import RobotDescription
from robospec.description.urdf import parse_urdf
from robospec.diagnostics import Diagnostic

DATA = Path(__file__).parent / "data"
INVALID = DATA / "urdf_invalid"


def parse_file(path: Path) -> tuple[RobotDescription | None, list[Diagnostic]]:
    return parse_urdf(path.read_bytes(), str(path))


def errors(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    return [d for d in diagnostics if d.is_error]


# -- order ------------------------------------------------------------------------------------


def test_active_joints_are_in_breadth_first_order_with_siblings_in_declaration_order() -> None:
    description, diagnostics = parse_file(DATA / "tree.urdf")
    assert diagnostics == []
    assert description is not None
    # Depth-first would give j_head, j_arm1, j_arm2, j_lift, ...: SAPIEN/PhysX uses BFS.
    assert description.active_joint_names == (
        "j_head",
        "j_arm1",
        "j_lift",
        "j_arm2",
        "j_finger_l",
        "j_finger_r",
    )


def test_links_are_listed_in_sapien_link_order() -> None:
    description, _ = parse_file(DATA / "tree.urdf")
    assert description is not None
    assert description.link_names == (
        "base",
        "head",
        "arm1",
        "lift",
        "camera",
        "arm2",
        "finger_l",
        "finger_r",
        "tool",
    )
    assert description.root_link == "base"
    assert not description.floating_root
    # One joint per non-root link, in link order; fixed joints are listed but not active.
    assert [j.child for j in description.joints] == list(description.link_names[1:])
    assert description.joint("j_cam") is not None
    assert not description.joint("j_cam").is_active  # type: ignore[union-attr]


def test_joint_and_link_lines_point_at_their_elements() -> None:
    description, _ = parse_file(DATA / "tree.urdf")
    assert description is not None
    lines = (DATA / "tree.urdf").read_text().splitlines()
    for joint in description.joints:
        assert f'<joint name="{joint.name}"' in lines[joint.line - 1]
    for link in description.links:
        assert f'<link name="{link.name}"' in lines[link.line - 1]


# -- limits and mimic ---------------------------------------------------------------------------


def test_limits_come_from_limit_element_and_continuous_joints_are_unbounded() -> None:
    description, _ = parse_file(DATA / "tree.urdf")
    assert description is not None
    limits = {j.name: (j.lower, j.upper) for j in description.joints}
    assert limits["j_head"] == (-1.5, 1.5)
    assert limits["j_arm1"] == (-2.0, 0.5)
    assert limits["j_lift"] == (0.0, 0.4)
    assert limits["j_arm2"] == (None, None)  # continuous: its <limit> has no bounds to keep
    assert limits["j_cam"] == (None, None)


def test_mimic_element_is_recorded_with_multiplier_and_offset() -> None:
    description, _ = parse_file(DATA / "tree.urdf")
    assert description is not None
    finger_r = description.joint("j_finger_r")
    assert finger_r is not None and finger_r.mimic is not None
    assert (finger_r.mimic.joint, finger_r.mimic.multiplier, finger_r.mimic.offset) == (
        "j_finger_l",
        -1.0,
        0.01,
    )
    assert description.joint("j_finger_l").mimic is None  # type: ignore[union-attr]


def test_mimic_defaults_to_multiplier_one_and_offset_zero() -> None:
    text = (DATA / "tree.urdf").read_text().replace(' multiplier="-1" offset="0.01"', "")
    description, diagnostics = parse_urdf(text, "tree.urdf")
    assert diagnostics == []
    assert description is not None
    mimic = description.joint("j_finger_r").mimic  # type: ignore[union-attr]
    assert mimic is not None and (mimic.multiplier, mimic.offset) == (1.0, 0.0)


# -- floating joints ------------------------------------------------------------------------------


def test_floating_joint_from_root_makes_its_child_a_free_root_and_is_reported() -> None:
    description, diagnostics = parse_file(DATA / "floating.urdf")
    assert description is not None
    assert description.floating_root
    assert description.root_link == "body"
    assert description.link_names == ("body", "wheel")  # 'world' is not part of the robot
    assert description.active_joint_names == ("j_wheel",)
    # SAPIEN 3.0.3 cannot load it (KeyError in its URDF loader): an error, with the way out.
    [problem] = diagnostics
    assert (problem.code, problem.location.line) == ("RS052", 11)
    assert problem.hint is not None and "fix_root_link: false" in problem.hint


# -- malformed input ------------------------------------------------------------------------------


def test_malformed_xml_is_rs051_at_lxml_line_and_column() -> None:
    text = '<robot name="r">\n  <link name="base">\n</robot>\n'
    description, diagnostics = parse_urdf(text, "bad.urdf")
    assert description is None
    [problem] = diagnostics
    assert problem.code == "RS051"
    assert (problem.location.file, problem.location.line, problem.location.column) == (
        "bad.urdf",
        3,
        9,
    )
    assert "mismatch" in problem.message
    assert "line 3" not in problem.message  # the location says it once


def test_empty_document_is_rs051() -> None:
    description, diagnostics = parse_urdf(b"", "empty.urdf")
    assert description is None
    assert [(d.code, d.location.line) for d in diagnostics] == [("RS051", 1)]


def test_external_entities_are_never_read() -> None:
    text = (
        '<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/hostname">]>\n'
        '<robot name="r"><link name="&x;"/></robot>'
    )
    description, diagnostics = parse_urdf(text, "entity.urdf")
    assert description is None
    assert [(d.code, d.location.line) for d in diagnostics] == [("RS051", 2)]
    assert "external entity" in diagnostics[0].message


def test_entity_expansion_bomb_is_refused_quickly() -> None:
    entities = '<!ENTITY e0 "lollollollollollollollollollol">'
    for level in range(1, 10):
        entities += f'<!ENTITY e{level} "{f"&e{level - 1};" * 10}">'
    text = f'<!DOCTYPE robot [{entities}]><robot name="r"><link name="&e9;"/></robot>'
    description, diagnostics = parse_urdf(text, "bomb.urdf")
    assert description is None
    assert [d.code for d in diagnostics] == ["RS051"]


def _invalid_cases() -> Iterator[Any]:
    for path in sorted(INVALID.glob("*.urdf")):
        marked = [
            (number, match.group(1))
            for number, line in enumerate(path.read_text().splitlines(), start=1)
            if (match := re.search(r"<!-- expect (RS\d{3}) -->", line))
        ]
        assert len(marked) == 1, f"{path.name} needs exactly one '<!-- expect RSnnn -->' marker"
        yield pytest.param(path, *marked[0], id=path.stem)


@pytest.mark.parametrize(("path", "line", "code"), list(_invalid_cases()))
def test_each_structural_defect_is_an_error_with_its_code_at_the_offending_line(
    path: Path, line: int, code: str
) -> None:
    _, diagnostics = parse_file(path)
    found = errors(diagnostics)
    assert found, f"{path.name}: no error reported"
    assert (found[0].code, found[0].location.line) == (code, line), [
        d.format_text() for d in diagnostics
    ]
    assert found[0].location.file == str(path)


@pytest.mark.parametrize(
    ("name", "words"),
    [
        ("missing_parent", "no <parent"),
        ("missing_child", "no <child"),
        ("unknown_link", "unknown parent link 'bse'"),
        ("duplicate_link", "duplicate link name 'arm' (first defined on line 3)"),
        ("duplicate_joint", "duplicate joint name 'j1' (first defined on line 5)"),
        ("cycle", "cycle"),
        ("several_roots", "several root links"),
        ("two_parents", "child of joint 'j3' and of joint 'j2'"),
        ("unknown_mimic", "mimics unknown joint 'finger_lft'"),
        ("bad_limit_number", 'lower="-1.5x" is not a number'),
        ("lower_above_upper", "lower=1 above upper=-1"),
        ("missing_limit", "has no <limit>"),
        ("limit_without_upper", "no upper="),
        ("unknown_joint_type", "unknown type 'revolut'"),
        ("bad_axis", 'xyz="0 1" is not 3 numbers'),
        ("floating_not_from_root", "not attached to the root link"),
        ("planar", "planar"),
        ("no_joints", "no joints"),
        ("wrong_root_element", "not <robot>"),
        ("link_without_name", "link without a name"),
    ],
)
def test_each_structural_defect_is_explained(name: str, words: str) -> None:
    _, diagnostics = parse_file(INVALID / f"{name}.urdf")
    assert words in errors(diagnostics)[0].message


def test_misspelled_names_get_a_did_you_mean_hint() -> None:
    _, link_diagnostics = parse_file(INVALID / "unknown_link.urdf")
    assert link_diagnostics[0].hint == "did you mean 'base'?"
    _, mimic_diagnostics = parse_file(INVALID / "unknown_mimic.urdf")
    assert mimic_diagnostics[0].hint == "did you mean 'finger_left'?"
    _, type_diagnostics = parse_file(INVALID / "unknown_joint_type.urdf")
    assert type_diagnostics[0].hint == "did you mean 'revolute'?"


def test_tree_breaking_errors_return_no_description() -> None:
    for name in ("duplicate_link", "duplicate_joint", "cycle", "several_roots", "unknown_link"):
        description, _ = parse_file(INVALID / f"{name}.urdf")
        assert description is None, name


def test_errors_that_leave_the_tree_intact_still_return_a_description() -> None:
    description, diagnostics = parse_file(INVALID / "unknown_mimic.urdf")
    assert errors(diagnostics)
    assert description is not None
    assert description.active_joint_names == ("finger_left", "finger_right")
    assert description.joint("finger_right").mimic is None  # type: ignore[union-attr]

    description, diagnostics = parse_file(INVALID / "bad_limit_number.urdf")
    assert errors(diagnostics)
    assert description is not None
    j1 = description.joint("j1")
    assert j1 is not None and j1.lower is None


def test_every_truncation_of_a_valid_urdf_yields_diagnostics_not_exceptions() -> None:
    text = (DATA / "tree.urdf").read_bytes()
    for end in range(0, len(text), 7):
        description, diagnostics = parse_urdf(text[:end], "cut.urdf")
        assert description is None
        assert errors(diagnostics)


# -- load_description -----------------------------------------------------------------------------


def test_missing_file_is_rs050_at_line_one(tmp_path: Path) -> None:
    missing = str(tmp_path / "nope.urdf")
    description, diagnostics = load_description(missing, "urdf")
    assert description is None
    [problem] = diagnostics
    assert problem.code == "RS050"
    assert (problem.location.file, problem.location.line, problem.location.column) == (
        missing,
        1,
        1,
    )


def test_unreadable_path_is_rs050(tmp_path: Path) -> None:
    description, diagnostics = load_description(str(tmp_path), "urdf")  # a directory
    assert description is None
    assert [d.code for d in diagnostics] == ["RS050"]


def test_load_description_reads_the_file_or_uses_given_text() -> None:
    path = str(DATA / "tree.urdf")
    from_file, _ = load_description(path, "urdf")
    from_text, _ = load_description(path, "urdf", text=(DATA / "tree.urdf").read_text())
    assert from_file is not None and from_text is not None
    assert from_file.active_joint_names == from_text.active_joint_names
    assert from_file.path == path


def test_description_modules_import_without_heavy_dependencies() -> None:
    code = (
        "import sys, time\n"
        "t = time.perf_counter()\n"
        "import robospec.description, robospec.description.urdf, robospec.description.mjcf\n"
        "elapsed = time.perf_counter() - t\n"
        "heavy = [m for m in ('numpy', 'sapien', 'mani_skill', 'torch', 'trimesh', 'yourdfpy')"
        " if m in sys.modules]\n"
        "print(heavy, elapsed)\n"
        "assert heavy == [], heavy\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=Path(__file__).parent.parent,
        check=False,
    )
    assert result.returncode == 0, result.stdout + result.stderr


# -- against SAPIEN ------------------------------------------------------------------------------


def _bundled_agents() -> list[tuple[str, str, str]]:
    """(uid, kind, path) of every registered agent whose description ships in the package."""
    import mani_skill.envs  # noqa: F401  (registers the agents)
    from mani_skill.agents.registration import REGISTERED_AGENTS

    found = []
    for uid, entry in REGISTERED_AGENTS.items():
        cls = entry.agent_cls
        if not cls.__module__.startswith("mani_skill."):
            continue  # agents registered by other tests (e.g. robospec's own) are not upstream's
        urdf, mjcf = getattr(cls, "urdf_path", None), getattr(cls, "mjcf_path", None)
        path = urdf or mjcf
        if path and os.path.exists(path):
            found.append((uid, "urdf" if urdf else "mjcf", str(path)))
    return found


def _sapien_facts(uid: str) -> dict[str, Any]:

    from robospec.maniskill.headless import make_empty_env

    env = make_empty_env(uid)
    try:
        robot = env.unwrapped.agent.robot  # type: ignore[attr-defined]
        return {
            "links": [link.name for link in robot.links],
            "joints": [joint.name for joint in robot.joints],
            "active": [joint.name for joint in robot.active_joints],
            "limits": [[float(x) for x in j.limits[0].flatten()] for j in robot.active_joints],
            "fixed_root": bool(robot.fixed_root_link.all()),
            "fix_root_link": env.unwrapped.agent.fix_root_link,  # type: ignore[attr-defined]
            "shaped": {link.name for link in robot.links if link._objs[0].collision_shapes},
        }
    finally:
        env.close()


def _same_limit(mine: float | None, sapien: float, sign: int) -> bool:
    if mine is None:
        return math.isinf(sapien) and sapien * sign > 0
    return abs(mine - sapien) <= 1e-5 * max(1.0, abs(mine))  # SAPIEN keeps float32


@pytest.mark.usefixtures("maniskill")
def test_parser_matches_sapien_for_every_bundled_maniskill_agent() -> None:
    agents = _bundled_agents()
    assert len(agents) == 24  # ManiSkill 3.0.1 bundles 24 of its 43 agents' descriptions
    mismatches: list[str] = []
    for uid, kind, path in agents:
        description, diagnostics = load_description(path, kind)  # type: ignore[arg-type]
        assert description is not None, (uid, [d.format_text() for d in diagnostics])
        assert not errors(diagnostics), (uid, [d.format_text() for d in diagnostics])
        facts = _sapien_facts(uid)
        if list(description.active_joint_names) != facts["active"]:
            mismatches.append(
                f"{uid} active: {description.active_joint_names} != {facts['active']}"
            )
        if list(description.link_names) != facts["links"]:
            mismatches.append(f"{uid} links: {description.link_names} != {facts['links']}")
        # Every named joint, in order (the root's and MJCF's synthesized fixed joints are '').
        if list(description.joint_names) != [name for name in facts["joints"] if name]:
            mismatches.append(f"{uid} joints: {description.joint_names} != {facts['joints']}")
        for joint, (lower, upper) in zip(description.active_joints, facts["limits"], strict=False):
            if not (_same_limit(joint.lower, lower, -1) and _same_limit(joint.upper, upper, 1)):
                mismatches.append(
                    f"{uid} {joint.name}: {joint.lower, joint.upper} != {lower, upper}"
                )
        if description.floating_root and facts["fixed_root"]:
            mismatches.append(f"{uid}: floating root expected, SAPIEN's root is fixed")
        shaped = {link.name for link in description.links if link.shaped}
        if shaped != facts["shaped"]:
            mismatches.append(f"{uid} links with collision shapes: {shaped ^ facts['shaped']}")
    assert mismatches == []


@pytest.mark.usefixtures("maniskill")
def test_fixture_order_and_limits_match_sapien() -> None:
    import mani_skill.envs  # noqa: F401
    import sapien

    from robospec.maniskill.headless import headless_loading, make_empty_env

    description, _ = parse_file(DATA / "tree.urdf")
    assert description is not None
    with headless_loading():  # the fixture's own parse below needs it too
        env = make_empty_env("panda", headless=False)
        try:
            loader = env.unwrapped.scene.create_urdf_loader()  # type: ignore[attr-defined]
            loader.name = "tree"
            builder = loader.parse(str(DATA / "tree.urdf"))["articulation_builders"][0]
            builder.initial_pose = sapien.Pose()
            robot = builder.build()
            assert [link.name for link in robot.links] == list(description.link_names)
            assert [j.name for j in robot.active_joints] == list(description.active_joint_names)
            for joint, sapien_joint in zip(
                description.active_joints, robot.active_joints, strict=True
            ):
                lower, upper = (float(x) for x in sapien_joint.limits[0].flatten())
                assert _same_limit(joint.lower, lower, -1) and _same_limit(joint.upper, upper, 1)
        finally:
            env.close()
