"""Each kind of syntax error a person makes in a YAML or TOML spec is reported as the mistake
it is, where it was made, with the fix: never in the parser's own words ("while parsing a flow
sequence expected ',' or ']', but got '<scalar>'") at the line after it.

One row per kind: the text, the code, where it is reported and words of its message or hint.
The catalogue (docs/examples/codes/, tests/test_spec_examples.py) shows the same in full specs.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from robospec.load.reader import read_spec

# (kind, file suffix, text, code, "line:column", words the message or hint holds)
MISTAKES = [
    # -- YAML
    (
        "a list never closed, the next key read as one more item",
        "yaml",
        "groups:\n  gripper: [j1, j2\ncontrollers:\n  x: 1\n",
        "RS015",
        "2:12",
        "close it with ']' after 'j2' on line 2",
    ),
    (
        "a list never closed, over several lines",
        "yaml",
        "joints: [j1,\n  j2,\n  j3\nnext: 4\n",
        "RS015",
        "1:9",
        "close it with ']' after 'j3' on line 3",
    ),
    (
        "a list never closed at the end of the file",
        "yaml",
        "robospec: 1\njoints: [j1,\n  j2",
        "RS015",
        "2:9",
        "to the end of the file, as more of the list; close it with ']' after 'j2' on line 3",
    ),
    (
        "a mapping never closed",
        "yaml",
        "description: {urdf: arm.urdf\ntcp: hand\n",
        "RS015",
        "1:14",
        "the mapping opened with '{' is never closed; close it with '}' after 'arm.urdf' on line 1",
    ),
    (
        "a list never closed inside a mapping that is",
        "yaml",
        "mimic: {a: [b, c}\nnext: 1\n",
        "RS015",
        "1:12",
        "close the list with ']' before that '}' (which closes the '{' on line 1, column 8)",
    ),
    (
        "a list closed with a brace",
        "yaml",
        "joints: [j1, j2}\nnext: 1\n",
        "RS015",
        "1:9",
        "is closed with '}' on line 1, column 16; write ']' for that '}'",
    ),
    (
        "a mapping closed with a bracket",
        "yaml",
        "pose: {p: 1]\nnext: 1\n",
        "RS015",
        "1:7",
        "write '}' for that ']'",
    ),
    (
        "a list closed twice",
        "yaml",
        "joints: [j1, j2]]\nnext: 1\n",
        "RS015",
        "1:17",
        "this ']' closes no list; delete this ']'",
    ),
    (
        "a mapping closed twice",
        "yaml",
        "pose: {p: 1}}\nnext: 1\n",
        "RS015",
        "1:13",
        "this '}' closes no mapping",
    ),
    (
        "a quoted text never closed",
        "yaml",
        'uid: "my_arm\ntcp: hand\n',
        "RS015",
        "1:6",
        "YAML reads the rest of the file as part of it; close it with '\"' after '\"my_arm'",
    ),
    (
        "a quoted text closed by the next quote, lines later",
        "yaml",
        'uid: "my_arm\ntcp: "hand"\n',
        "RS015",
        "1:6",
        "YAML reads on to the '\"' on line 2, column 6",
    ),
    (
        "a glob that starts with '*', read as an alias",
        "yaml",
        "groups:\n  arm: *joint[1-7]\n",
        "RS002",
        "2:8",
        'needs quotes: "*joint[1-7]"',
    ),
    (
        "a key indented to no level",
        "yaml",
        "groups:\n    arm: a\n  hand: b\n",
        "RS011",
        "3:3",
        "lines up with no key above it",
    ),
    (
        "a key indented under a key that has a value",
        "yaml",
        "groups:\n  arm: a\n    hand: b\n",
        "RS011",
        "3:5",
        "is indented more than 'arm' on line 2",
    ),
    ("a tab in the indentation", "yaml", "groups:\n\tarm: a\n", "RS012", "2:1", "spaces only"),
    (
        "': ' in a plain value",
        "yaml",
        "robospec: 1\ndescription: urdf: arm.urdf\n",
        "RS014",
        "2:18",
        "description: {urdf: arm.urdf}",
    ),
    (
        "a key given twice",
        "yaml",
        "uid: a\ngroups:\n  uid: x\nuid: b\n",
        "RS003",
        "4:1",
        "'uid' is given twice in the same mapping (first on line 1); keep one of them",
    ),
    # -- TOML
    (
        "an array never closed, the next key read as one more value",
        "toml",
        '[groups]\narm = ["j1", "j2"\nhand = ["j3"]\n',
        "RS015",
        "2:7",
        "on to line 3, as more of its values; close it with ']' after '\"j2\"' on line 2",
    ),
    (
        "an array never closed, over several lines",
        "toml",
        'arm = [\n  "j1",\n  "j2"\n[controllers]\n',
        "RS015",
        "1:7",
        "close it with ']' after '\"j2\"' on line 3",
    ),
    (
        "an array never closed at the end of the file",
        "toml",
        'arm = ["j1", "j2",\n',
        "RS015",
        "1:7",
        "to the end of the file",
    ),
    (
        "an inline table never closed",
        "toml",
        'pose = {p = [0, 0, 1]\nuid = "x"\n',
        "RS015",
        "1:8",
        "TOML writes an inline table on one line; close it with '}' after '1]' on line 1",
    ),
    (
        "an array closed with a brace",
        "toml",
        'arm = ["j1", "j2"}\n',
        "RS015",
        "1:7",
        "write ']' for that '}'",
    ),
    (
        "an array never closed inside an inline table that is",
        "toml",
        'mimic = {a = ["b", "c"}\n',
        "RS015",
        "1:14",
        "close the array with ']' before that '}' (which closes the '{' on line 1, column 9)",
    ),
    (
        "an array closed twice",
        "toml",
        'arm = ["j1"]]\n',
        "RS015",
        "1:13",
        "this ']' closes no array; delete this ']'",
    ),
    (
        "an inline table closed twice",
        "toml",
        "pose = {p = 1}}\n",
        "RS015",
        "1:15",
        "this '}' closes no inline table",
    ),
    (
        "a string never closed",
        "toml",
        'uid = "my_arm\ntcp = "hand"\n',
        "RS015",
        "1:7",
        "a TOML string ends on the line it starts; close it with '\"' after '\"my_arm' on line 1",
    ),
    (
        "a literal string never closed",
        "toml",
        "uid = 'my_arm\n",
        "RS015",
        "1:7",
        'close it with "\'" after',
    ),
    (
        "a table header never closed",
        "toml",
        "[groups\narm = 'j1'\n",
        "RS015",
        "1:1",
        "write [groups]",
    ),
    (
        "an array-of-tables header never closed",
        "toml",
        "[[parts]\nspec = 'hand.yaml'\n",
        "RS015",
        "1:1",
        "write [[parts]]",
    ),
    (
        "values of an array without ',' between them",
        "toml",
        'arm = ["j1" "j2"]\n',
        "RS002",
        "1:13",
        "a ',' is missing before this value; write ',' after '\"j1\"'",
    ),
    (
        "an inline table over several lines",
        "toml",
        "pose = {\n  p = [0, 0, 1] }\n",
        "RS002",
        "1:8",
        "TOML writes an inline table on one line",
    ),
    (
        "a key and its value written with ':', as in YAML",
        "toml",
        'robospec = 1\nuid: "my_arm"\n',
        "RS002",
        "2:4",
        'write uid = "my_arm"',
    ),
    (
        "text without quotes",
        "toml",
        "tcp = hand\n",
        "RS013",
        "1:7",
        'write tcp = "hand"',
    ),
    (
        "a key given twice",
        "toml",
        "uid = 'a'\n[groups]\nuid = 'x'\nuid = 'b'\n",
        "RS003",
        "4:1",
        "'uid' is given twice in the same table (first on line 3)",
    ),
    (
        "a table declared twice",
        "toml",
        "[groups]\narm = 'a'\n[groups]\nhand = 'b'\n",
        "RS003",
        "3:1",
        "the table [groups] is declared twice (first on line 1)",
    ),
]


@pytest.mark.parametrize(
    ("suffix", "text", "code", "where", "words"),
    [row[1:] for row in MISTAKES],
    ids=[f"{row[1]}: {row[0]}" for row in MISTAKES],
)
def test_each_syntax_mistake_is_told_as_itself_where_it_was_made(
    tmp_path: Path, suffix: str, text: str, code: str, where: str, words: str
) -> None:
    spec = tmp_path / f"spec.{suffix}"
    spec.write_text(text, encoding="utf-8")
    loaded, diagnostics = read_spec(spec)
    assert loaded is None
    (diagnostic,) = diagnostics
    said = f"{diagnostic.message}; {diagnostic.hint}"
    assert (diagnostic.code, f"{diagnostic.location.line}:{diagnostic.location.column}") == (
        code,
        where,
    ), said
    for part in words.split("; "):
        assert part in said, said
    assert diagnostic.hint, said
    # the parser's own words stay out of it
    for parser_words in ("while parsing", "but got", "Unclosed", "Invalid value"):
        assert parser_words not in said, said


def test_a_quote_never_closed_after_a_lone_carriage_return_is_rs015_on_the_line_yaml_counts(
    tmp_path: Path,
) -> None:
    """YAML (and ruamel.yaml's marks) count a lone carriage return as a line break: the quote
    opened after one is on line 2 (the hint once read the text's lines by newline alone and
    raised IndexError)."""
    spec = tmp_path / "spec.yaml"
    spec.write_bytes(b"robospec: 1\r'open")
    loaded, diagnostics = read_spec(spec)
    assert loaded is None
    (diagnostic,) = diagnostics
    assert (diagnostic.code, diagnostic.location.line, diagnostic.location.column) == (
        "RS015",
        2,
        1,
    ), diagnostic.format_text()
