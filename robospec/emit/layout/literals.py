"""Literals as ``ruff format`` writes them: strings, f-strings, docstrings and numbers.

Text from specs and robot descriptions (names, paths) enters generated code only through these
functions, so they are what keeps it data: every quote, backslash and line break is escaped,
whatever the text holds. Characters that are not printable ASCII or Latin letters are written
as escapes too: every character in a generated module is then one column wide, so this
emitter, ``ruff format`` and ``ruff check`` all measure a line the same way (East Asian wide
characters, combining marks and emoji would not be), and a name cannot hide a line separator
or a character that looks like another.
"""

from __future__ import annotations

import ast

# Latin-1 Supplement and Latin Extended-A/B: letters a spec may well use, each one column wide
_LATIN = range(0xA1, 0x250)
_SOFT_HYPHEN = 0xAD  # invisible: escaped like any other format character
_SHORT_ESCAPES = {"\\": "\\\\", "\n": "\\n", "\r": "\\r", "\t": "\\t"}


def _is_literal(character: str) -> bool:
    code = ord(character)
    return 0x20 <= code < 0x7F or (code in _LATIN and code != _SOFT_HYPHEN)


def _escape(text: str, quote: str) -> str:
    out = []
    for character in text:
        if character in _SHORT_ESCAPES:
            out.append(_SHORT_ESCAPES[character])
        elif character == quote:
            out.append("\\" + quote)
        elif _is_literal(character):
            out.append(character)
        else:
            out.append(_code_escape(ord(character)))
    return "".join(out)


def _code_escape(code: int) -> str:
    # lower-case hex digits, as ruff normalises them
    if code < 0x100:
        return f"\\x{code:02x}"
    if code < 0x10000:
        return f"\\u{code:04x}"
    return f"\\U{code:08x}"


def _quote_for(*texts: str) -> str:
    """Double quotes, unless the text holds more double quotes than single ones (ruff's
    choice: the one that needs fewer escapes, double on a tie)."""
    singles = sum(text.count("'") for text in texts)
    doubles = sum(text.count('"') for text in texts)
    return "'" if singles < doubles else '"'


def string_literal(value: str) -> str:
    quote = _quote_for(value)
    return quote + _escape(value, quote) + quote


def fstring_literal(parts: list[str | tuple[str]]) -> str:
    """An f-string from literal text and ``(name,)`` placeholders: ``f"{NAME}/robots"``.
    Braces in the text are doubled; the names are the emitter's own identifiers."""
    texts = [part for part in parts if isinstance(part, str)]
    quote = _quote_for(*texts)
    out = ["f", quote]
    for part in parts:
        if isinstance(part, str):
            out.append(_escape(part, quote).replace("{", "{{").replace("}", "}}"))
        else:
            out.append("{" + part[0] + "}")
    out.append(quote)
    return "".join(out)


def docstring_lines(text: str) -> list[str]:
    """The lines of a docstring's body, escaped for triple double quotes. A closing line break
    in ``text`` gives a last empty line: the closing quotes then stand on their own line."""
    return [_escape(line, '"') for line in text.split("\n")]


def number_literal(text: str) -> str:
    """A Python number literal written as ruff writes it: lower-case ``e`` and prefixes,
    upper-case hex digits, no ``+`` in an exponent, and ``0.5``/``5.0`` for ``.5``/``5.``."""
    lowered = text.lower()
    if lowered.startswith(("0x", "0o", "0b")):
        digits = text[2:].upper() if lowered.startswith("0x") else text[2:]
        return lowered[:2] + digits
    mantissa, e, exponent = lowered.partition("e")
    if mantissa.startswith("."):
        mantissa = "0" + mantissa
    if mantissa.endswith("."):
        mantissa += "0"
    if exponent.startswith("+"):
        exponent = exponent[1:]
    return mantissa + e + exponent


def number_text(node: ast.Constant) -> str:
    """A number as the spec wrote it (the emitter sets ``node.text``), else as Python
    writes it; either way as ruff writes number literals."""
    text = getattr(node, "text", None)
    return number_literal(text if text is not None else repr(node.value))


def constant_text(node: ast.Constant) -> str:
    value = node.value
    if isinstance(value, str):
        return string_literal(value)
    if value is None or isinstance(value, bool):
        return str(value)
    if value is Ellipsis:
        return "..."
    if isinstance(value, (int, float)):
        return number_text(node)
    raise TypeError(f"the emitter does not write {type(value).__name__} constants")


def fstring_text(node: ast.JoinedStr) -> str:
    parts: list[str | tuple[str]] = []
    for value in node.values:
        if isinstance(value, ast.Constant) and isinstance(value.value, str):
            parts.append(value.value)
        elif (
            isinstance(value, ast.FormattedValue)
            and isinstance(value.value, ast.Name)
            and value.conversion == -1
            and value.format_spec is None
        ):
            parts.append((value.value.id,))
        else:
            raise TypeError("the emitter writes f-strings of text and plain names only")
    return fstring_literal(parts)
