"""Every snippet of the docs that makes a ManiSkill environment runs, as written, on this
machine (no GPU): each Python block with ``gym.make(`` on a guide page or the README runs in a
fresh process, where the page's reader would run it, after the page's own commands before it.
(docs/bring-your-own-robot.md runs whole in tests/test_bring_your_own_robot.py.)"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from conftest import DOCS, ROOT
from test_docs import FENCE, _run_console, _workdir

pytestmark = [pytest.mark.maniskill, pytest.mark.minutes]  # the snippets simulate

# page -> where its reader stands: the tutorial's folder of their own, robospec's clone, or the
# clone after the page's own commands (which write into it: here, a copy of its specs)
PAGES = {
    "index.md": "tutorial folder",
    "tutorial.md": "tutorial folder",
    "README.md": "clone",
    "optimize.md": "clone after its commands",
}


def _snippets() -> list[tuple[str, int]]:
    found = []
    for page in PAGES:
        text = (ROOT / page if page == "README.md" else DOCS / page).read_text("utf-8")
        blocks = [m for m in FENCE.finditer(text) if m["lang"] == "python"]
        found += [(page, i) for i, m in enumerate(blocks) if "gym.make(" in m["body"]]
    return found


def test_the_pages_with_environments_are_all_here() -> None:
    pages = {
        p.name
        for p in [*DOCS.glob("*.md"), ROOT / "README.md"]
        if re.search(r"```python\n(?:(?!```).)*gym\.make\(", p.read_text("utf-8"), re.S)
    }
    assert pages - {"bring-your-own-robot.md"} == set(PAGES)


@pytest.mark.parametrize(("page", "index"), _snippets())
def test_every_snippet_that_makes_an_environment_runs_as_written(
    page: str, index: int, tmp_path: Path
) -> None:
    text = (ROOT / page if page == "README.md" else DOCS / page).read_text("utf-8")
    blocks = [m for m in FENCE.finditer(text) if m["lang"] == "python"]
    snippet = blocks[index]
    if PAGES[page] == "clone":
        cwd = ROOT
    else:
        if PAGES[page] == "tutorial folder":
            cwd = _workdir(tmp_path)
        else:  # the clone's specs, read where they are; what the commands write stays here
            cwd = tmp_path / "clone"
            cwd.mkdir()
            (cwd / "specs").symlink_to(ROOT / "specs", target_is_directory=True)
        # the page's commands before the snippet, in the reader's folder (what they write); a
        # command shown twice (once to run, once with its output) runs once
        before = text[: snippet.start()]
        commands: dict[str, None] = {}
        for console in re.findall(r"```console\n(.*?)```", before, re.S):
            # (a block in a list item is indented)
            for command in re.findall(r"^ *\$ (robospec (?!check|tune).*)$", console, re.M):
                commands[command] = None
        for command in commands:
            _run_console(command, cwd)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(cwd), str(ROOT)])}
    result = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(snippet["body"])],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert result.returncode == 0, f"{page}:\n{snippet['body']}\n{result.stderr[-3000:]}"
