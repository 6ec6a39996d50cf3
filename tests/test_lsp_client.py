"""The LSP client the editor tests rely on fails fast instead of hanging CI: a server that never
answers times out, one that dies is reported with its stderr, and close() leaves no process."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from lsp_client import LspClient, LspError

SILENT_SERVER = "import time; time.sleep(60)"
DYING_SERVER = "import sys; sys.stderr.write('boom: no such workspace'); sys.exit(3)"


def test_a_server_that_never_answers_times_out(tmp_path: Path) -> None:
    client = LspClient([sys.executable, "-c", SILENT_SERVER], cwd=tmp_path, timeout_s=0.5)
    try:
        with pytest.raises(LspError, match=r"no answer to initialize within 0\.5 s"):
            client.initialize(tmp_path)
    finally:
        client.close()
    assert client._process.poll() is not None  # killed, not left behind


def test_a_server_that_dies_is_reported_with_its_stderr(tmp_path: Path) -> None:
    client = LspClient([sys.executable, "-c", DYING_SERVER], cwd=tmp_path, timeout_s=10)
    try:
        with pytest.raises(LspError, match="boom: no such workspace"):
            client.initialize(tmp_path)
    finally:
        client.close()
