"""`robospec validate` without building the typer app: the command people run most often (in
editors, pre-commit hooks and CI) starts in a fraction of the time.

Only the plain form is taken here: ``validate`` followed by spec paths and at most the options
``--format/-f FORMAT`` and ``--color WHEN`` (also as ``--format=FORMAT``), with valid values.
Anything else (``--help``, an unknown option, a bad value, no paths, shell completion) returns
None and the typer app handles it, so usage errors and help read exactly as before. The output
and exit status are those of the typer command: tests/test_cli_fast_path.py runs both.
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from robospec.reporting import Format, render
from robospec.reporting.color import ColorChoice, use_color

FORMATS = tuple(f.value for f in Format)
COLORS = tuple(c.value for c in ColorChoice)
_OPTIONS = {"--format": "format", "-f": "format", "--color": "color"}
# what click.echo strips from output that is not meant to be coloured
_ANSI = re.compile(r"\033\[[;?0-9]*[a-zA-Z]")


@dataclass(frozen=True)
class ValidateArgs:
    paths: list[Path]
    format: str = "text"
    color: str = "auto"
    silence: frozenset[str] = frozenset()


def parse(argv: Sequence[str], environ: Mapping[str, str]) -> ValidateArgs | None:
    """``argv`` (without the program name) as a plain validate command, or None."""
    if not argv or argv[0] != "validate" or "_ROBOSPEC_COMPLETE" in environ:
        return None
    paths: list[Path] = []
    chosen = {"format": "text", "color": "auto"}
    tokens = list(argv[1:])
    while tokens:
        token = tokens.pop(0)
        if not token.startswith("-"):
            paths.append(Path(token))
            continue
        name, has_value, value = token.partition("=")
        if name not in _OPTIONS or (has_value and name == "-f"):
            return None
        if not has_value:
            if not tokens:
                return None
            value = tokens.pop(0)
        key = _OPTIONS[name]
        if value not in (FORMATS if key == "format" else COLORS):
            return None
        chosen[key] = value
    if not paths:
        return None
    return ValidateArgs(paths, chosen["format"], chosen["color"])


def run(args: ValidateArgs) -> int:
    """Validate, print the report on stdout; the exit status."""
    from robospec.diagnostics import has_errors
    from robospec.pipeline import compile_all

    compiled, diagnostics = compile_all(args.paths, silence=args.silence)
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    colored = use_color(args.color, sys.stdout, os.environ)
    text = render(diagnostics, len(compiled), args.format, color=colored)
    if not colored:
        text = _ANSI.sub("", text)
    try:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()
    except BrokenPipeError:
        # as click does: a closed pipe (`robospec validate ... | head`) is exit 1, quietly
        sys.stdout = None
        return 1
    return 1 if has_errors(diagnostics) else 0
