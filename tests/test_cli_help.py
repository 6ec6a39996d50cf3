"""Every command explains itself: ``--help`` shows a runnable example, and the shell completion
that ``robospec --show-completion`` prints really completes commands and option values in bash."""

from __future__ import annotations

import itertools
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import typer.main
from conftest import ROOT, fast_first, run_robospec
from typer.testing import CliRunner

from robospec.cli import app
from robospec.cli.help_style import EXAMPLE
from robospec.docgen.cli_page import HELP_ENV

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


def _help(args: list[str], width: int) -> str:
    env = {**HELP_ENV, "COLUMNS": str(width)}
    result = CliRunner().invoke(app, [*args, "--help"], env=env, prog_name="robospec")
    assert result.exit_code == 0, result.output
    return result.output


def _description(help_text: str) -> list[list[str]]:
    """The paragraphs of the text between ``Usage:`` and the first panel, as lines."""
    lines = help_text.splitlines()
    start = next(i for i, line in enumerate(lines) if "Usage:" in line) + 1
    end = next(i for i, line in enumerate(lines) if line.lstrip().startswith("╭"))
    paragraphs: list[list[str]] = [[]]
    for line in lines[start:end]:
        if line.strip():
            paragraphs[-1].append(line.strip())
        elif paragraphs[-1]:
            paragraphs.append([])
    return [paragraph for paragraph in paragraphs if paragraph]


@pytest.mark.parametrize("name", ["", *COMMANDS])
@pytest.mark.parametrize("width", [60, 100])
def test_every_command_help_is_written_for_reflow(name: str, width: int) -> None:
    """Each paragraph is wrapped by the terminal, at its width, not where the source broke its
    lines: a line ends early only before an ``Example:`` line (robospec/cli/help_style.py)."""
    paragraphs = _description(_help([name] if name else [], width))
    assert paragraphs
    for paragraph in paragraphs:
        for line, following in itertools.pairwise(paragraph):
            if following.startswith(EXAMPLE):
                continue
            # rich leaves a column each side; the next word would have fitted on this line
            fits = len(line) + 1 + len(following.split()[0]) <= width - 2
            assert not fits, f"robospec {name} --help wraps early:\n{line}\n{following}"


@pytest.mark.parametrize("name", ["", *COMMANDS])
def test_every_boolean_option_reads_as_a_flag(name: str) -> None:
    """``--force``, not ``--force <bool>``: a flag takes no value, so its help shows none."""
    text = _help([name] if name else [], 100)
    assert "<bool>" not in text
    command = typer.main.get_command(app)
    if name:
        command = command.commands[name]  # type: ignore[attr-defined]
    for param in command.params:
        assert "\n" not in (getattr(param, "help", None) or ""), param.name


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


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_bash_completion_completes_command_names() -> None:
    assert _bash_complete("val") == ["validate"]
    assert set(_bash_complete("")) >= {"validate", "build", "schema", "check"}


@pytest.mark.slow
def test_bash_completion_completes_option_names_and_choices() -> None:
    assert "--format" in _bash_complete("validate", "--f")
    assert {"text", "json"} <= set(_bash_complete("validate", "--format", ""))


def test_version_prints_the_version_robospec_says_everywhere() -> None:
    from robospec.version import __version__

    result = run_robospec("--version")
    assert result.returncode == 0, result.stderr
    assert result.stdout == f"robospec {__version__}\n"


# what typer writes for a value's Python type, e.g. `<list[Path]>`, `<str>`, `<int range>`
_PYTHON_TYPE = re.compile(
    r"<(?:list\[[^>]*\]|str|path|int|float|bool|tuple|uuid|datetime)(?: range)?>"
)
# a placeholder in a usage line: capitals (FILE, SPEC, MODULE:CLASS), maybe optional, maybe more
_PLACEHOLDER = re.compile(r"^\[?[A-Z][A-Z0-9_:]*\]?(?:\.\.\.)?$")


@pytest.mark.parametrize("name", ["", *COMMANDS])
def test_every_help_shows_values_as_placeholders_not_python_types(name: str) -> None:
    """``robospec validate [OPTIONS] SPEC...``, ``--out FILE``: never ``{spec}``,
    ``<list[Path]>`` or ``<str>``; a choice shows its choices (``<text|json>``)."""
    text = _help([name] if name else [], 100)
    assert not _PYTHON_TYPE.search(text), _PYTHON_TYPE.search(text)
    for shown in re.findall(r"<([^<>\s]*)>", text):
        if "|" in shown:  # a choice: its values, each a lower-case word
            assert all(re.fullmatch(r"[a-z][a-z0-9_]*", v) for v in shown.split("|")), shown
    usage = next(line for line in text.splitlines() if "Usage:" in line)
    pieces = usage.split("Usage:", 1)[1].split()[1:]  # after the program's name
    pieces = [p for p in pieces if p not in (name, "[OPTIONS]", "COMMAND", "[ARGS]...")]
    assert all(_PLACEHOLDER.match(piece) for piece in pieces), usage


def test_an_optional_argument_is_shown_in_brackets_and_a_required_one_bare() -> None:
    from typer.core import TyperArgument

    from robospec.cli.help_style import _readable

    required = TyperArgument(param_decls=["spec"], type_descriptor=_descriptor(), required=True)
    optional = TyperArgument(param_decls=["file"], type_descriptor=_descriptor(), required=False)
    shown = [p.get_usage_pieces(None) for p in _readable([required, optional])]
    assert shown == [["SPEC"], ["[FILE]"]]
    assert required.display_type_rich(None) is None  # no `<path>` beside its name


def _descriptor() -> object:
    from typer.core import TyperArgument

    command = typer.main.get_command(app).commands["inspect"]  # type: ignore[attr-defined]
    argument = next(p for p in command.params if isinstance(p, TyperArgument))
    return argument.type_descriptor


def _journey() -> list[str]:
    """The commands of the README's "From a URDF to a registered robot" block, in order."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = readme.split("## From a URDF to a registered robot", 1)[1].split("```sh\n", 1)[1]
    block = block.split("```", 1)[0]
    return [line.split()[1] for line in block.splitlines() if line.startswith("robospec ")]


def test_the_top_level_help_lists_commands_in_the_order_of_the_readmes_journey() -> None:
    """A newcomer reads the commands in the order they use them: inspect and new first, then
    validate, ..., build and solve last of the journey; the other commands come after it."""
    from robospec.docgen.cli_page import command_names

    journey = _journey()
    assert journey[:2] == ["inspect", "new"] and journey[-2:] == ["build", "solve"], journey
    listed = command_names()
    assert listed[: len(journey)] == journey
    text = _help([], 100)
    at = [text.index(f"│ {name} ") for name in listed]
    assert at == sorted(at)


def test_every_page_spells_new_one_way_the_description_first() -> None:
    """``robospec new FILE -o SPEC`` in the README and on every docs page: the description is
    the command's one positional argument, with no option that names it another way."""
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    spelled = [p.name for p in pages if "--from-urdf" in p.read_text(encoding="utf-8")]
    assert not spelled, spelled
    assert "--from-urdf" not in _help(["new"], 100)
    assert re.search(r"Usage: robospec new \[OPTIONS\] FILE *\n", _help(["new"], 100))
