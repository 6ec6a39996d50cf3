"""`robospec lsp`: the Language Server over stdio (pygls).

Diagnostics are robospec validate's, on the editor's unsaved text: published on open at once
and after a change once typing pauses (DEBOUNCE_S), those located in the URDF/MJCF for that
file. A description file that changes on disk (the client's file watcher, or a save in the
editor) compiles the open specs that read it again; requests (completion, hover, definition)
see such a change anyway, because they compile again whenever a file the last compilation read
has changed.
"""

from __future__ import annotations

import asyncio
import os
from functools import cache
from pathlib import Path

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

from robospec.diagnostics import Diagnostic, Severity
from robospec.lsp.completion import complete
from robospec.lsp.definition import definition
from robospec.lsp.documents import Analysis, Workspace
from robospec.lsp.hover import hover_text
from robospec.lsp.positions import Cursor, locate, word_span

# after the last keystroke; small, so that fresh diagnostics arrive within 200 ms of an edit
DEBOUNCE_S = 0.03
# description files whose changes the server asks the client to report
WATCHED = "**/*.{urdf,URDF,xml,srdf,xacro}"


@cache
def code_href(code: str) -> str | None:
    """The code's docs page (docs/codes/RSxxx.md): in this checkout when it has the docs, else
    under the installed package's Documentation URL, if it declares one."""
    page = Path(__file__).resolve().parents[2] / "docs" / "codes" / f"{code}.md"
    if page.is_file():
        return page.as_uri()
    from robospec.reporting.sarif import project_urls

    docs = project_urls().get("documentation")
    return f"{docs.rstrip('/')}/codes/{code}.md" if docs else None


class RobospecServer(LanguageServer):
    def __init__(self) -> None:
        from robospec.version import __version__

        super().__init__("robospec", __version__)
        self.state = Workspace()
        self.pending: dict[Path, asyncio.TimerHandle] = {}
        # description file -> spec -> its diagnostics there (several specs may share a URDF)
        self.in_descriptions: dict[Path, dict[Path, list[Diagnostic]]] = {}

    # -- diagnostics ---------------------------------------------------------------------------

    def schedule(self, path: Path, delay: float) -> None:
        waiting = self.pending.pop(path, None)
        if waiting is not None:
            waiting.cancel()
        if delay <= 0:
            self.publish(path)
            return
        self.pending[path] = asyncio.get_running_loop().call_later(delay, self.publish, path)

    def publish(self, path: Path) -> None:
        self.pending.pop(path, None)
        if path not in self.state.texts:
            return
        analysis = self.state.analyse(path)
        found = analysis.by_file()
        lines = analysis.text.split("\n")
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(
                uri=_uri(path),
                version=analysis.version,
                diagnostics=[to_lsp(d, lines) for d in found.pop(path, [])],
            )
        )
        touched = set(found)
        for file, by_spec in self.in_descriptions.items():
            if path in by_spec:
                touched.add(file)
                del by_spec[path]
        for file, diagnostics in found.items():
            self.in_descriptions.setdefault(file, {})[path] = diagnostics
        for file in touched:
            self._publish_description(file)

    def _publish_description(self, file: Path) -> None:
        merged = list(
            dict.fromkeys(d for ds in self.in_descriptions.get(file, {}).values() for d in ds)
        )
        try:
            lines = file.read_text(encoding="utf-8", errors="replace").split("\n")
        except OSError:
            lines = []
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(
                uri=_uri(file), diagnostics=[to_lsp(d, lines) for d in merged]
            )
        )

    def description_changed(self, file: Path) -> None:
        for spec in self.state.dependents(file):
            if spec in self.state.texts:
                self.schedule(spec, 0)


def to_lsp(diagnostic: Diagnostic, lines: list[str]) -> types.Diagnostic:
    """A robospec diagnostic as LSP has it: 0-based, spanning the word it points at."""
    loc = diagnostic.location
    line = max(loc.line - 1, 0)
    start = max(loc.column - 1, 0)
    text = lines[line] if line < len(lines) else ""
    if start < len(text) and text[start] in "\"'":
        close = text.find(text[start], start + 1)
        end = close + 1 if close > start else len(text)
    else:
        end = word_span(text, start)[1] if start < len(text) else start
        if end <= start:
            end = len(text) if start < len(text) else start + 1
    href = code_href(diagnostic.code)
    message = diagnostic.message + (f"\nhint: {diagnostic.hint}" if diagnostic.hint else "")
    return types.Diagnostic(
        range=types.Range(
            start=types.Position(line=line, character=start),
            end=types.Position(line=line, character=end),
        ),
        message=message,
        severity={
            Severity.ERROR: types.DiagnosticSeverity.Error,
            Severity.WARNING: types.DiagnosticSeverity.Warning,
        }.get(diagnostic.severity, types.DiagnosticSeverity.Information),
        code=diagnostic.code,
        code_description=types.CodeDescription(href=href) if href else None,
        source="robospec",
    )


def _uri(path: Path) -> str:
    return from_fs_path(str(path)) or path.as_uri()


def _path(uri: str) -> Path | None:
    local = to_fs_path(uri)
    return Path(os.path.abspath(local)) if local else None


server = RobospecServer()


@server.feature(types.INITIALIZED)
async def initialized(ls: RobospecServer, params: types.InitializedParams) -> None:
    watch = ls.client_capabilities.workspace
    changed = watch.did_change_watched_files if watch else None
    if changed is None or not changed.dynamic_registration:
        return
    try:
        await ls.client_register_capability_async(
            types.RegistrationParams(
                registrations=[
                    types.Registration(
                        id="robospec-descriptions",
                        method=types.WORKSPACE_DID_CHANGE_WATCHED_FILES,
                        register_options=types.DidChangeWatchedFilesRegistrationOptions(
                            watchers=[types.FileSystemWatcher(glob_pattern=WATCHED)]
                        ),
                    )
                ]
            )
        )
    except Exception as exc:  # a client that declared it but refuses: requests still see changes
        ls.window_log_message(
            types.LogMessageParams(
                type=types.MessageType.Warning, message=f"no file watcher: {exc}"
            )
        )


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: RobospecServer, params: types.DidOpenTextDocumentParams) -> None:
    path = _path(params.text_document.uri)
    if path is None:
        return
    if ls.state.is_spec(path):
        ls.state.open(path, params.text_document.text, params.text_document.version)
        ls.schedule(path, 0)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: RobospecServer, params: types.DidChangeTextDocumentParams) -> None:
    path = _path(params.text_document.uri)
    if path is None or not ls.state.is_spec(path):
        return
    document = ls.workspace.get_text_document(params.text_document.uri)
    ls.state.open(path, document.source, params.text_document.version)
    ls.schedule(path, DEBOUNCE_S)


@server.feature(types.TEXT_DOCUMENT_DID_SAVE)
def did_save(ls: RobospecServer, params: types.DidSaveTextDocumentParams) -> None:
    path = _path(params.text_document.uri)
    if path is not None and not ls.state.is_spec(path):
        ls.description_changed(path)


@server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: RobospecServer, params: types.DidCloseTextDocumentParams) -> None:
    path = _path(params.text_document.uri)
    if path is None or not ls.state.is_spec(path):
        return
    ls.state.close(path)
    ls.text_document_publish_diagnostics(
        types.PublishDiagnosticsParams(uri=params.text_document.uri, diagnostics=[])
    )
    for file, by_spec in ls.in_descriptions.items():
        if by_spec.pop(path, None) is not None:
            ls._publish_description(file)


@server.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
def watched_changed(ls: RobospecServer, params: types.DidChangeWatchedFilesParams) -> None:
    for change in params.changes:
        path = _path(change.uri)
        if path is not None:
            ls.description_changed(path)


@server.feature(
    types.TEXT_DOCUMENT_COMPLETION,
    types.CompletionOptions(trigger_characters=[" ", ":", "[", ",", "=", '"']),
)
def completion(ls: RobospecServer, params: types.CompletionParams) -> types.CompletionList | None:
    found = _at(ls, params.text_document.uri, params.position)
    if found is None:
        return None
    analysis, cursor, _ = found
    if cursor is None:
        return None
    return types.CompletionList(is_incomplete=False, items=complete(analysis, cursor))


@server.feature(types.TEXT_DOCUMENT_HOVER)
def hover(ls: RobospecServer, params: types.HoverParams) -> types.Hover | None:
    found = _at(ls, params.text_document.uri, params.position)
    if found is None:
        return None
    analysis, cursor, line_text = found
    line = params.position.line + 1
    here = [
        d
        for d in analysis.compiled.diagnostics
        if d.location.line == line and analysis.file_of(d.location.file) == analysis.path
    ]
    text = hover_text(analysis, cursor, line_text, params.position.character, here, code_href)
    if text is None:
        return None
    return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text))


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
def goto_definition(ls: RobospecServer, params: types.DefinitionParams) -> types.Location | None:
    found = _at(ls, params.text_document.uri, params.position)
    if found is None or found[1] is None:
        return None
    analysis, cursor, _ = found
    assert cursor is not None
    target = definition(analysis, cursor)
    if target is None:
        return None
    position = types.Position(line=target.line - 1, character=target.column - 1)
    return types.Location(uri=_uri(target.file), range=types.Range(start=position, end=position))


def _at(
    ls: RobospecServer, uri: str, position: types.Position
) -> tuple[Analysis, Cursor | None, str] | None:
    path = _path(uri)
    if path is None or not ls.state.is_spec(path):
        return None
    if path not in ls.state.texts:  # a request before didOpen: the file's text
        ls.state.open(path, ls.workspace.get_text_document(uri).source)
    analysis = ls.state.current(path)
    lines = analysis.text.split("\n")
    line_text = lines[position.line] if position.line < len(lines) else ""
    cursor = locate(analysis.text, analysis.fmt, position.line, position.character)
    if cursor is not None and analysis.compiled.loaded is None:
        # the text does not parse as it stands (`tcp = pan`, a TOML value not quoted yet):
        # the cursor's repaired text does, and names the description to complete from
        ls.state.describe_from(analysis, cursor.data)
    return analysis, cursor, line_text


def main() -> None:
    server.start_io()
