"""yaml-language-server (the engine behind VS Code's YAML extension and most LSP editors) driven
over the Language Server Protocol with schemas/robospec.schema.json: what a user typing a spec
sees — diagnostics at the right place, completion of keys, enum values and, with the schema
narrowed to one robot (`robospec schema --for`), that robot's joint names.

The client is pytest-lsp's (pygls underneath): it starts the server over stdio, answers its
``workspace/configuration`` requests from the settings below, and keeps what it publishes. Every
wait is bounded (TIMEOUT_S), so a hung server fails the test instead of hanging CI.

Positions are LSP's: 0-based lines and columns.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Sequence
from pathlib import Path
from typing import Any

import pytest
import pytest_asyncio
from conftest import PANDA_SPEC, ROOT, SCHEMA, sample_fast, spec_params
from editor_engines import narrowed_schema, yaml_language_server_argv
from lsprotocol import types
from pygls.protocol import default_converter
from pytest_lsp import LanguageClient
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, configuration, register_lsp_features

from robospec.model.controller_kinds import CONTROLLER_TYPES as CONTROLLER_TYPE_NAMES

pytestmark = pytest.mark.asyncio(loop_scope="module")

YAML_SPECS = sorted((ROOT / "specs").rglob("*.yaml"))
PANDA_JOINTS = {f"panda_joint{i}" for i in range(1, 8)} | {
    "panda_finger_joint1",
    "panda_finger_joint2",
}
CONTROLLER_TYPES = set(CONTROLLER_TYPE_NAMES)
# files under this folder get the schema from the yaml.schemas setting, not from a modeline
SETTINGS_MAPPED_GLOB = "**/mapped-by-settings/*.yaml"
SETTINGS = {
    "validate": True,
    "completion": True,
    "hover": False,
    # offline and deterministic: no schemastore.org catalog
    "schemaStore": {"enable": False},
    "schemas": {SCHEMA.as_uri(): [SETTINGS_MAPPED_GLOB]},
}
TIMEOUT_S = 30.0
CAPABILITIES = types.ClientCapabilities(
    workspace=types.WorkspaceClientCapabilities(
        configuration=True,
        did_change_configuration=types.DidChangeConfigurationClientCapabilities(),
    ),
    text_document=types.TextDocumentClientCapabilities(
        completion=types.CompletionClientCapabilities(
            # as VS Code declares them (pytest-lsp warns when a server sends what the client
            # did not declare)
            completion_item=types.ClientCompletionItemOptions(
                snippet_support=True,
                documentation_format=[types.MarkupKind.Markdown, types.MarkupKind.PlainText],
            )
        ),
        publish_diagnostics=types.PublishDiagnosticsClientCapabilities(related_information=False),
    ),
)


class Client(LanguageClient):
    """pytest-lsp's client, counting the settings the server has pulled: the server reads them
    (workspace/configuration) once initialized, and documents opened before that would be
    checked without the yaml.schemas mapping."""

    def __init__(self) -> None:
        super().__init__(converter_factory=default_converter)
        self.configuration_pulled = asyncio.Event()

        def pulled(client: Client, params: types.ConfigurationParams) -> list[Any]:
            client.configuration_pulled.set()
            return configuration(client, params)

        register_lsp_features(
            self, {**DEFAULT_CLIENT_FEATURES, types.WORKSPACE_CONFIGURATION: pulled}
        )

    def open(self, path: Path, text: str | None = None) -> str:
        """Open ``path`` (its contents, or ``text``) as the editor would; returns its URI."""
        uri = path.resolve().as_uri()
        self.text_document_did_open(
            types.DidOpenTextDocumentParams(
                text_document=types.TextDocumentItem(
                    uri=uri,
                    language_id="yaml",
                    version=1,
                    text=path.read_text() if text is None else text,
                )
            )
        )
        return uri

    async def diagnostics_of(self, uri: str) -> Sequence[types.Diagnostic]:
        """What the server publishes for ``uri``."""

        async def published() -> Sequence[types.Diagnostic]:
            while uri not in self.diagnostics:
                await self.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
            return self.diagnostics[uri]

        return await asyncio.wait_for(published(), TIMEOUT_S)

    async def completion_labels(self, uri: str, line: int, character: int) -> set[str]:
        """Labels of the completion items at a 0-based position."""
        result = await asyncio.wait_for(
            self.text_document_completion_async(
                types.CompletionParams(
                    text_document=types.TextDocumentIdentifier(uri=uri),
                    position=types.Position(line=line, character=character),
                )
            ),
            TIMEOUT_S,
        )
        items = result.items if isinstance(result, types.CompletionList) else result or []
        return {item.label for item in items}


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def server(tmp_path_factory: pytest.TempPathFactory) -> AsyncIterator[Client]:
    workspace = tmp_path_factory.mktemp("yaml-workspace")
    client = Client()
    client.set_configuration(SETTINGS, section="yaml")
    await client.start_io(*yaml_language_server_argv(), cwd=workspace)
    try:
        await asyncio.wait_for(
            client.initialize_session(
                types.InitializeParams(
                    capabilities=CAPABILITIES,
                    root_uri=workspace.as_uri(),
                    workspace_folders=[
                        types.WorkspaceFolder(uri=workspace.as_uri(), name=workspace.name)
                    ],
                )
            ),
            TIMEOUT_S,
        )
        await asyncio.wait_for(client.configuration_pulled.wait(), TIMEOUT_S)
        yield client
        await asyncio.wait_for(client.shutdown_session(), TIMEOUT_S)
    finally:
        await client.stop()


def write_spec(path: Path, body: str, schema: Path = SCHEMA) -> Path:
    """A spec at ``path`` whose modeline points at ``schema``; ``body`` starts on line 1."""
    path.write_text(f"# yaml-language-server: $schema={schema.as_uri()}\n{body}")
    return path


def errors(diagnostics: Sequence[types.Diagnostic]) -> list[types.Diagnostic]:
    return [d for d in diagnostics if d.severity in (None, types.DiagnosticSeverity.Error)]


def starts(diagnostics: Sequence[types.Diagnostic]) -> dict[tuple[int, int], str]:
    """Each diagnostic's start as (line, column) -> its message."""
    return {(d.range.start.line, d.range.start.character): d.message for d in diagnostics}


async def test_unknown_key_is_flagged_at_the_key(server: Client, tmp_path: Path) -> None:
    spec = write_spec(
        tmp_path / "unknown_key.yaml",
        "robospec: 1\nuid: demo\ndescription:\n  urdf: arm.urdf\nloader:\n  fix_root_lnk: true\n",
    )
    found = starts(errors(await server.diagnostics_of(server.open(spec))))
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
async def test_wrong_type_is_flagged_at_the_value(
    server: Client, tmp_path: Path, body: str, value_at: tuple[int, int]
) -> None:
    spec = write_spec(tmp_path / "wrong_type.yaml", body)
    found = starts(errors(await server.diagnostics_of(server.open(spec))))
    assert value_at in found, found


# every spec in the full suite; the fast loop opens a sample
@pytest.mark.parametrize(
    "spec",
    sample_fast(spec_params(YAML_SPECS, ROOT), {PANDA_SPEC, ROOT / "specs/maniskill/fetch.yaml"}),
)
async def test_repo_spec_has_no_errors_through_its_own_modeline(server: Client, spec: Path) -> None:
    assert PANDA_SPEC in YAML_SPECS
    found = starts(errors(await server.diagnostics_of(server.open(spec))))
    assert not found, found


async def test_panda_modeline_reaches_the_schema(server: Client) -> None:
    # the same text with one unknown key, at a sibling URI so the relative modeline resolves the
    # same way: proves the clean result above comes from a schema that was found and applied
    edited = PANDA_SPEC.read_text().replace("\nuid:", "\nuid_typo: 1\nuid:", 1)
    uri = server.open(PANDA_SPEC.with_name("_edited_panda.yaml"), text=edited)
    messages = [d.message for d in errors(await server.diagnostics_of(uri))]
    assert any("uid_typo" in message for message in messages), messages


async def test_yaml_schemas_setting_applies_the_schema_without_a_modeline(
    server: Client, tmp_path: Path
) -> None:
    folder = tmp_path / "mapped-by-settings"
    folder.mkdir()
    spec = folder / "no_modeline.yaml"
    spec.write_text("robospec: 1\nuid: 3\n")
    found = starts(errors(await server.diagnostics_of(server.open(spec))))
    assert (1, 5) in found, found


async def test_completion_at_a_blank_top_level_line_offers_spec_keys(
    server: Client, tmp_path: Path
) -> None:
    spec = write_spec(tmp_path / "keys.yaml", "robospec: 1\n\ndescription:\n  urdf: arm.urdf\n")
    uri = server.open(spec)
    await server.diagnostics_of(uri)
    offered = await server.completion_labels(uri, 2, 0)
    assert {"uid", "controllers", "control_modes", "keyframes", "groups", "cameras"} <= offered
    assert "robospec" not in offered  # already written above


async def test_completion_of_controller_type_offers_every_controller_type(
    server: Client, tmp_path: Path
) -> None:
    spec = write_spec(
        tmp_path / "enum.yaml", "robospec: 1\nuid: demo\ncontrollers:\n  arm:\n    type: \n"
    )
    uri = server.open(spec)
    await server.diagnostics_of(uri)
    assert await server.completion_labels(uri, 5, 10) >= CONTROLLER_TYPES


@pytest.fixture(scope="module")
def panda_schema(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The schema narrowed to the Panda by `robospec schema --for`."""
    return narrowed_schema(PANDA_SPEC, tmp_path_factory.mktemp("narrowed") / "panda.schema.json")


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
async def test_narrowed_schema_completes_joint_names_in_keyframe_qpos(
    server: Client, panda_schema: Path, tmp_path: Path
) -> None:
    spec = write_spec(
        tmp_path / "qpos.yaml",
        "robospec: 1\nuid: demo\nkeyframes:\n  rest:\n    qpos:\n      \n",
        schema=panda_schema,
    )
    uri = server.open(spec)
    await server.diagnostics_of(uri)
    assert await server.completion_labels(uri, 6, 6) >= PANDA_JOINTS


async def test_narrowed_schema_completes_joint_names_in_a_group_list(
    server: Client, panda_schema: Path, tmp_path: Path
) -> None:
    spec = write_spec(
        tmp_path / "group.yaml",
        "robospec: 1\nuid: demo\ngroups:\n  fingers:\n    - \n",
        schema=panda_schema,
    )
    uri = server.open(spec)
    await server.diagnostics_of(uri)
    assert await server.completion_labels(uri, 5, 6) >= PANDA_JOINTS


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
async def test_narrowed_schema_flags_a_misspelled_name_at_the_name(
    server: Client,
    panda_schema: Path,
    tmp_path: Path,
    body: str,
    name_at: tuple[int, int],
    named: str,
) -> None:
    spec = write_spec(
        tmp_path / "typo.yaml", f"robospec: 1\nuid: demo\n{body}", schema=panda_schema
    )
    found = starts(errors(await server.diagnostics_of(server.open(spec))))
    assert name_at in found, found
    # the message names the typo ("Property x is not allowed") or the real names to pick from
    assert named in found[name_at], found


async def test_narrowed_schema_accepts_the_panda_spec(server: Client, panda_schema: Path) -> None:
    # the Panda's own text, its modeline swapped for the narrowed schema
    text = PANDA_SPEC.read_text().split("\n", 1)[1]
    uri = server.open(
        PANDA_SPEC.with_name("_narrowed_panda.yaml"),
        text=f"# yaml-language-server: $schema={panda_schema.as_uri()}\n{text}",
    )
    found = starts(errors(await server.diagnostics_of(uri)))
    assert not found, found
