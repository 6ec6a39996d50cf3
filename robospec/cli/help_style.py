"""How robospec's help is written, and the typer classes that keep it so.

The convention, for every command and option (tests/test_cli_help.py checks each one, so a new
command or flag is held to it too):

- A command's help is its docstring, written as paragraphs separated by blank lines. Lines
  inside a paragraph may be wrapped in the source (at 100 columns, as ruff wants): they are
  joined here, and the terminal wraps the paragraph at its own width. A line that starts with
  ``Example:`` stays a line of its own, so examples can be copied one per line.
- An option's help is one sentence fragment, lower case, on one logical line (implicit string
  concatenation, no ``\\n``).
- A boolean option is a flag (``--force``): the help shows no type for it, and it takes no
  value. Name it after what it turns on.
- Every value is shown as a placeholder in capitals (``SPEC...``, ``FILE``, ``--out DIR``,
  ``--steps N``), never as a Python type (``<list[Path]>``, ``<str>``): an argument is named
  by its placeholder alone, in the usage line too (``[FILE]`` where it may be left out); an
  option's placeholder is its ``metavar``, else its name in capitals; a choice shows its
  choices (``<text|json>``).
- A command that writes files says what it wrote (``wrote PATH``), on stdout.
- A command that needs an extra says so: ``@app.command(needs=("maniskill",))``. It then
  stops at once, exit 2, naming the extra, where that extra is not installed (and so does any
  command that meets a missing module of a known extra: robospec/cli/extras.py).
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import Any, NoReturn

import typer
from typer.core import TyperArgument, TyperCommand, TyperGroup, TyperOption

from robospec.cli.extras import extra_of, missing_module, needs_extra_message

EXAMPLE = "Example:"


def reflow(text: str | None) -> str | None:
    """``text`` (a docstring) with the line breaks inside each paragraph removed, except before
    an ``Example:`` line."""
    if text is None:
        return None
    paragraphs = []
    for paragraph in inspect.cleandoc(text).split("\n\n"):
        lines: list[str] = []
        for line in paragraph.splitlines():
            line = line.strip()
            if lines and not line.startswith(EXAMPLE) and not lines[-1].startswith(EXAMPLE):
                lines[-1] = f"{lines[-1]} {line}"
            else:
                lines.append(line)
        paragraphs.append("\n".join(lines))
    return "\n\n".join(paragraphs)


class _Placeholder(TyperArgument):
    """An argument shown as its placeholder alone: typer shows an argument's Python type beside
    its name (``SPEC <list[Path]>``) and wraps it in braces in the usage line (``{SPEC}...``)."""

    def display_type_rich(self, ctx: Any) -> str | None:
        return None

    def _usage_display_name(self) -> str:
        name = self.display_name_raw if self.required else f"[{self.display_name_raw}]"
        return name + ("..." if self.nargs != 1 else "")


def _readable(params: list[Any]) -> list[Any]:
    """``params`` shown by placeholders, as the convention above says."""
    for param in params:
        if isinstance(param, TyperOption):
            # typer shows every option's type, "<bool>" for a flag too, which reads as if the
            # flag took a value (`--force <bool>`); an empty metavar shows nothing there
            if param.is_flag and param.metavar is None:
                param.metavar = ""
            elif param.metavar is None and not param.type_descriptor.is_choice:
                param.metavar = (param.name or "value").upper()
        elif isinstance(param, TyperArgument) and not isinstance(param, _Placeholder):
            if param.metavar is None:
                param.metavar = (param.name or "value").upper()
            param.__class__ = _Placeholder  # the same argument, shown without its type
    return params


class ReflowCommand(TyperCommand):
    """A command whose help follows the convention above."""

    def __init__(self, *args: Any, help: str | None = None, **kwargs: Any) -> None:
        super().__init__(*args, help=reflow(help), **kwargs)

    def get_params(self, ctx: Any) -> list[Any]:
        return _readable(super().get_params(ctx))


class ReflowGroup(TyperGroup):
    """The top level (``robospec --help``), held to the same convention."""

    def __init__(self, *args: Any, help: str | None = None, **kwargs: Any) -> None:
        super().__init__(*args, help=reflow(help), **kwargs)

    def get_params(self, ctx: Any) -> list[Any]:
        return _readable(super().get_params(ctx))


class App(typer.Typer):
    """A typer app whose commands are ReflowCommands unless told otherwise: a command added
    with ``@app.command()`` follows the convention without anyone remembering it."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(cls=ReflowGroup, **kwargs)

    def command(
        self,
        name: str | None = None,
        *,
        needs: tuple[str, ...] = (),
        cls: type[TyperCommand] | None = None,
        **kwargs: Any,
    ) -> Any:
        register = super().command(name, cls=cls or ReflowCommand, **kwargs)

        def decorator(function: Callable[..., Any]) -> Any:
            command = name or function.__name__.replace("_", "-")

            @functools.wraps(function)
            def run(*args: Any, **kwargs: Any) -> Any:
                for extra in needs:
                    missing = missing_module(extra)
                    if missing is not None:
                        _stop(command, extra, missing)
                try:
                    return function(*args, **kwargs)
                except ModuleNotFoundError as exc:
                    missing_extra = extra_of(exc.name)
                    if missing_extra is None:
                        raise
                    _stop(command, missing_extra, exc.name or missing_extra)

            register(run)
            return function

        return decorator


def _stop(command: str, extra: str, module: str) -> NoReturn:
    typer.echo(needs_extra_message(command, extra, module), err=True)
    raise typer.Exit(2)
