"""A small Language Server Protocol client over stdio, for tests that drive real editor engines
(yaml-language-server) the way an editor does.

JSON-RPC 2.0 messages framed with ``Content-Length`` headers. A reader thread parses the
server's stdout and files each message: responses by request id, notifications (published
diagnostics) by document URI. Every wait has a timeout, so a hung or crashed server fails the
test with the server's stderr instead of hanging CI.
"""

from __future__ import annotations

import json
import subprocess
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

JsonObject = dict[str, Any]

DEFAULT_TIMEOUT_S = 30.0


class LspError(RuntimeError):
    """The server answered with an error, died, or did not answer in time."""


def _read_message(stream: IO[bytes]) -> JsonObject | None:
    """One framed message from ``stream``; None at end of stream."""
    content_length: int | None = None
    while True:
        line = stream.readline()
        if not line:
            return None
        line = line.strip()
        if not line:  # the blank line that ends the headers
            break
        name, _, value = line.decode("ascii").partition(":")
        if name.strip().lower() == "content-length":
            content_length = int(value.strip())
    if content_length is None:
        raise LspError("message without a Content-Length header")
    body = stream.read(content_length)
    if len(body) < content_length:
        return None
    return json.loads(body.decode("utf-8"))


class LspClient:
    """A running language server and the client side of its conversation."""

    def __init__(self, argv: Sequence[str], cwd: Path, timeout_s: float = DEFAULT_TIMEOUT_S):
        self.timeout_s = timeout_s
        self._process = subprocess.Popen(
            list(argv),
            cwd=cwd,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        self._next_id = 0
        self._lock = threading.Condition()
        self._responses: dict[int, JsonObject] = {}
        # every publishDiagnostics per URI, in arrival order: a server may publish several times
        self._diagnostics: dict[str, list[list[JsonObject]]] = {}
        self._closed = False
        self._unresponsive = False  # a wait timed out: close() kills instead of asking
        self._stderr_chunks: list[bytes] = []
        # settings by section, for the server's workspace/configuration requests
        self._settings: JsonObject = {}
        self._configuration_requests_answered = 0
        threading.Thread(target=self._read_stdout, daemon=True).start()
        threading.Thread(target=self._read_stderr, daemon=True).start()

    # -- plumbing -------------------------------------------------------------------------------

    def _read_stdout(self) -> None:
        assert self._process.stdout is not None
        try:
            while (message := _read_message(self._process.stdout)) is not None:
                self._dispatch(message)
        finally:
            with self._lock:
                self._closed = True
                self._lock.notify_all()

    def _read_stderr(self) -> None:
        assert self._process.stderr is not None
        for chunk in iter(lambda: self._process.stderr.read1(4096), b""):  # type: ignore[union-attr]
            self._stderr_chunks.append(chunk)

    def _dispatch(self, message: JsonObject) -> None:
        if "id" in message and "method" in message:
            self._answer_server_request(message)
            return
        with self._lock:
            if "id" in message:
                self._responses[message["id"]] = message
            elif message.get("method") == "textDocument/publishDiagnostics":
                params = message["params"]
                self._diagnostics.setdefault(params["uri"], []).append(params["diagnostics"])
            self._lock.notify_all()

    def _answer_server_request(self, request: JsonObject) -> None:
        if request["method"] == "workspace/configuration":
            # servers like yaml-language-server ignore didChangeConfiguration's payload and pull
            # their settings this way, section by section
            with self._lock:
                sections = [
                    self._settings.get(item.get("section", ""))
                    for item in request["params"]["items"]
                ]
            self._send({"jsonrpc": "2.0", "id": request["id"], "result": sections})
            with self._lock:
                self._configuration_requests_answered += 1
                self._lock.notify_all()
            return
        # anything else (registerCapability, workDoneProgress/create, ...): accept it with a null
        # result, as an editor that ignores it would
        self._send({"jsonrpc": "2.0", "id": request["id"], "result": None})

    def _send(self, message: JsonObject) -> None:
        body = json.dumps(message).encode("utf-8")
        assert self._process.stdin is not None
        try:
            self._process.stdin.write(f"Content-Length: {len(body)}\r\n\r\n".encode("ascii"))
            self._process.stdin.write(body)
            self._process.stdin.flush()
        except BrokenPipeError as error:
            raise LspError(f"the server is gone{self._stderr_tail()}") from error

    def _stderr_tail(self) -> str:
        text = b"".join(self._stderr_chunks).decode("utf-8", "replace").strip()
        return f"; its stderr ends:\n{text[-2000:]}" if text else ""

    def _wait(self, ready: Any, what: str, timeout_s: float | None) -> None:
        """Block until ``ready()`` is true (under the lock), the server dies, or time runs out."""
        with self._lock:
            finished = self._lock.wait_for(
                lambda: ready() or self._closed, timeout=timeout_s or self.timeout_s
            )
            if not finished:
                self._unresponsive = True
                raise LspError(f"no {what} within {timeout_s or self.timeout_s} s")
            if not ready():
                raise LspError(f"the server exited before {what}{self._stderr_tail()}")

    # -- the protocol ---------------------------------------------------------------------------

    def request(
        self, method: str, params: JsonObject | None, timeout_s: float | None = None
    ) -> Any:
        self._next_id += 1
        request_id = self._next_id
        self._send({"jsonrpc": "2.0", "id": request_id, "method": method, "params": params})
        self._wait(lambda: request_id in self._responses, f"answer to {method}", timeout_s)
        with self._lock:
            response = self._responses.pop(request_id)
        if "error" in response:
            raise LspError(f"{method} failed: {response['error']}")
        return response.get("result")

    def notify(self, method: str, params: JsonObject | None) -> None:
        self._send({"jsonrpc": "2.0", "method": method, "params": params})

    def initialize(self, root: Path) -> JsonObject:
        result = self.request(
            "initialize",
            {
                "processId": None,
                "rootUri": root.as_uri(),
                "capabilities": {
                    "workspace": {"configuration": True, "didChangeConfiguration": {}},
                    "textDocument": {
                        "completion": {"completionItem": {"snippetSupport": False}},
                        "publishDiagnostics": {"relatedInformation": False},
                    },
                },
                "workspaceFolders": [{"uri": root.as_uri(), "name": root.name}],
            },
        )
        self.notify("initialized", {})
        return result

    def configure(self, settings: JsonObject) -> None:
        """Give the server ``settings`` (by section, e.g. {"yaml": {...}}) and wait until it has
        pulled them, so documents opened afterwards are handled under them."""
        with self._lock:
            self._settings = settings
            answered_before = self._configuration_requests_answered
        self.notify("workspace/didChangeConfiguration", {"settings": settings})
        self._wait(
            lambda: self._configuration_requests_answered > answered_before,
            "workspace/configuration request after didChangeConfiguration",
            None,
        )

    def open(self, path: Path, language_id: str, text: str | None = None) -> str:
        """Open ``path`` (its contents, or ``text``) as the editor would; returns its URI."""
        uri = path.resolve().as_uri()
        self.notify(
            "textDocument/didOpen",
            {
                "textDocument": {
                    "uri": uri,
                    "languageId": language_id,
                    "version": 1,
                    "text": path.read_text() if text is None else text,
                }
            },
        )
        return uri

    def diagnostics(self, uri: str, timeout_s: float | None = None) -> list[JsonObject]:
        """The first diagnostics the server publishes for ``uri``."""
        self._wait(lambda: self._diagnostics.get(uri), f"diagnostics for {uri}", timeout_s)
        with self._lock:
            return self._diagnostics[uri][0]

    def completion(self, uri: str, line: int, character: int) -> list[JsonObject]:
        """Completion items at a 0-based position (LSP's convention)."""
        result = self.request(
            "textDocument/completion",
            {
                "textDocument": {"uri": uri},
                "position": {"line": line, "character": character},
            },
        )
        if result is None:
            return []
        return result["items"] if isinstance(result, dict) else result

    def close(self) -> None:
        """shutdown and exit as an editor does; kill a server that does not go."""
        if not self._unresponsive and not self._closed:
            try:
                self.request("shutdown", None, timeout_s=5)
                self.notify("exit", None)
            except LspError:
                pass  # it is killed below
        try:
            self._process.wait(timeout=0 if self._unresponsive else 5)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait(timeout=5)
        for stream in (self._process.stdin, self._process.stdout, self._process.stderr):
            if stream is not None:
                stream.close()
