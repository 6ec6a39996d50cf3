"""toml_positions: every key path of a TOML document mapped to exact 1-based key/value positions."""

from __future__ import annotations

import sys
from typing import Any

import pytest

from robospec.load.toml_positions import (
    Path,
    toml_positions,
    tomllib_error_location,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - the project's tests run on 3.11+
    tomllib = pytest.importorskip("tomli")


def all_paths(node: Any, prefix: Path = ()) -> set[Path]:
    """Every key path tomllib's data has (what a source map must cover)."""
    out: set[Path] = set()
    if isinstance(node, dict):
        for key, value in node.items():
            out.add((*prefix, key))
            out |= all_paths(value, (*prefix, key))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            out.add((*prefix, index))
            out |= all_paths(value, (*prefix, index))
    return out


def positions(text: str) -> dict[Path, tuple[tuple[int, int], tuple[int, int]]]:
    result = toml_positions(text)
    # whatever the positions are, they must name exactly the paths tomllib produces
    assert set(result) == all_paths(tomllib.loads(text))
    return result


def test_top_level_keys() -> None:
    text = 'robospec = 1\nuid   =   "rs_panda"\n'
    assert positions(text) == {
        ("robospec",): ((1, 1), (1, 12)),
        ("uid",): ((2, 1), (2, 11)),
    }


def test_quoted_keys_are_unquoted() -> None:
    text = (
        '"panda_*finger" = 1\n'
        "'lit.eral' = 2\n"
        '"esc\\"aped\\u00e9" = 3\n'
        'links."panda_[1-7]".material = "gripper"\n'
    )
    assert positions(text) == {
        ("panda_*finger",): ((1, 1), (1, 19)),
        ("lit.eral",): ((2, 1), (2, 14)),
        ('esc"apedé',): ((3, 1), (3, 21)),
        ("links",): ((4, 1), (4, 7)),
        ("links", "panda_[1-7]"): ((4, 7), (4, 21)),
        ("links", "panda_[1-7]", "material"): ((4, 21), (4, 32)),
    }


def test_dotted_keys() -> None:
    # an implicit table's value position is where the key continues; spacing around dots is legal
    text = "a.b.c = 1\na . d = 2\n"
    assert positions(text) == {
        ("a",): ((1, 1), (1, 3)),
        ("a", "b"): ((1, 3), (1, 5)),
        ("a", "b", "c"): ((1, 5), (1, 9)),
        ("a", "d"): ((2, 5), (2, 9)),
    }


def test_tables_and_dotted_headers() -> None:
    text = "[loader]\nfix_root_link = true\n\n[controllers.arm_pos]\ntype = 'pd_joint_pos'\n"
    assert positions(text) == {
        ("loader",): ((1, 2), (1, 2)),
        ("loader", "fix_root_link"): ((2, 1), (2, 17)),
        ("controllers",): ((4, 2), (4, 14)),
        ("controllers", "arm_pos"): ((4, 14), (4, 14)),
        ("controllers", "arm_pos", "type"): ((5, 1), (5, 8)),
    }


def test_explicit_table_wins_over_implicit() -> None:
    # [a.b] creates a implicitly; the later [a] header is where a is defined
    text = "[a.b]\nc = 1\n[a]\nd = 2\n"
    result = positions(text)
    assert result[("a",)] == ((3, 2), (3, 2))
    assert result[("a", "b")] == ((1, 4), (1, 4))


def test_inline_tables() -> None:
    text = "materials = {gripper = {static_friction = 2.0, restitution = 0}}\n"
    assert positions(text) == {
        ("materials",): ((1, 1), (1, 13)),
        ("materials", "gripper"): ((1, 14), (1, 24)),
        ("materials", "gripper", "static_friction"): ((1, 25), (1, 43)),
        ("materials", "gripper", "restitution"): ((1, 48), (1, 62)),
    }


def test_arrays_nested_and_multiline() -> None:
    text = "qpos = [0, [1, 2],\n  {g = 0.04}, # a comment\n  3,\n]\n"
    assert positions(text) == {
        ("qpos",): ((1, 1), (1, 8)),
        ("qpos", 0): ((1, 9), (1, 9)),
        ("qpos", 1): ((1, 12), (1, 12)),
        ("qpos", 1, 0): ((1, 13), (1, 13)),
        ("qpos", 1, 1): ((1, 16), (1, 16)),
        ("qpos", 2): ((2, 3), (2, 3)),
        ("qpos", 2, "g"): ((2, 4), (2, 8)),
        ("qpos", 3): ((3, 3), (3, 3)),
    }


def test_arrays_of_tables() -> None:
    text = (
        "[[collision_rules]]\n"  # 1
        "links = ['l_wheel']\n"  # 2
        "[[collision_rules]]\n"  # 3
        "bit = 30\n"  # 4
        "[[collision_rules.extra]]\n"  # 5
        "x = 1\n"  # 6
        "[collision_rules.meta]\n"  # 7
        "y = 2\n"  # 8
    )
    assert positions(text) == {
        ("collision_rules",): ((1, 3), (1, 3)),
        ("collision_rules", 0): ((1, 3), (1, 3)),
        ("collision_rules", 0, "links"): ((2, 1), (2, 9)),
        ("collision_rules", 0, "links", 0): ((2, 10), (2, 10)),
        ("collision_rules", 1): ((3, 3), (3, 3)),
        ("collision_rules", 1, "bit"): ((4, 1), (4, 7)),
        # a sub-header continues the last element
        ("collision_rules", 1, "extra"): ((5, 19), (5, 19)),
        ("collision_rules", 1, "extra", 0): ((5, 19), (5, 19)),
        ("collision_rules", 1, "extra", 0, "x"): ((6, 1), (6, 5)),
        ("collision_rules", 1, "meta"): ((7, 18), (7, 18)),
        ("collision_rules", 1, "meta", "y"): ((8, 1), (8, 5)),
    }


def test_columns_count_characters_not_bytes() -> None:
    # "é", "ü" and "→" are 2 and 3 bytes in UTF-8; every column after them counts characters
    text = 'name = "é"\n[t]\n"ü→" = {a = "→→", b = 2}\nc = [\'ü\', 1]\n'
    assert positions(text) == {
        ("name",): ((1, 1), (1, 8)),
        ("t",): ((2, 2), (2, 2)),
        ("t", "ü→"): ((3, 1), (3, 8)),
        ("t", "ü→", "a"): ((3, 9), (3, 13)),
        ("t", "ü→", "b"): ((3, 19), (3, 23)),
        ("t", "c"): ((4, 1), (4, 5)),
        ("t", "c", 0): ((4, 6), (4, 6)),
        ("t", "c", 1): ((4, 11), (4, 11)),
    }


def test_tabs_crlf_and_multiline_strings() -> None:
    text = 'a = """\r\nline\r\n"""\r\n\tb\t=\t2\r\n'
    assert positions(text) == {
        ("a",): ((1, 1), (1, 5)),
        ("b",): ((4, 2), (4, 6)),
    }


def test_a_spec_in_toml_is_fully_mapped() -> None:
    text = """#:schema ../../schemas/robospec.schema.json
robospec = 1
uid = "rs_panda"
description.urdf = "{maniskill_assets}/robots/panda/panda_v2.urdf"
loader = {fix_root_link = true, load_multiple_collisions = false}

[links."panda_*finger"]
material = "gripper"
patch_radius = 0.1

[groups]
arm = "panda_joint[1-7]"
gripper = ["panda_finger_joint1", "panda_finger_joint2"]

[keyframes.rest]
qpos = {arm = [0, "pi/8", 0, "-5*pi/8", 0, "3*pi/4", "pi/4"], gripper = 0.04}
pose = {p = [0, 0, 0]}

[controllers.gripper]
type = "pd_joint_pos_mimic"
mimic = {panda_finger_joint2 = "panda_finger_joint1"}

[[collision_rules]]
links = ["l_wheel_link", "r_wheel_link"]
group = 2
"""
    result = positions(text)  # checks the path set against tomllib
    assert result[("keyframes", "rest", "qpos", "arm", 3)] == ((16, 30), (16, 30))
    assert result[("links", "panda_*finger", "material")] == ((8, 1), (8, 12))
    assert result[("description", "urdf")] == ((4, 13), (4, 20))


def test_deep_nesting_does_not_recurse() -> None:
    depth = 5000
    text = "a = " + "[" * depth + "]" * depth + "\n"
    result = toml_positions(text)
    assert len(result) == depth
    assert result[("a",) + (0,) * (depth - 1)] == ((1, depth + 4), (1, depth + 4))


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        # nothing outside the syntax error to map
        ("a = [1,\n", {}),
        ("[x\n", {}),
        ("= 3\n", {}),
        ("\x00\ud800", {}),
        # the parts before the error are mapped; the key segment or the value tree-sitter only
        # assumed (a MISSING node) is not part of any path
        pytest.param(
            "a.b. = 1\n",
            {("a",): ((1, 1), (1, 3)), ("a", "b"): ((1, 3), (1, 5))},
            id="dotted key missing its last segment",
        ),
        pytest.param(
            "a = {b = }\n",
            {("a",): ((1, 1), (1, 5))},
            id="inline pair missing its value",
        ),
        pytest.param(
            "[a.]\nb = 1\n",
            {("a",): ((1, 2), (1, 4))},
            id="table header missing its last segment",
        ),
    ],
)
def test_invalid_toml_maps_only_what_lies_outside_the_syntax_errors(
    text: str, expected: dict[Path, tuple[tuple[int, int], tuple[int, int]]]
) -> None:
    assert toml_positions(text) == expected  # and it does not raise


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("a = 1\nb = \n", (2, 5, "Invalid value")),
        ("a = 1\na = 2\n", (2, 6, "Cannot overwrite a value")),
        ('x = "é" y\n', (1, 9, "Expected newline or end of document after a statement")),
    ],
)
def test_tomllib_error_location(text: str, expected: tuple[int, int, str]) -> None:
    with pytest.raises(tomllib.TOMLDecodeError) as info:
        tomllib.loads(text)
    assert tomllib_error_location(info.value, text) == expected


def test_tomllib_error_at_end_of_document() -> None:
    class FakeError(ValueError):
        pass

    text = "a = 1\nb = [1,"
    error = FakeError("Unclosed array (at end of document)")
    assert tomllib_error_location(error, text) == (2, 8, "Unclosed array")


def test_an_error_at_the_end_after_a_final_newline_is_on_a_line_the_file_has(
    tmp_path: Any,
) -> None:
    # found by the fuzz tests: a quote opened on the first line runs to the end of the file,
    # which tomllib puts on the line after the final newline; reported at the quote (RS015),
    # and where tomllib's "end of document" is kept (a multi-line string left open: RS002
    # with tomllib's words), on the last line the file shows
    from robospec.load.reader import read_spec

    spec = tmp_path / "spec.toml"
    spec.write_text("'#:schema x\nrobospec = 1\n\n[[collision_rules]]\nbit = 5\n\n")
    _, (diagnostic,) = read_spec(spec)
    assert diagnostic.code == "RS015"
    assert (diagnostic.location.line, diagnostic.location.column) == (1, 1)
    spec.write_text('robospec = 1\nuid = """rs\n\n')
    _, (diagnostic,) = read_spec(spec)
    lines = spec.read_text().splitlines()
    assert (diagnostic.location.line, diagnostic.location.column) == (len(lines), 1)
