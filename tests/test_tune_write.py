"""robospec tune --write's editing, without simulation: which controller a gain is written at
(``extends``), and that a YAML spec's text changes only in the gain values."""

from __future__ import annotations

import pytest

from robospec.tune.edits import Edit, WriteError, flow_list, plan
from robospec.tune.results import ControllerTuning, Gains
from robospec.tune.yaml_write import edit_yaml

JOINTS = ("j1", "j2", "j3")


def _tuned(name: str, stiffness: tuple[float, ...], damping: tuple[float, ...]) -> ControllerTuning:
    before = Gains((10.0,) * 3, (1.0,) * 3, (1e10,) * 3)
    after = Gains(stiffness, damping, (1e10,) * 3)
    return ControllerTuning(name, "m", "arm", "position", JOINTS, "tuned", None, before, after)


CONTROLLERS = {
    "base": {"type": "pd_joint_pos", "joints": "arm", "stiffness": 10, "damping": 1},
    "child": {"extends": "base", "use_delta": True},
}


def test_a_gain_every_controller_extending_it_agrees_on_changes_at_the_base() -> None:
    same = ((100.0, 100.0, 100.0), (20.0, 20.0, 20.0))
    edits = plan(CONTROLLERS, [_tuned("base", *same), _tuned("child", *same)])
    assert {(e.owner, e.field, e.insert) for e in edits} == {
        ("base", "stiffness", False),
        ("base", "damping", False),
    }


def test_a_gain_the_controllers_disagree_on_is_overridden_at_the_one_that_inherits_it() -> None:
    edits = plan(
        CONTROLLERS,
        [
            _tuned("base", (100.0,) * 3, (20.0,) * 3),
            _tuned("child", (300.0,) * 3, (20.0,) * 3),
        ],
    )
    assert Edit("child", "stiffness", JOINTS, (300.0,) * 3, insert=True) in edits
    assert Edit("base", "stiffness", JOINTS, (100.0,) * 3, insert=False) in edits
    assert Edit("base", "damping", JOINTS, (20.0,) * 3, insert=False) in edits


def test_a_base_changed_under_a_controller_not_tuned_needs_that_controller_tuned_too() -> None:
    with pytest.raises(WriteError, match="tune both"):
        plan(CONTROLLERS, [_tuned("base", (100.0, 200.0, 300.0), (20.0,) * 3)])


YAML_SPEC = """\
# a comment that stays
controllers:
  base:   {type: pd_joint_pos, joints: arm, stiffness: 10,   # aligned by hand
           damping: 1e0, force_limit: 100}
  child: {extends: base, use_delta: true}   # inherits the gains
  named:
    type: pd_joint_pos
    joints: [j1, j2, j3]
    stiffness: {j1: 10, j2: 10, j3: 10}   # by joint
    damping: [1, 1, 1]
"""


def _changed_lines(before: str, after: str) -> list[tuple[str, str]]:
    old, new = before.splitlines(), after.splitlines()
    assert len(old) == len(new)
    return [(a, b) for a, b in zip(old, new, strict=True) if a != b]


def test_yaml_gains_change_in_place_and_nothing_else_does() -> None:
    tunings = [
        _tuned("base", (100.0,) * 3, (20.0,) * 3),
        _tuned("child", (100.0,) * 3, (20.0,) * 3),
        _tuned("named", (10.0, 55.5, 10.0), (1.0, 3.0, 1.0)),
    ]
    edited = edit_yaml(YAML_SPEC, tunings, None)
    assert _changed_lines(YAML_SPEC, edited) == [
        (
            "  base:   {type: pd_joint_pos, joints: arm, stiffness: 10,   # aligned by hand",
            "  base:   {type: pd_joint_pos, joints: arm, stiffness: 100,   # aligned by hand",
        ),
        ("           damping: 1e0, force_limit: 100}", "           damping: 20, force_limit: 100}"),
        (
            "    stiffness: {j1: 10, j2: 10, j3: 10}   # by joint",
            "    stiffness: {j1: 10, j2: 55.5, j3: 10}   # by joint",
        ),
        ("    damping: [1, 1, 1]", "    damping: [1, 3, 1]"),
    ]


def test_yaml_one_value_becomes_a_flow_list_per_joint_and_an_override_is_a_new_key() -> None:
    tunings = [
        _tuned("base", (100.0, 200.0, 300.0), (20.0,) * 3),
        _tuned("child", (7.0,) * 3, (20.0,) * 3),
    ]
    edited = edit_yaml(YAML_SPEC, tunings, None)
    assert "stiffness: [100, 200, 300]," in edited
    assert (
        "  child: {extends: base, use_delta: true, stiffness: 7}   # inherits the gains" in edited
    )
    assert edited.startswith("# a comment that stays\n")


def test_a_long_flow_list_wraps_with_its_lines_aligned_after_the_bracket() -> None:
    text = flow_list([123.0] * 30, 10)
    lines = text.splitlines()
    assert len(lines) > 1 and 10 + len(lines[0]) <= 100
    assert all(len(line) <= 100 for line in lines[1:])
    assert all(line.startswith(" " * 11) for line in lines[1:])
    assert text.replace("\n", " ").split() == ["[123,", *["123,"] * 28, "123]"]


BLOCK_SPEC = """\
controllers:
  base:
    type: pd_joint_pos
    joints: arm
    stiffness: 10
    damping: 1
  child:
    extends: base
    use_delta: true
  after: {type: passive, joints: arm}
"""


def test_a_new_key_goes_after_the_last_key_of_a_block_mapping() -> None:
    # the child inherits its gains; tuned apart from its base, it gets its own stiffness: a new
    # key, written as the block mapping's last entry, at its indentation
    tunings = [
        _tuned("base", (100.0,) * 3, (20.0,) * 3),
        _tuned("child", (7.0,) * 3, (20.0,) * 3),
    ]
    edited = edit_yaml(BLOCK_SPEC, tunings, None)
    lines = edited.splitlines()
    child = lines.index("  child:")
    assert lines[child + 1 : child + 4] == [
        "    extends: base",
        "    use_delta: true",
        "    stiffness: 7",
    ]
    assert lines[child + 4] == "  after: {type: passive, joints: arm}"
    assert "    stiffness: 100" in lines and "    damping: 20" in lines


def test_every_line_of_a_wrapped_flow_list_fits_the_line_length() -> None:
    for indent in (4, 10, 30):
        text = flow_list([123.456] * 40, indent)
        lines = text.splitlines()
        assert len(lines) > 1
        # the first line follows the key at column `indent`; the others carry their indentation
        assert indent + len(lines[0]) <= 100
        assert all(len(line) <= 100 for line in lines[1:]), lines


def test_write_refuses_an_edit_that_does_not_give_the_tuned_gains(
    tmp_path: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    from conftest import PANDA_SPEC, maniskill_assets

    from robospec.pipeline import compile_spec
    from robospec.tune import write
    from robospec.tune.results import Gains

    spec = tmp_path / "panda.yaml"  # type: ignore[operator]
    assets = maniskill_assets()
    spec.write_text(PANDA_SPEC.read_text().replace("{maniskill_assets}", str(assets)))
    item = compile_spec(spec)
    assert item.ok and item.robot is not None
    joints = tuple(f"panda_joint{i}" for i in range(1, 8))
    before = Gains((1e3,) * 7, (1e2,) * 7, (100.0,) * 7)
    after = Gains((2e3,) * 7, (1e2,) * 7, (100.0,) * 7)
    tuning = ControllerTuning(
        "arm_pos", "m", "arm", "position", joints, "tuned", None, before, after
    )
    original = spec.read_text()
    # an editor that writes nothing (or the wrong place) must not pass for a written spec
    monkeypatch.setattr("robospec.tune.yaml_write.edit_yaml", lambda text, *args: text + "\n")
    written, diagnostics = write.write_gains(item, [tuning])
    assert not written and [d.code for d in diagnostics] == ["RS622"]
    assert "would get stiffness" in diagnostics[0].message
    assert spec.read_text() == original  # nothing was written


def test_a_list_that_fits_a_line_of_its_own_is_never_broken_where_it_starts_far_right() -> None:
    """`damping: [150,` / `100, ...]` reads as two values: a list that can be read whole on
    one line stays whole, even past the column where a long list would wrap."""
    seven = [150.0, 100.0, 120.5, 80.25, 60.125, 40.0, 20.0]
    assert flow_list(seven, 85, 6) == "[150, 100, 120, 80.2, 60.1, 40, 20]"
    assert flow_list(seven, 85) == "[150, 100, 120, 80.2, 60.1, 40, 20]"


SEVEN = tuple(f"j{i}" for i in range(1, 8))
WRAPPED_SPEC = """\
controllers:
  arm_pos:   {type: pd_joint_pos, joints: arm, stiffness: 1e3, damping: 1e2,
              force_limit: 100, normalize_action: false}
"""


def _seven_tuned(spec_name: str = "arm_pos") -> ControllerTuning:
    before = Gains((1000.0,) * 7, (100.0,) * 7, (100.0,) * 7)
    after = Gains(
        (1230.0, 1450.0, 980.0, 1510.0, 812.0, 640.5, 433.0),
        (123.0, 145.0, 98.0, 151.0, 81.2, 64.1, 43.3),
        (100.0,) * 7,
    )
    return ControllerTuning(spec_name, "m", "arm", "position", SEVEN, "tuned", None, before, after)


def test_gains_written_into_a_wrapped_flow_mapping_keep_its_lines_within_the_width() -> None:
    """Two per-joint lists in one line of a flow mapping made it 140 characters long: the line
    is broken after the mapping's commas, aligned after its brace, each list whole."""
    from ruamel.yaml import YAML

    edited = edit_yaml(WRAPPED_SPEC, [_seven_tuned()], None)
    assert edited.splitlines() == [
        "controllers:",
        "  arm_pos:   {type: pd_joint_pos, joints: arm, stiffness: [1230, 1450, 980, 1510, 812, "
        "640, 433],",
        "              damping: [123, 145, 98, 151, 81.2, 64.1, 43.3],",
        "              force_limit: 100, normalize_action: false}",
    ]
    gains = YAML(typ="safe").load(edited)["controllers"]["arm_pos"]
    assert gains["damping"] == [123, 145, 98, 151, 81.2, 64.1, 43.3]


def test_a_spec_written_wider_keeps_its_own_width() -> None:
    wide = "# " + "a comment written wide " * 6 + "and on it goes\n" + WRAPPED_SPEC
    assert max(map(len, wide.splitlines())) == 154
    edited = edit_yaml(wide, [_seven_tuned()], None)
    lines = edited.splitlines()
    assert max(map(len, lines)) <= 154
    # both lists fit the line, 145 characters in a spec that has lines of 154: not broken
    assert len(lines[2]) == 145
    assert lines[2].endswith("damping: [123, 145, 98, 151, 81.2, 64.1, 43.3],")


def test_a_toml_list_past_the_width_breaks_inside_the_list_never_the_inline_table() -> None:
    import tomllib

    from robospec.tune.toml_write import edit_toml

    spec = (
        "[controllers]\n"
        'arm_pos = { type = "pd_joint_pos", joints = "arm", stiffness = 1e3, damping = 1e2 }\n'
    )
    edited = edit_toml(spec, [_seven_tuned()], None)
    lines = edited.splitlines()
    assert max(map(len, lines)) <= 100, lines
    assert len(lines) > 2  # broken, and only inside the arrays: the table reads back the same
    assert tomllib.loads(edited)["controllers"]["arm_pos"]["damping"] == [
        123,
        145,
        98,
        151,
        81.2,
        64.1,
        43.3,
    ]
