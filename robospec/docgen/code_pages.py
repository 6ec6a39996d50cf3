"""One page per diagnostic code (``docs/codes/RSxxx.md``), written from the examples the page
shows and from what robospec really reports for them."""

from __future__ import annotations

import sys
from pathlib import Path

from robospec.checks import BINDING_CHECKS, ROBOT_CHECKS
from robospec.diagnostics.codes import CODES, UNKNOWN_MOUNT, Code
from robospec.docgen.code_examples import (
    RESERVED_CODES,
    CodeExamples,
    RunExample,
    is_documented_only,
    load_code_examples,
)
from robospec.physics import (
    described,
    gravity,
    ground,
    keyframe_hold,
    loops,
    mimic_limits,
    mujoco_hold,
    random_actions,
    rating,
    self_contact,
    step_response,
    task_run,
    upstream_findings,
)

# the physics checks of `robospec check`, whose docstrings document RS501-RS508, RS518, RS519,
# RS521-RS527, RS530-RS535, RS545
PHYSICS_CHECKS = (
    described,
    rating,
    keyframe_hold,
    loops,
    mimic_limits,
    mujoco_hold,
    random_actions,
    step_response,
    self_contact,
    gravity,
    ground,
    task_run,
    upstream_findings,
)

LANGUAGES = {".yaml": "yaml", ".yml": "yaml", ".toml": "toml", ".urdf": "xml", ".xml": "xml"}
LANGUAGES |= {".xacro": "xml", ".srdf": "xml", ".json": "json", ".py": "python"}


def page_path(code: str) -> str:
    return f"codes/{code}.md"


def module_docs() -> dict[str, str]:
    """Docstrings of the check modules, by each code their first sentence names: the prose the
    rule's author wrote next to the rule."""
    checks = BINDING_CHECKS + ROBOT_CHECKS
    modules = [sys.modules[check.__module__] for check in checks] + list(PHYSICS_CHECKS)
    docs: dict[str, str] = {}
    for module in modules:
        doc = (module.__doc__ or "").strip()
        head = doc.split("\n\n", 1)[0]
        for code in CODES:
            if code in head:
                docs[code] = doc
    return docs


def all_code_pages(docs_dir: Path) -> dict[str, str]:
    docstrings = module_docs()
    return {
        page_path(code): code_page(entry, load_code_examples(docs_dir, code), docstrings.get(code))
        for code, entry in CODES.items()
    }


def code_page(entry: Code, examples: CodeExamples, docstring: str | None) -> str:
    lines = [f"# {entry.code}: {entry.title}", ""]
    severity = _severity(examples)
    if severity:
        lines += [f"Severity: **{severity}**.", ""]
    if examples.about:
        lines += [examples.about.strip(), ""]
    lines += _mend_lines(entry.code)
    if docstring:
        lines += [_docstring_markdown(docstring), ""]
    if examples.failing and examples.passing:
        lines += _run_sections(examples)
    elif entry.code in RESERVED_CODES:
        lines += [
            "!!! note",
            "",
            "    No check of this version reports this code; it stays listed because codes are",
            "    never reused.",
            "",
        ]
    elif is_documented_only(entry.code):
        lines += [
            "!!! note",
            "",
            "    This page's example is documented, not run when the docs are generated:",
            "    " + _why_not_run(entry.code),
            "",
        ]
    lines += ["[All diagnostic codes](../diagnostics.md)"]
    return "\n".join(lines).rstrip() + "\n"


def mends_for(code: str) -> list[str]:
    """The mend classes that mend the problem ``code`` reports (robospec.derive)."""
    from robospec.derive import MENDS

    return [mend.NAME for mend in MENDS if code in mend.FIXES]


def _mend_lines(code: str) -> list[str]:
    names = mends_for(code)
    if not names:
        return []
    links = ", ".join(f"[`{name}`](../mends.md#{name})" for name in names)
    return [
        f"**Mend:** robospec can mend this in a copy of the description it loads instead of "
        f"the file (`description: {{mend: ...}}`; `robospec new` writes it): {links}.",
        "",
    ]


def _why_not_run(code: str) -> str:
    if code.startswith(("RS56", "RS57", "RS66")):
        return "`robospec doc --images` draws pictures with MuJoCo's renderer (seconds per robot)."
    if code.startswith(("RS62", "RS63")):
        return "`robospec tune` runs SAPIEN physics (seconds per controller)."
    if code.startswith("RS6"):
        return (
            "`robospec inspect`, `new` and `doc` report it about files named on the command line."
        )
    if code.startswith("RS4"):
        return "`robospec import` reads a Python agent class, which imports ManiSkill (seconds)."
    if code.startswith("RS5"):
        # (tests/test_physics_checks.py runs a passing and a failing robot for each check)
        return "`robospec check` runs SAPIEN physics (seconds per robot)."
    return "no spec triggers it on purpose."


def _severity(examples: CodeExamples) -> str | None:
    if examples.failing is None:
        return None
    found = {d.severity.value for d in examples.failing.diagnostics if d.code == examples.code}
    return " or ".join(sorted(found)) or None


def _docstring_markdown(doc: str) -> str:
    """A check module's docstring as Markdown: reST literals (``x``) become code spans and a
    ``Passing::`` block becomes a YAML block."""
    body = doc.split(":", 1)[1].strip() if doc[:5] in CODES else doc
    body = body[:1].upper() + body[1:]
    out: list[str] = []
    in_block = False
    for line in body.replace("``", "`").splitlines():
        if in_block and line.strip() and not line.startswith("    "):
            while out and not out[-1].strip():
                out.pop()
            out += ["```", ""]
            in_block = False
        if line.rstrip().endswith("::"):
            out += [line.rstrip()[:-1], "", "```yaml"]
            in_block = True
        elif in_block:
            if line.strip() or out[-1] != "```yaml":
                out.append(line[4:])
        else:
            out.append(line)
    while out and not out[-1].strip():
        out.pop()
    if in_block:
        out.append("```")
    return "\n".join(out)


def _run_sections(examples: CodeExamples) -> list[str]:
    assert examples.failing and examples.passing
    shown: set[Path] = set()
    notes = _severity(examples) == "note"  # robospec said what it did: nothing failed
    mend = examples.code < UNKNOWN_MOUNT  # RS700-RS729: mends (RS730 on: parts)
    first, second = (
        ("the mend applied", "nothing to mend") if mend else ("what robospec did", "nothing to do")
    )
    lines = [f"## Example: {first}" if notes else "## Failing example", ""]
    lines += _example(examples.failing, examples.support_files, shown)
    lines += [f"## Example: {second}" if notes else "## Passing example", ""]
    lines += _example(examples.passing, examples.support_files, shown)
    if examples.more_failing:
        lines += ["## More failing examples", ""]
        for example in examples.more_failing:
            lines += _example(example, examples.support_files, shown)
    # (for developers, not on the page: the examples are docs/examples/codes/<code>/;
    # tests/test_docs.py checks that each page is current, and tests/test_spec_examples.py that
    # each failing example reports what docs/examples/codes/expected.toml says, where it says)
    return lines


def _example(example: RunExample, support: tuple[Path, ...], shown: set[Path]) -> list[str]:
    """The spec, the files it names that no earlier example showed, and robospec's report."""
    name = example.path.name
    lines = [f"`{name}`:", ""]
    text = example.text  # read from disk at each access
    lines += _fenced(text, LANGUAGES.get(example.path.suffix, "text"))
    for path in support:
        if path.name in text and path not in shown:
            shown.add(path)
            lines += [f"`{path.name}`:", ""]
            lines += _fenced(path.read_text(encoding="utf-8"), LANGUAGES.get(path.suffix, "text"))
    folder = f"docs/examples/codes/{example.path.parent.name}/"
    lines += [f"In `{folder}`, robospec prints:", ""]
    lines += _fenced(f"$ robospec validate {name}\n{example.report}", "console")
    return lines


def _fenced(text: str, language: str) -> list[str]:
    fence = "````" if "```" in text else "```"
    return [f"{fence}{language}", text.rstrip("\n"), fence, ""]
