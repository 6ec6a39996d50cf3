"""``robospec new`` never writes a spec its own ``validate`` rejects: on every robot of the
corpus (tests/corpus.py, MJCF included), either it writes a spec that validates without an error
(with the mends the robot needs), or it writes nothing and says, located, why.

Without the rest-pose search (``--no-sim``: no simulation here); ``run_new``'s own check of
the text it would write covers the searched pose too, and tests/test_corpus.py takes the whole
journey with it. A robot is refused only for what no mend can mend.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import fast_first
from corpus import CORPUS, CorpusMissing, Robot, locate

from robospec.authoring.commands import run_new
from robospec.pipeline import compile_spec

# what may stop `new` on a corpus robot: nothing robospec can mend (a robot without an active
# joint, files the package does not ship). Empty: every corpus robot gets a spec.
REFUSED: dict[str, str] = {}


@pytest.mark.parametrize("robot", fast_first(CORPUS), ids=lambda r: r.key)
def test_new_writes_a_spec_that_validates_or_nothing(robot: Robot, tmp_path: Path) -> None:
    try:
        description = locate(robot)
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    out = tmp_path / f"{robot.key}.yaml"
    result = run_new(description, out, None, force=False, simulate=False).write()
    if result.failed:
        assert not out.exists()
        assert all(d.location.line >= 1 for d in result.diagnostics if d.is_error)
        assert robot.key in REFUSED, [d.format_text() for d in result.diagnostics if d.is_error]
        return
    errors = [d.format_text() for d in compile_spec(out).diagnostics if d.is_error]
    assert errors == []
