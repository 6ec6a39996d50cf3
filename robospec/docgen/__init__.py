"""Generate the parts of ``docs/`` that restate the code, so they cannot drift from it (a test
compares the committed files with this output):

- ``diagnostics.md``: the table of codes (``robospec/diagnostics/codes.py``), linking to
- ``codes/RSxxx.md``: one page per code, with its examples from ``docs/examples/codes/`` and
  what robospec really reports for them,
- ``reference.md``: every spec field, from the JSON Schema of the models,
- ``cli-reference.md``: every command's ``--help``.

    python -m robospec.docgen --write docs     # regenerate all of them
    python -m robospec.docgen > docs/diagnostics.md
"""

from __future__ import annotations

from pathlib import Path

from robospec.docgen.cli_page import cli_reference_markdown
from robospec.docgen.code_pages import all_code_pages
from robospec.docgen.diagnostics_page import diagnostics_markdown
from robospec.docgen.reference_page import reference_markdown

CODES_FOLDER = "codes"

__all__ = ["diagnostics_markdown", "generated_pages", "stale_pages", "write_pages"]


def generated_pages(docs_dir: Path) -> dict[str, str]:
    """Every generated page, by its path relative to ``docs_dir``."""
    return {
        "diagnostics.md": diagnostics_markdown(),
        "reference.md": reference_markdown(),
        "cli-reference.md": cli_reference_markdown(),
        **all_code_pages(docs_dir),
    }


def stale_pages(docs_dir: Path, pages: dict[str, str]) -> list[str]:
    """Pages whose committed text differs from ``pages``, and code pages no code has any more."""
    stale = [
        name
        for name, text in pages.items()
        if not (docs_dir / name).is_file() or (docs_dir / name).read_text(encoding="utf-8") != text
    ]
    stale += [
        f"{CODES_FOLDER}/{path.name}"
        for path in sorted((docs_dir / CODES_FOLDER).glob("*.md"))
        if f"{CODES_FOLDER}/{path.name}" not in pages
    ]
    return stale


def write_pages(docs_dir: Path) -> list[str]:
    """Regenerate every page under ``docs_dir``; returns the names that changed."""
    pages = generated_pages(docs_dir)
    changed = stale_pages(docs_dir, pages)
    for name in changed:
        path = docs_dir / name
        if name in pages:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(pages[name], encoding="utf-8")
        else:
            path.unlink()  # a code page whose code is gone
    return changed
