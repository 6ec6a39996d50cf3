"""``python -m robospec.docgen``: print docs/diagnostics.md, or ``--write DOCS`` to regenerate
every generated page under DOCS."""

from __future__ import annotations

import sys
from pathlib import Path

from robospec.docgen import diagnostics_markdown, write_pages


def main(argv: list[str]) -> int:
    if not argv:
        sys.stdout.write(diagnostics_markdown())
        return 0
    if len(argv) == 2 and argv[0] == "--write":
        for name in write_pages(Path(argv[1])):
            print(f"wrote {name}")
        return 0
    print("usage: python -m robospec.docgen [--write DOCS_DIR]", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
