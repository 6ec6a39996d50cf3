"""Text for people: each diagnostic's ``file:line:col: severity[CODE] message`` line (the same
line as :meth:`Diagnostic.format_text`, which tools grep), the source line it points at with a
caret under the key or value, then the hint — in the manner of rustc and ruff."""

from __future__ import annotations

from collections.abc import Sequence

import robospec.reporting.color as ansi
from robospec.diagnostics import Diagnostic, Severity
from robospec.reporting.excerpt import source_line, span_width
from robospec.reporting.summary import summary_line


class _Style:
    """ANSI styles when colour is on; empty strings otherwise, so the layout code is shared."""

    def __init__(self, on: bool) -> None:
        self.on = on

    def __call__(self, code: str, text: str) -> str:
        return f"{code}{text}{ansi.RESET}" if self.on else text


def render(diagnostics: Sequence[Diagnostic], files: int, *, color: bool = False) -> str:
    style = _Style(color)
    lines: list[str] = []
    for d in diagnostics:
        lines.extend(format_diagnostic(d, style))
    lines.append(summary_line(diagnostics, files))
    return "\n".join(lines)


def plain_lines(d: Diagnostic) -> list[str]:
    """One diagnostic as text without colour: its line, the excerpt with the caret, the hint."""
    return format_diagnostic(d, _Style(False))


def format_diagnostic(d: Diagnostic, style: _Style) -> list[str]:
    loc = d.location
    severity = {Severity.ERROR: ansi.ERROR, Severity.WARNING: ansi.WARNING}.get(
        d.severity, ansi.NOTE
    )
    lines = [
        f"{style(ansi.BOLD, f'{loc.file}:{loc.line}:{loc.column}:')} "
        f"{style(severity, f'{d.severity.value}[{d.code}]')} {d.message}"
    ]
    lines.extend(_excerpt(loc.file, loc.line, loc.column, style, severity))
    if d.hint:
        lines.append(f"    {style(ansi.HINT, 'hint:')} {d.hint}")
    return lines


def _excerpt(file: str, line: int, column: int, style: _Style, severity: str) -> list[str]:
    text = source_line(file, line)
    if text is None:
        return []
    text = _printable(text.rstrip())
    number = str(line)
    gutter = " " * len(number)
    # keep tabs in the padding so the caret lines up however the terminal expands them
    pad = "".join("\t" if ch == "\t" else " " for ch in text[: column - 1])
    pad += " " * max(0, column - 1 - len(text))
    carets = "^" * span_width(text, column)
    return [
        f"  {style(ansi.GUTTER, f'{number} |')} {text}",
        f"  {style(ansi.GUTTER, f'{gutter} |')} {pad}{style(severity, carets)}",
    ]


def _printable(text: str) -> str:
    """A spec may hold control characters (an escape sequence would drive the terminal):
    show them as U+FFFD, one for one, so columns still line up."""
    return "".join(ch if ch == "\t" or ch.isprintable() else "\ufffd" for ch in text)
