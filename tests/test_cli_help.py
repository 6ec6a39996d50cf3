"""Every command explains itself: ``--help`` shows a runnable example, and the shell completion
that ``robospec --show-completion`` prints really completes commands and option values in bash."""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import typer.main
from conftest import ROOT, fast_first, run_robospec

from robospec.cli import app

COMMANDS = sorted(typer.main.get_command(app).commands)  # type: ignore[attr-defined]


def test_every_command_is_listed_in_the_top_level_help() -> None:
    result = run_robospec("--help")
    assert result.returncode == 0
    for name in COMMANDS:
        assert name in result.stdout


@pytest.mark.parametrize("name", fast_first(COMMANDS))
def test_every_command_help_shows_an_example_of_itself(name: str) -> None:
    result = run_robospec(name, "--help", env={**os.environ, "COLUMNS": "200"})
    assert result.returncode == 0, result.stderr
    assert f"Example: robospec {name}" in result.stdout


def _bash_complete(*words: str) -> list[str]:
    """Complete the last of ``words`` (``""``: a new word) in a real bash, through the script
    a user installs."""
    bash = shutil.which("bash")
    assert bash, "bash is needed to test shell completion"
    # typer finds the shell from the parent process (shellingham), as when a user types
    # `robospec --show-completion` in bash; a second command keeps bash from exec-ing python
    show = f"{shlex.quote(sys.executable)} -m robospec.cli --show-completion\nexit $?"
    shown = subprocess.run([bash, "--norc", "-c", show], capture_output=True, text=True, cwd=ROOT)
    assert shown.returncode == 0, shown.stdout + shown.stderr
    script = shown.stdout
    # the script calls `robospec` by name: put this interpreter's console script on PATH
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    quoted = " ".join(shlex.quote(word) for word in ("robospec", *words))
    driver = (
        f"{script}\nCOMP_WORDS=({quoted})\nCOMP_CWORD={len(words)}\n"
        '_robospec_completion robospec\nprintf "%s\\n" "${COMPREPLY[@]}"\n'
    )
    result = subprocess.run(
        [bash, "--norc", "-c", driver], capture_output=True, text=True, env=env, cwd=ROOT
    )
    assert result.returncode == 0, result.stderr
    return [line for line in result.stdout.splitlines() if line]


def test_bash_completion_completes_command_names() -> None:
    assert _bash_complete("val") == ["validate"]
    assert set(_bash_complete("")) >= {"validate", "build", "schema", "check"}


@pytest.mark.slow
def test_bash_completion_completes_option_names_and_choices() -> None:
    assert "--format" in _bash_complete("validate", "--f")
    assert {"text", "json"} <= set(_bash_complete("validate", "--format", ""))
