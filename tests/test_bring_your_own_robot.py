"""docs/bring-your-own-robot.md does what it says: its steps, run in order in a fresh project
folder holding the corpus robot it copies, print what the page shows.

The page's blocks, in order: each ``$ robospec ...`` or ``$ python FILE`` line of a console
block runs and its output (stdout and stderr, less SAPIEN's complaints about Vulkan) must be
the lines below it; a block after ``<!-- generated: FILE -->`` must be FILE as robospec wrote
it; ``<!-- edit: FILE -->`` before a ``diff`` block makes that edit to FILE (the reader's
fix: each hunk's old lines, found exactly once, become its new lines), and ``<!-- file: FILE
-->`` writes the block to FILE (a script the reader saves).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import DOCS
from corpus import BY_KEY, CorpusMissing, locate

# check, register and gym.make simulate the robot
pytestmark = [pytest.mark.maniskill, pytest.mark.minutes]

PAGE = DOCS / "bring-your-own-robot.md"
ROBOT = BY_KEY["pb_laikago"]  # the page's robot: pybullet's Unitree Laikago
# a fenced block with the `<!-- ... -->` line before it, if any
BLOCK = re.compile(
    r"^(?:<!-- (?P<marker>[^>]*) -->\n)?```(?P<lang>\w*)\n(?P<body>.*?)^```$", re.M | re.S
)


def _project(tmp_path: Path) -> Path:
    """A fresh project folder with the robot copied in, as the page's first step does."""
    try:
        description = locate(ROBOT)
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    shutil.copytree(description.parent, tmp_path / "robots" / description.parent.name)
    return tmp_path


def _run(command: str, cwd: Path) -> str:
    args = shlex.split(command)
    if args[0] == "robospec":
        args = [sys.executable, "-m", "robospec.cli", *args[1:]]
    else:
        assert args[0] == "python", command
        args = [sys.executable, *args[1:]]
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "100"}
    env.pop("FORCE_COLOR", None)
    result = subprocess.run(
        args,
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=300,
        env=env,
    )
    lines = result.stdout.splitlines()
    return "\n".join(line for line in lines if not _is_sapien_noise(line))


def _is_sapien_noise(line: str) -> bool:
    """SAPIEN's import-time complaints about Vulkan on a machine without a GPU."""
    return "vulkan" in line.lower() or line.strip().startswith("warn(")


def apply_diff(text: str, diff: str) -> str:
    """``text`` with the edit a unified diff's hunks describe (``@@`` lines, or blank lines
    between hunks, separate them): each hunk's context and ``-`` lines must occur exactly once."""
    for hunk in re.split(r"^(?:@@.*|)\n", diff, flags=re.M):
        lines = hunk.splitlines(keepends=True)
        old = "".join(line[1:] for line in lines if line[:1] in (" ", "-"))
        new = "".join(line[1:] for line in lines if line[:1] in (" ", "+"))
        if not old:
            continue
        assert text.count(old) == 1, f"this hunk's old lines are not in the file once:\n{hunk}"
        text = text.replace(old, new)
    return text


def test_the_page_copies_the_corpus_robot_it_names() -> None:
    page = PAGE.read_text(encoding="utf-8")
    folder = Path(ROBOT.path).parent.name
    found = "python -c 'import pybullet_data; print(pybullet_data.getDataPath())'"
    assert f'data="$({found})"' in page
    assert f'cp -r "$data/{folder}" robots/' in page
    assert f"robots/{folder}/{Path(ROBOT.path).name}" in page


def test_the_page_works_in_a_folder_of_its_own() -> None:
    """Its first step makes a project folder and goes into it, before anything is written, and
    every path a later command names lies inside it: run in the robospec clone, `-o
    specs/laikago.yaml` would land among the example specs."""
    blocks = list(BLOCK.finditer(PAGE.read_text(encoding="utf-8")))
    first = blocks[0]["body"].splitlines()
    made = re.fullmatch(r"mkdir (?P<folder>[\w.-]+) && cd (?P=folder)\b.*", first[0])
    assert made, first[0]
    for match in blocks:
        if match["lang"] != "console":
            continue
        for command in re.findall(r"^\$ (.*)$", match["body"], flags=re.M):
            for word in shlex.split(command)[1:]:
                assert not word.startswith(("/", "~")) and ".." not in Path(word).parts, command


def test_every_step_of_the_page_does_what_the_page_shows(tmp_path: Path) -> None:
    project = _project(tmp_path)
    ran = 0
    for match in BLOCK.finditer(PAGE.read_text(encoding="utf-8")):
        marker, language, body = match["marker"] or "", match["lang"], match["body"]
        action, _, file = marker.partition(": ")
        if action == "generated":
            assert (project / file).read_text(encoding="utf-8") == body, file
        elif action == "edit":
            assert language == "diff", marker
            edited = apply_diff((project / file).read_text(encoding="utf-8"), body)
            (project / file).write_text(edited, encoding="utf-8")
        elif action == "file":
            (project / file).write_text(body, encoding="utf-8")
        elif language == "console":
            for chunk in re.split(r"^\$ ", body, flags=re.M)[1:]:
                command, _, expected = chunk.partition("\n")
                assert _run(command, project) == expected.rstrip("\n"), command
                ran += 1
    assert ran >= 5, "the page runs inspect, new, validate, check and the script"
