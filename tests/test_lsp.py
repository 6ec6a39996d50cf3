"""`robospec lsp` end to end: a real Language Server Protocol client (pytest-lsp's) starts
`python -m robospec lsp` over stdio and does what an editor does — opens a spec, types into it
without saving, asks for completion, hover and definition, edits the URDF on disk.

One server serves the module (starting it costs a second); each test opens its own files under
tmp_path, so tests do not see each other's documents. Every wait is bounded (TIMEOUT_S).
Positions are LSP's: 0-based lines and columns.
"""

from __future__ import annotations

import asyncio
import shutil
import subprocess
import sys
from collections.abc import AsyncIterator, Callable, Sequence
from pathlib import Path

import pytest
import pytest_asyncio
from conftest import CODE_EXAMPLES, PANDA_SPEC, ROOT
from lsprotocol import types
from pytest_lsp import LanguageClient
from pytest_lsp.client import make_test_lsp_client

pytestmark = pytest.mark.asyncio(loop_scope="module")

TIMEOUT_S = 20.0
PANDA_TEXT = PANDA_SPEC.read_text()
GRIPPER_LINE = "  gripper: [panda_finger_joint1, panda_finger_joint2]"
CAPABILITIES = types.ClientCapabilities(
    workspace=types.WorkspaceClientCapabilities(
        did_change_watched_files=types.DidChangeWatchedFilesClientCapabilities(
            dynamic_registration=True
        )
    ),
    text_document=types.TextDocumentClientCapabilities(
        completion=types.CompletionClientCapabilities(
            completion_item=types.ClientCompletionItemOptions(
                documentation_format=[types.MarkupKind.Markdown, types.MarkupKind.PlainText]
            )
        ),
        hover=types.HoverClientCapabilities(
            content_format=[types.MarkupKind.Markdown, types.MarkupKind.PlainText]
        ),
    ),
)


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def client() -> AsyncIterator[LanguageClient]:
    lsp = make_test_lsp_client()
    registered: list[types.Registration] = []

    @lsp.feature(types.CLIENT_REGISTER_CAPABILITY)
    def register(params: types.RegistrationParams) -> None:
        # the server asks to be told of description files that change (the editor's watcher)
        registered.extend(params.registrations)

    await lsp.start_io(sys.executable, "-m", "robospec", "lsp", cwd=ROOT)
    try:
        await asyncio.wait_for(
            lsp.initialize_session(types.InitializeParams(capabilities=CAPABILITIES)), TIMEOUT_S
        )
        yield lsp
        await asyncio.wait_for(lsp.shutdown_session(), TIMEOUT_S)
    finally:
        await lsp.stop()


# -- helpers -----------------------------------------------------------------------------------


def open_doc(client: LanguageClient, path: Path, text: str | None = None) -> str:
    """Open ``path`` as an editor would, with ``text`` (unsaved) or the file's contents."""
    uri = path.resolve().as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(
                uri=uri,
                language_id="yaml" if path.suffix != ".toml" else "toml",
                version=1,
                text=path.read_text() if text is None else text,
            )
        )
    )
    return uri


def change(client: LanguageClient, uri: str, text: str, version: int) -> None:
    """Replace the buffer's whole text (not saved)."""
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )


async def diagnostics_until(
    client: LanguageClient, uri: str, ready: Callable[[Sequence[types.Diagnostic]], bool]
) -> Sequence[types.Diagnostic]:
    """The diagnostics published for ``uri`` once ``ready`` says they are the awaited ones."""

    async def wait() -> Sequence[types.Diagnostic]:
        while uri not in client.diagnostics or not ready(client.diagnostics[uri]):
            await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        return list(client.diagnostics[uri])

    return await asyncio.wait_for(wait(), TIMEOUT_S)


def codes(diagnostics: Sequence[types.Diagnostic]) -> list[str]:
    return [str(d.code) for d in diagnostics]


def position_of(text: str, needle: str, offset: int = 0) -> types.Position:
    """Where ``needle`` (plus ``offset`` characters) first stands in ``text``."""
    index = text.index(needle) + offset
    line = text.count("\n", 0, index)
    return types.Position(line=line, character=index - (text.rfind("\n", 0, index) + 1))


async def labels(client: LanguageClient, uri: str, position: types.Position) -> set[str]:
    result = await asyncio.wait_for(
        client.text_document_completion_async(
            types.CompletionParams(
                text_document=types.TextDocumentIdentifier(uri=uri), position=position
            )
        ),
        TIMEOUT_S,
    )
    items = result.items if isinstance(result, types.CompletionList) else result or []
    return {item.label for item in items}


async def hover(client: LanguageClient, uri: str, position: types.Position) -> str:
    result = await asyncio.wait_for(
        client.text_document_hover_async(
            types.HoverParams(
                text_document=types.TextDocumentIdentifier(uri=uri), position=position
            )
        ),
        TIMEOUT_S,
    )
    assert result is not None
    assert isinstance(result.contents, types.MarkupContent)
    return result.contents.value


async def definition(client: LanguageClient, uri: str, position: types.Position) -> types.Location:
    result = await asyncio.wait_for(
        client.text_document_definition_async(
            types.DefinitionParams(
                text_document=types.TextDocumentIdentifier(uri=uri), position=position
            )
        ),
        TIMEOUT_S,
    )
    assert isinstance(result, types.Location), result
    return result


def panda_copy(tmp_path: Path) -> Path:
    """The ManiSkill Panda spec, copied (its description is in ManiSkill's assets)."""
    path = tmp_path / "panda.yaml"
    path.write_text(PANDA_TEXT)
    return path


TWO_JOINT_URDF = """<?xml version="1.0"?>
<robot name="tiny">
  <link name="base"/>
  <link name="upper"><inertial><mass value="1.5"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="lower"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="lower"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
</robot>
"""

TINY_SPEC = """robospec: 1
uid: rs_tiny
description:
  urdf: tiny.urdf
groups:
  arm: [shoulder, elbow]
controllers:
  arm_pos: {type: pd_joint_pos, joints: arm, lower: -1, upper: 1, stiffness: 100, damping: 10}
control_modes:
  pd_joint_pos: {arm: arm_pos}
"""


def tiny_robot(tmp_path: Path) -> tuple[Path, Path]:
    urdf = tmp_path / "tiny.urdf"
    urdf.write_text(TWO_JOINT_URDF)
    spec = tmp_path / "tiny.yaml"
    spec.write_text(TINY_SPEC)
    return spec, urdf


# -- diagnostics -------------------------------------------------------------------------------


async def test_a_misspelled_joint_in_an_unsaved_buffer_is_flagged_on_its_line_with_its_code(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = panda_copy(tmp_path)
    uri = open_doc(client, spec)
    assert await diagnostics_until(client, uri, lambda ds: True) == []
    typed = PANDA_TEXT.replace(GRIPPER_LINE, GRIPPER_LINE.replace("joint1", "joint9"))
    change(client, uri, typed, 2)  # the file on disk still has the right name
    found = await diagnostics_until(client, uri, lambda ds: bool(ds))
    assert codes(found) == ["RS201"]
    (diagnostic,) = found
    at = position_of(typed, "panda_finger_joint9")
    assert diagnostic.range.start == at
    assert diagnostic.range.end.character == at.character + len("panda_finger_joint9")
    assert diagnostic.severity == types.DiagnosticSeverity.Error
    assert "hint: did you mean" in diagnostic.message
    assert diagnostic.code_description is not None
    assert diagnostic.code_description.href.endswith("docs/codes/RS201.md")
    # typing the right name again clears it
    change(client, uri, PANDA_TEXT, 3)
    assert await diagnostics_until(client, uri, lambda ds: not ds) == []


async def test_a_problem_in_the_urdf_is_published_for_the_urdf(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec, urdf = tiny_robot(tmp_path)
    broken = TWO_JOINT_URDF.replace('<parent link="upper"/>', '<parent link="uper"/>')
    urdf.write_text(broken)
    open_doc(client, spec)
    found = await diagnostics_until(client, urdf.resolve().as_uri(), lambda ds: bool(ds))
    assert codes(found) == ["RS052"]
    assert found[0].range.start.line == broken.split("\n").index(
        '    <parent link="uper"/><child link="lower"/><axis xyz="0 0 1"/>'
    )
    assert "unknown parent link 'uper'" in found[0].message


async def test_a_mend_is_published_as_information_at_the_element_it_changed(
    client: LanguageClient, tmp_path: Path
) -> None:
    folder = tmp_path / "robot"
    shutil.copytree(CODE_EXAMPLES / "RS706", folder)
    open_doc(client, folder / "fail.yaml")
    urdf = (folder / "skewed.urdf").resolve().as_uri()
    found = await diagnostics_until(client, urdf, lambda ds: bool(ds))
    assert codes(found) == ["RS706"]
    assert found[0].severity == types.DiagnosticSeverity.Information
    assert found[0].range.start.line == 6  # the <inertia> element, line 7


async def test_a_urdf_edited_on_disk_updates_diagnostics_and_completions(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec, urdf = tiny_robot(tmp_path)
    uri = open_doc(client, spec)
    assert await diagnostics_until(client, uri, lambda ds: True) == []
    at = position_of(TINY_SPEC, "[shoulder", 1)
    assert {"shoulder", "elbow", "arm"} <= await labels(client, uri, at)
    # the URDF's elbow is renamed on disk while the spec stays open, as another tool would
    urdf.write_text(TWO_JOINT_URDF.replace('"elbow"', '"knee"'))
    assert "knee" in await labels(client, uri, at)  # completion compiles what changed
    client.workspace_did_change_watched_files(
        types.DidChangeWatchedFilesParams(
            changes=[
                types.FileEvent(uri=urdf.resolve().as_uri(), type=types.FileChangeType.Changed)
            ]
        )
    )
    found = await diagnostics_until(client, uri, lambda ds: "RS201" in codes(ds))
    assert any("'elbow'" in d.message for d in found)


async def test_saving_the_urdf_republishes_the_diagnostics_of_the_specs_that_read_it(
    client: LanguageClient, tmp_path: Path
) -> None:
    """An editor that saves the URDF it has open sends didSave (no file watcher involved):
    the specs that read it are compiled again and their diagnostics published."""
    spec, urdf = tiny_robot(tmp_path)
    uri = open_doc(client, spec)
    assert await diagnostics_until(client, uri, lambda ds: True) == []
    urdf.write_text(TWO_JOINT_URDF.replace('"elbow"', '"knee"'))  # as the editor saves it
    client.text_document_did_save(
        types.DidSaveTextDocumentParams(
            text_document=types.TextDocumentIdentifier(uri=urdf.resolve().as_uri())
        )
    )
    found = await diagnostics_until(client, uri, lambda ds: "RS201" in codes(ds))
    assert any("'elbow'" in d.message for d in found)


# -- completion --------------------------------------------------------------------------------


async def test_completion_offers_the_robots_joints_and_groups_in_a_group(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = panda_copy(tmp_path)
    typed = PANDA_TEXT.replace(GRIPPER_LINE, "  gripper: [panda_finger_joint1, panda_f]")
    uri = open_doc(client, spec, typed)
    found = await labels(client, uri, position_of(typed, "panda_f]", 7))
    assert {f"panda_joint{i}" for i in range(1, 8)} <= found
    assert {"panda_finger_joint1", "panda_finger_joint2", "arm"} <= found
    assert "panda_hand" not in found  # a link is no joint


@pytest.mark.parametrize(
    ("before", "after", "expected", "absent"),
    [
        ("tcp: panda_hand_tcp", "tcp: ", {"panda_hand_tcp", "panda_link0"}, {"panda_joint1"}),
        (
            "pd_joint_pos: {arm: arm_pos,",
            "pd_joint_pos: {arm: ,",
            {"arm_pos", "arm_delta_pos", "gripper"},
            {"panda_joint1"},
        ),
        ("{material: gripper,", "{material: ,", {"gripper"}, set()),
        ("type: pd_joint_pos_mimic", "type: ", {"pd_joint_pos", "pd_ee_pose", "passive"}, set()),
    ],
    ids=["tcp-links", "mode-controllers", "materials", "controller-types"],
)
async def test_completion_offers_the_names_the_place_takes(
    client: LanguageClient,
    tmp_path: Path,
    before: str,
    after: str,
    expected: set[str],
    absent: set[str],
) -> None:
    spec = panda_copy(tmp_path)
    typed = PANDA_TEXT.replace(before, after, 1)
    uri = open_doc(client, spec, typed)
    found = await labels(client, uri, position_of(typed, after, len(after.rstrip(","))))
    assert expected <= found
    assert not absent & found


async def test_completion_offers_the_fields_of_the_controllers_type_as_keys(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = panda_copy(tmp_path)
    typed = PANDA_TEXT.replace(
        "    force_limit: 100\n    mimic:", "    force_limit: 100\n    nor\n    mimic:"
    )
    uri = open_doc(client, spec, typed)
    found = await labels(client, uri, position_of(typed, "    nor\n", 7))
    assert {"normalize_action", "drive_mode", "use_delta"} <= found
    assert "stiffness" not in found  # already given
    assert "ee_link" not in found  # a field of the EE controllers, not of pd_joint_pos_mimic


async def test_completion_in_a_toml_spec_offers_its_robots_joints(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = tmp_path / "tiny.toml"
    tiny_robot(tmp_path)
    text = (
        'robospec = 1\nuid = "rs_tiny"\n[description]\nurdf = "tiny.urdf"\n[groups]\narm = ["sh"]\n'
    )
    spec.write_text(text)
    uri = open_doc(client, spec)
    assert {"shoulder", "elbow"} <= await labels(client, uri, position_of(text, '"sh"', 3))


async def test_completion_of_a_half_typed_bare_toml_value_offers_the_robots_links(
    client: LanguageClient, tmp_path: Path
) -> None:
    """`tcp = up|`: no quotes typed yet (TOML needs them, so the line does not parse): the
    link names still come, each to be written as a string."""
    spec = tmp_path / "tiny.toml"
    tiny_robot(tmp_path)
    text = 'robospec = 1\nuid = "rs_tiny"\ntcp = up\n[description]\nurdf = "tiny.urdf"\n'
    spec.write_text(text)
    uri = open_doc(client, spec)
    found = await labels(client, uri, position_of(text, "tcp = up", len("tcp = up")))
    assert "upper" in found
    assert "shoulder" not in found  # a joint is no tcp


# -- hover -------------------------------------------------------------------------------------


async def test_hover_on_a_joint_shows_its_type_limits_axis_and_parent_and_child(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = panda_copy(tmp_path)
    uri = open_doc(client, spec)
    text = await hover(client, uri, position_of(PANDA_TEXT, "panda_finger_joint2]", 3))
    assert "prismatic" in text
    assert "limits: [0.0, 0.04]" in text
    assert "axis: 0 -1 0" in text
    assert "panda_hand -> panda_rightfinger" in text
    assert "mimics panda_finger_joint1" in text


async def test_hover_on_a_link_a_group_and_a_controller(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec, _ = tiny_robot(tmp_path)
    text = TINY_SPEC + "tcp: lower\n"
    uri = open_doc(client, spec, text)
    link = await hover(client, uri, position_of(text, "tcp: lower", 6))
    assert "lower <- elbow <- upper <- shoulder <- base" in link
    panda = panda_copy(tmp_path)
    panda_uri = open_doc(client, panda)
    group = await hover(client, panda_uri, position_of(PANDA_TEXT, "joints: gripper", 10))
    assert "panda_finger_joint1" in group and "panda_finger_joint2" in group
    controller = await hover(
        client, panda_uri, position_of(PANDA_TEXT, "extends: arm_delta_pos", 12)
    )
    assert "- use_delta: true" in controller  # its own
    assert "use_delta: true (from" not in controller
    assert "use_target" not in controller  # its child's
    assert "stiffness: 1e3 (from arm_pos)" in controller
    upper = await hover(client, uri, position_of(text, "upper"))  # a link's mass
    assert "mass: 1.5 kg" in upper


async def test_hover_on_a_diagnostic_shows_its_code_and_message(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = panda_copy(tmp_path)
    typed = PANDA_TEXT.replace("tcp: panda_hand_tcp", "tcp: panda_hand_tpc")
    uri = open_doc(client, spec, typed)
    await diagnostics_until(client, uri, lambda ds: bool(ds))
    text = await hover(client, uri, position_of(typed, "tcp:"))
    assert "RS2" in text and "panda_hand_tpc" in text


# -- definition --------------------------------------------------------------------------------


async def test_definition_jumps_from_a_joint_into_the_urdf(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec, urdf = tiny_robot(tmp_path)
    uri = open_doc(client, spec)
    target = await definition(client, uri, position_of(TINY_SPEC, "elbow]", 2))
    assert target.uri == urdf.resolve().as_uri()
    assert (
        TWO_JOINT_URDF.split("\n")[target.range.start.line]
        .strip()
        .startswith('<joint name="elbow"')
    )


TINY_XACRO = """<?xml version="1.0"?>
<robot name="tiny" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="reach" value="1.5"/>
  <link name="base"/>
  <link name="upper"/>
  <link name="lower"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
    <limit lower="-${reach}" upper="${reach}" effort="10" velocity="2"/>
  </joint>

  <!-- the elbow, three lines below its comment -->

    <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="lower"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
</robot>
"""


async def test_definition_jumps_from_a_joint_into_the_xacro_on_its_exact_line(
    client: LanguageClient, tmp_path: Path
) -> None:
    """The expansion's lines are not the xacro's: the jump lands on the xacro's own line of
    the joint, at its start tag."""
    xacro = tmp_path / "tiny.urdf.xacro"
    xacro.write_text(TINY_XACRO)
    spec = tmp_path / "tiny.yaml"
    text = TINY_SPEC.replace("urdf: tiny.urdf", "xacro: tiny.urdf.xacro")
    spec.write_text(text)
    uri = open_doc(client, spec)
    target = await definition(client, uri, position_of(text, "elbow]", 2))
    assert target.uri == xacro.resolve().as_uri()
    assert target.range.start == position_of(TINY_XACRO, '<joint name="elbow"')


async def test_definition_jumps_from_extends_to_the_base_and_from_a_group_to_it(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = panda_copy(tmp_path)
    uri = open_doc(client, spec)
    base = await definition(client, uri, position_of(PANDA_TEXT, "extends: arm_pos", 10))
    assert base.uri == uri
    assert base.range.start == position_of(PANDA_TEXT, "  arm_pos:", 2)
    group = await definition(client, uri, position_of(PANDA_TEXT, "joints: gripper", 10))
    assert group.range.start == position_of(PANDA_TEXT, "  gripper: [", 2)


# -- the command -------------------------------------------------------------------------------


async def test_lsp_without_pygls_says_what_to_install_and_exits_2() -> None:
    program = (
        "import sys; sys.modules['pygls'] = None; sys.argv = ['robospec', 'lsp'];"
        "from robospec.cli import main; main()"
    )
    done = subprocess.run(
        [sys.executable, "-c", program], capture_output=True, text=True, timeout=60, cwd=ROOT
    )
    assert done.returncode == 2
    assert "pip install 'robospec[lsp]'" in done.stderr
    assert "Traceback" not in done.stderr


# -- the server's state, without a client ------------------------------------------------------


async def test_the_description_is_parsed_once_and_again_only_when_its_file_changes(
    tmp_path: Path,
) -> None:
    from robospec.lsp.documents import Workspace

    spec, urdf = tiny_robot(tmp_path)
    state = Workspace()
    state.open(spec, TINY_SPEC, 1)
    for version, typed in enumerate([TINY_SPEC, TINY_SPEC + "\n", TINY_SPEC + "tcp: lower\n"]):
        state.open(spec, typed, version + 2)
        assert state.current(spec).description is not None
    assert state.memo.parses == 1
    urdf.write_text(TWO_JOINT_URDF.replace('"elbow"', '"knee"'))
    assert state.current(spec).description.joint("knee") is not None  # type: ignore[union-attr]
    assert state.memo.parses == 2


async def test_the_server_imports_neither_maniskill_nor_sapien_nor_torch() -> None:
    program = (
        "import sys\n"
        "from pathlib import Path\n"
        "import robospec.lsp.server\n"
        "from robospec.lsp.documents import Workspace\n"
        f"Workspace().analyse(Path({str(PANDA_SPEC)!r}))\n"
        "heavy = ('mani_skill', 'sapien', 'torch', 'trimesh', 'yourdfpy')\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", program], capture_output=True, text=True, timeout=60, cwd=ROOT
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


# -- parts -------------------------------------------------------------------------------------

PART_FILES = CODE_EXAMPLES / "RS730"  # an arm, a gripper and the gripper's spec
ARM_WITH_GRIPPER = """robospec: 1
uid: my_arm
description: {urdf: arm.urdf}
parts:
  gripper: {spec: gripper.yaml, at: tool0}
controllers:
  arm: {type: pd_joint_pos, joints: [shoulder], lower: -3, upper: 3, stiffness: 100, damping: 10}
control_modes:
  pd_joint_pos: {arm: arm}
  both: {arm: arm, hand: fingers}
tcp: left_finger
"""


def arm_with_gripper(tmp_path: Path) -> Path:
    for name in ("arm.urdf", "gripper.urdf", "gripper.yaml"):
        shutil.copy(PART_FILES / name, tmp_path / name)
    spec = tmp_path / "arm.yaml"
    spec.write_text(ARM_WITH_GRIPPER)
    return spec


async def test_completion_offers_a_parts_links_joints_and_controllers(
    client: LanguageClient, tmp_path: Path
) -> None:
    spec = arm_with_gripper(tmp_path)
    typed = ARM_WITH_GRIPPER.replace("hand: fingers}", "hand: }").replace(
        "tcp: left_finger", "tcp: "
    )
    uri = open_doc(client, spec, typed)
    controllers = await labels(client, uri, position_of(typed, "hand: }", 6))
    assert {"arm", "fingers"} <= controllers  # the gripper's controller came along
    links = await labels(client, uri, position_of(typed, "tcp: ", 5))
    assert {"upper_arm", "palm", "left_finger"} <= links
    joints = await labels(client, uri, position_of(typed, "joints: [shoulder]", 10))
    assert {"shoulder", "left", "right"} <= joints


async def test_definition_jumps_into_the_part(client: LanguageClient, tmp_path: Path) -> None:
    spec = arm_with_gripper(tmp_path)
    uri = open_doc(client, spec)
    gripper_spec = (tmp_path / "gripper.yaml").resolve()
    link = await definition(client, uri, position_of(ARM_WITH_GRIPPER, "tcp: left_finger", 6))
    assert link.uri == (tmp_path / "gripper.urdf").resolve().as_uri()
    lines = (tmp_path / "gripper.urdf").read_text().split("\n")
    assert lines[link.range.start.line].strip() == '<link name="left_finger">'
    controller = await definition(client, uri, position_of(ARM_WITH_GRIPPER, "hand: fingers", 7))
    assert controller.uri == gripper_spec.as_uri()
    text = gripper_spec.read_text()
    assert controller.range.start == position_of(text, "  fingers: {type", 2)
    part = await definition(client, uri, position_of(ARM_WITH_GRIPPER, "spec: gripper.yaml", 8))
    assert (part.uri, part.range.start.line) == (gripper_spec.as_uri(), 0)
