"""How soon `robospec lsp` publishes fresh diagnostics after an edit, for the Panda spec.

A Language Server Protocol client (pygls's) starts `python -m robospec
lsp` over stdio and opens specs/maniskill/panda.yaml. Then, edit after edit, it replaces the
unsaved buffer's text, alternately misspelling a joint and putting it right, and measures the
wall time from sending `textDocument/didChange` to receiving the `publishDiagnostics` of that
version with the expected diagnostics (RS201, or none). That time includes the server's
debounce (it waits for typing to pause), the compilation of the spec with its URDF parsed
once and reused, and both ways of the JSON-RPC pipe. Target: under 200 ms.
"""

from __future__ import annotations

import asyncio
import statistics
import time

from measure import PYTHON, ROOT, child_env
from section import Section

TITLE = "Fresh diagnostics after an edit in the language server"
SPEC = ROOT / "specs" / "maniskill" / "panda.yaml"
TARGET_S = 0.200
RIGHT = "  gripper: [panda_finger_joint1, panda_finger_joint2]"
WRONG = "  gripper: [panda_finger_joint9, panda_finger_joint2]"


async def _edits(count: int) -> tuple[list[float], float]:
    """The latency of ``count`` edits, and the time to the first diagnostics after opening."""
    from lsprotocol import types
    from pygls.lsp.client import LanguageClient

    client = LanguageClient("robospec-benchmark", "1")
    await client.start_io(PYTHON, "-m", "robospec", "lsp", cwd=ROOT, env=child_env())
    await client.initialize_async(types.InitializeParams(capabilities=types.ClientCapabilities()))
    client.initialized(types.InitializedParams())
    uri = SPEC.resolve().as_uri()
    text = SPEC.read_text(encoding="utf-8")
    published: dict[int, tuple[float, list[str]]] = {}
    arrived = asyncio.Event()

    @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def _published(params: types.PublishDiagnosticsParams) -> None:
        if params.uri == uri and params.version is not None:
            published[params.version] = (
                time.perf_counter(),
                [str(d.code) for d in params.diagnostics],
            )
            arrived.set()

    async def until(version: int) -> float:
        while version not in published:
            arrived.clear()
            await asyncio.wait_for(arrived.wait(), 30)
        return published[version][0]

    started = time.perf_counter()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="yaml", version=1, text=text)
        )
    )
    first = await until(1) - started
    latencies: list[float] = []
    for version in range(2, count + 2):
        wrong = version % 2 == 0
        edited = text.replace(RIGHT, WRONG) if wrong else text
        await asyncio.sleep(0.3)  # a pause in typing, so each edit is compiled on its own
        sent = time.perf_counter()
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[types.TextDocumentContentChangeWholeDocument(text=edited)],
            )
        )
        received = await until(version)
        codes = published[version][1]
        assert codes == (["RS201"] if wrong else []), codes
        latencies.append(received - sent)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return latencies, first


def measure(edits: int = 40) -> Section:
    from robospec.lsp.server import DEBOUNCE_S

    latencies, first = asyncio.run(_edits(edits))
    ordered = sorted(latencies)
    median = statistics.median(ordered)
    p90 = ordered[min(len(ordered) - 1, round(0.9 * (len(ordered) - 1)))]
    worst = ordered[-1]
    # judged on the 90th percentile: the machine is shared with other work, and a single edit
    # it slowed says more about the machine than about the server (the slowest is shown too)
    meets = p90 < TARGET_S
    verdict = "met" if meets else "**missed**"
    body = f"""`benchmarks/lsp_latency.py`: a Language Server Protocol client opens
`specs/maniskill/panda.yaml` in `robospec lsp`, then replaces the unsaved text {edits} times,
alternately misspelling `panda_finger_joint1` and putting it right, and times each edit from
`didChange` sent to that version's `publishDiagnostics` received (RS201, then none). The server
waits {DEBOUNCE_S * 1000:.0f} ms for typing to pause before it compiles; the Panda's URDF is
parsed once and reused while it is unchanged.

| edits | median ms | 90th percentile ms | slowest ms | first diagnostics after opening ms |
| ---: | ---: | ---: | ---: | ---: |
| {edits} | {median * 1000:.0f} | {p90 * 1000:.0f} | {worst * 1000:.0f} | {first * 1000:.0f} |

Target: fresh diagnostics within 200 ms of an edit, judged on the 90th percentile (the
machine is shared with other work): {verdict}; the slowest edit took {worst * 1000:.0f} ms
({"within" if worst < TARGET_S else "over"} the target). The first diagnostics after opening
include reading ManiSkill's registered uids and the URDF once.
"""
    return Section(TITLE, body, meets)


if __name__ == "__main__":
    import sys

    section = measure(int(sys.argv[1]) if len(sys.argv) > 1 else 40)
    print(section.markdown())
    sys.exit(0 if section.meets_target else 1)
