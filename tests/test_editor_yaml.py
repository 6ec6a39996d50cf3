"""yaml-language-server (the engine behind VS Code's YAML extension and most LSP editors) driven
over the Language Server Protocol with schemas/robospec.schema.json: what a user typing a spec
sees — diagnostics at the right place, completion of keys, enum values and, with the schema
narrowed to one robot (`robospec schema --for`), that robot's joint names.

Positions are LSP's: 0-based lines and columns.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import PANDA_SPEC, ROOT, SCHEMA
from editor_engines import narrowed_schema, yaml_language_server_argv
from lsp_client import JsonObject, LspClient

from robospec.model.rules import CONTROLLER_TYPES as CONTROLLER_TYPE_NAMES

YAML_SPECS = sorted((ROOT / "specs").rglob("*.yaml"))
PANDA_JOINTS = {f"panda_joint{i}" for i in range(1, 8)} | {
    "panda_finger_joint1",
    "panda_finger_joint2",
}
CONTROLLER_TYPES = set(CONTROLLER_TYPE_NAMES)
# files under this folder get the schema from the yaml.schemas setting, not from a modeline
SETTINGS_MAPPED_GLOB = "**/mapped-by-settings/*.yaml"
ERROR = 1  # LSP DiagnosticSeverity.Error


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LspClient]:
    workspace = tmp_path_factory.mktemp("yaml-workspace")
    client = LspClient(yaml_language_server_argv(), cwd=workspace)
    try:
        client.initialize(workspace)
        client.configure(
            {
                "yaml": {
                    "validate": True,
                    "completion": True,
                    "hover": False,
                    # offline and deterministic: no schemastore.org catalog
                    "schemaStore": {"enable": False},
                    "schemas": {SCHEMA.as_uri(): [SETTINGS_MAPPED_GLOB]},
                }
            }
        )
        yield client
    finally:
        client.close()


def write_spec(path: Path, body: str, schema: Path = SCHEMA) -> Path:
    """A spec at ``path`` whose modeline points at ``schema``; ``body`` starts on line 1."""
    path.write_text(f"# yaml-language-server: $schema={schema.as_uri()}\n{body}")
    return path


def errors(diagnostics: list[JsonObject]) -> list[JsonObject]:
    return [d for d in diagnostics if d.get("severity", ERROR) == ERROR]


def starts(diagnostics: list[JsonObject]) -> dict[tuple[int, int], str]:
    """Each diagnostic's start as (line, column) -> its message."""
    return {
        (d["range"]["start"]["line"], d["range"]["start"]["character"]): d["message"]
        for d in diagnostics
    }


def labels(items: list[JsonObject]) -> set[str]:
    return {item["label"] for item in items}


def test_unknown_key_is_flagged_at_the_key(server: LspClient, tmp_path: Path) -> None:
    spec = write_spec(
        tmp_path / "unknown_key.yaml",
        "robospec: 1\nuid: demo\ndescription:\n  urdf: arm.urdf\nloader:\n  fix_root_lnk: true\n",
    )
    found = starts(errors(server.diagnostics(server.open(spec, "yaml"))))
    assert (6, 2) in found, found
    assert "fix_root_lnk" in found[(6, 2)]


@pytest.mark.parametrize(
    ("body", "value_at"),
    [
        ("robospec: 1\nuid: 3\n", (2, 5)),
        ('robospec: "x"\nuid: demo\n', (1, 10)),
        (
            "robospec: 1\nuid: demo\ncontrollers:\n  arm:\n    type: pd_joint_pos\n"
            "    joints: arm\n    lower: -1\n    upper: 1\n    stiffness: hard\n    damping: 10\n",
            (9, 15),
        ),
    ],
    ids=["uid-number", "robospec-string", "stiffness-word"],
)
def test_wrong_type_is_flagged_at_the_value(
    server: LspClient, tmp_path: Path, body: str, value_at: tuple[int, int]
) -> None:
    spec = write_spec(tmp_path / "wrong_type.yaml", body)
    found = starts(errors(server.diagnostics(server.open(spec, "yaml"))))
    assert value_at in found, found


@pytest.mark.parametrize("spec", YAML_SPECS, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_repo_spec_has_no_errors_through_its_own_modeline(server: LspClient, spec: Path) -> None:
    assert PANDA_SPEC in YAML_SPECS
    found = starts(errors(server.diagnostics(server.open(spec, "yaml"))))
    assert not found, found


def test_panda_modeline_reaches_the_schema(server: LspClient) -> None:
    # the same text with one unknown key, at a sibling URI so the relative modeline resolves the
    # same way: proves the clean result above comes from a schema that was found and applied
    edited = PANDA_SPEC.read_text().replace("\nuid:", "\nuid_typo: 1\nuid:", 1)
    uri = server.open(PANDA_SPEC.with_name("_edited_panda.yaml"), "yaml", text=edited)
    messages = [d["message"] for d in errors(server.diagnostics(uri))]
    assert any("uid_typo" in message for message in messages), messages


def test_yaml_schemas_setting_applies_the_schema_without_a_modeline(
    server: LspClient, tmp_path: Path
) -> None:
    folder = tmp_path / "mapped-by-settings"
    folder.mkdir()
    spec = folder / "no_modeline.yaml"
    spec.write_text("robospec: 1\nuid: 3\n")
    found = starts(errors(server.diagnostics(server.open(spec, "yaml"))))
    assert (1, 5) in found, found


def test_completion_at_a_blank_top_level_line_offers_spec_keys(
    server: LspClient, tmp_path: Path
) -> None:
    spec = write_spec(tmp_path / "keys.yaml", "robospec: 1\n\ndescription:\n  urdf: arm.urdf\n")
    uri = server.open(spec, "yaml")
    server.diagnostics(uri)
    offered = labels(server.completion(uri, 2, 0))
    assert {"uid", "controllers", "control_modes", "keyframes", "groups", "cameras"} <= offered
    assert "robospec" not in offered  # already written above


def test_completion_of_controller_type_offers_every_controller_type(
    server: LspClient, tmp_path: Path
) -> None:
    spec = write_spec(
        tmp_path / "enum.yaml", "robospec: 1\nuid: demo\ncontrollers:\n  arm:\n    type: \n"
    )
    uri = server.open(spec, "yaml")
    server.diagnostics(uri)
    assert labels(server.completion(uri, 5, 10)) >= CONTROLLER_TYPES


@pytest.fixture(scope="module")
def panda_schema(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The schema narrowed to the Panda by `robospec schema --for`."""
    return narrowed_schema(PANDA_SPEC, tmp_path_factory.mktemp("narrowed") / "panda.schema.json")


def test_narrowed_schema_completes_joint_names_in_keyframe_qpos(
    server: LspClient, panda_schema: Path, tmp_path: Path
) -> None:
    spec = write_spec(
        tmp_path / "qpos.yaml",
        "robospec: 1\nuid: demo\nkeyframes:\n  rest:\n    qpos:\n      \n",
        schema=panda_schema,
    )
    uri = server.open(spec, "yaml")
    server.diagnostics(uri)
    assert labels(server.completion(uri, 6, 6)) >= PANDA_JOINTS


def test_narrowed_schema_completes_joint_names_in_a_group_list(
    server: LspClient, panda_schema: Path, tmp_path: Path
) -> None:
    spec = write_spec(
        tmp_path / "group.yaml",
        "robospec: 1\nuid: demo\ngroups:\n  fingers:\n    - \n",
        schema=panda_schema,
    )
    uri = server.open(spec, "yaml")
    server.diagnostics(uri)
    assert labels(server.completion(uri, 5, 6)) >= PANDA_JOINTS


@pytest.mark.parametrize(
    ("body", "name_at", "named"),
    [
        pytest.param(
            "keyframes:\n  rest:\n    qpos: {panda_joint8: 0}\n",
            (5, 11),
            "panda_joint8",
            id="keyframe-qpos-flow",
        ),
        pytest.param(
            "keyframes:\n  rest:\n    qpos:\n      panda_joint8: 0\n",
            (6, 6),
            "panda_joint8",
            id="keyframe-qpos-block",
        ),
        pytest.param(
            "groups:\n  arm: [panda_joint1, panda_jointX]\n",
            (4, 22),
            "panda_joint1",
            id="group-list",
        ),
        pytest.param(
            "controllers:\n  a:\n    type: pd_joint_pos\n    joints: [panda_jointX]\n",
            (6, 13),
            "panda_joint1",
            id="controller-joints",
        ),
        pytest.param("tcp: panda_handX\n", (3, 5), "panda_hand_tcp", id="tcp-link"),
        pytest.param(
            "links:\n  panda_handX: {patch_radius: 0.1}\n", (4, 2), "panda_handX", id="link-rule"
        ),
        pytest.param(
            "control_modes:\n  m: {arm: arm_posX}\n", (4, 11), "arm_pos", id="mode-controller"
        ),
    ],
)
def test_narrowed_schema_flags_a_misspelled_name_at_the_name(
    server: LspClient,
    panda_schema: Path,
    tmp_path: Path,
    body: str,
    name_at: tuple[int, int],
    named: str,
) -> None:
    spec = write_spec(
        tmp_path / "typo.yaml", f"robospec: 1\nuid: demo\n{body}", schema=panda_schema
    )
    found = starts(errors(server.diagnostics(server.open(spec, "yaml"))))
    assert name_at in found, found
    # the message names the typo ("Property x is not allowed") or the real names to pick from
    assert named in found[name_at], found


def test_narrowed_schema_accepts_the_panda_spec(server: LspClient, panda_schema: Path) -> None:
    # the Panda's own text, its modeline swapped for the narrowed schema
    text = PANDA_SPEC.read_text().split("\n", 1)[1]
    uri = server.open(
        PANDA_SPEC.with_name("_narrowed_panda.yaml"),
        "yaml",
        text=f"# yaml-language-server: $schema={panda_schema.as_uri()}\n{text}",
    )
    found = starts(errors(server.diagnostics(uri)))
    assert not found, found
