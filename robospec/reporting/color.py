"""Whether text output is coloured, and the ANSI styles it uses.

Precedence, first match wins:

1. ``--color always`` / ``--color never`` — a per-command choice overrides the environment
   (https://no-color.org: "command-line arguments should override $NO_COLOR");
2. ``NO_COLOR`` set and non-empty: no colour;
3. ``FORCE_COLOR`` set, non-empty and not ``0``/``false``: colour (CI logs that render ANSI);
4. ``TERM=dumb``: no colour;
5. otherwise colour exactly when the stream is a terminal.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from typing import TextIO


class ColorChoice(str, enum.Enum):
    auto = "auto"
    always = "always"
    never = "never"


def use_color(choice: str, stream: TextIO, environ: Mapping[str, str]) -> bool:
    if choice == ColorChoice.always.value:
        return True
    if choice == ColorChoice.never.value:
        return False
    if environ.get("NO_COLOR"):
        return False
    if environ.get("FORCE_COLOR", "").lower() not in ("", "0", "false"):
        return True
    if environ.get("TERM") == "dumb":
        return False
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False


RESET = "\x1b[0m"
BOLD = "\x1b[1m"
ERROR = "\x1b[1;31m"
WARNING = "\x1b[1;33m"
NOTE = "\x1b[1;32m"
GUTTER = "\x1b[1;34m"
HINT = "\x1b[1;36m"
