"""The golden modules: what robospec generates for the Panda, Fetch and the two-link robot,
kept in ``tests/golden/`` so that a change to the generated code shows in review as a diff.

``tests/test_generated_code.py`` fails while they are out of date. After changing the emitter on
purpose, write them again and read the diff::

    .venv/bin/python tests/golden_modules.py --write
    git diff tests/golden
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from conftest import MANISKILL_SPECS, PANDA_SPEC, ROOT, TWOLINK_SPEC

GOLDEN = ROOT / "tests" / "golden"
SPECS = (PANDA_SPEC, MANISKILL_SPECS / "fetch.yaml", TWOLINK_SPEC)


def generated_modules() -> dict[str, str]:
    """``{file name: source}`` of each golden spec's module, as ``robospec build`` writes it
    (built in a temporary folder: the modules then name their specs by file name only)."""
    from robospec.output.package import plan_package
    from robospec.pipeline import compile_spec

    compiled = [compile_spec(spec) for spec in SPECS]
    for item in compiled:
        assert item.robot is not None, [d.format_text() for d in item.diagnostics]
    with tempfile.TemporaryDirectory() as folder:
        files = plan_package(compiled, Path(folder) / "robospec_agents")
    # the agent modules: not the package's __init__, nor its support module (a copy of
    # robospec/maniskill/render_fallback.py, which tests/test_headless.py compares)
    return {
        name: text
        for name, text in files.items()
        if name.endswith(".py") and name != "__init__.py" and not name.startswith("_")
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="write tests/golden/ again")
    arguments = parser.parse_args()
    modules = generated_modules()
    stale = sorted(
        name
        for name, text in modules.items()
        if not (GOLDEN / name).is_file() or (GOLDEN / name).read_text(encoding="utf-8") != text
    )
    if arguments.write:
        GOLDEN.mkdir(exist_ok=True)
        for name, text in modules.items():
            (GOLDEN / name).write_text(text, encoding="utf-8")
        print(f"wrote {len(modules)} golden module(s); changed: {', '.join(stale) or 'none'}")
        return 0
    print("\n".join(f"stale: {name}" for name in stale) or "golden modules are up to date")
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
