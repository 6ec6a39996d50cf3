"""The `robospec` command line. Exit codes: 0 no errors, 1 errors, 2 usage error.

The commands live in robospec.cli.commands (a typer app). Building that app imports typer, click
and rich; a plain `robospec validate PATH... [--format F] [--color C]`, the command run on every
save and commit, skips it (robospec.cli.fast_validate) with the same output and exit status.
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from robospec.cli.commands import app


def main() -> None:
    try:
        from robospec.cli import fast_validate

        plain = fast_validate.parse(sys.argv[1:], os.environ)
        if plain is not None:
            sys.exit(fast_validate.run(plain))
        from robospec.cli.commands import app

        # a fixed name, so that `python -m robospec.cli` shows and completes as `robospec`
        app(prog_name="robospec")
    except KeyboardInterrupt:
        sys.exit(130)


def __getattr__(name: str) -> Any:
    # `from robospec.cli import app` (tests, docgen) builds the typer app only when asked
    if name == "app":
        from robospec.cli.commands import app

        return app
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["app", "main"]
