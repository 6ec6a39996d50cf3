"""The README says what is so: every repository path it names exists (or is written by the
command the README names before it), and its time for the fast loop is read from a run."""

from __future__ import annotations

import re

from conftest import ROOT

README = (ROOT / "README.md").read_text(encoding="utf-8")
# paths the README names that a command it names makes: the path, and what makes it
MADE_BY = {
    ".venv/bin/mkdocs": ("scripts/demo", "docs"),  # the docs extra, set up by scripts/demo
    ".venv/bin/python": ("scripts/demo", "maniskill"),
    ".venv/bin/robospec": ("scripts/demo", "maniskill"),
    ".venv/bin/activate": ("scripts/demo", "maniskill"),
    ".venv/bin/ruff": ("scripts/test", "dev"),
    "out/fast-loop.json": ("scripts/test", "out/fast-loop.json"),
}


def _named_paths() -> set[str]:
    spans = re.findall(r"`([^`\s]+)`", README)
    return {
        span.rstrip(".,:")
        for span in spans
        if "/" in span
        # not the repository's: URLs, variables, the home folder, GitHub actions, patterns
        and not span.startswith(("http", "{", "<", "-", "'", "$", "~", "github/"))
        and not any(mark in span for mark in "*<")
    }


def test_every_path_the_readme_names_exists_or_a_named_command_makes_it() -> None:
    missing = []
    for path in sorted(_named_paths()):
        if path in MADE_BY:
            script, needle = MADE_BY[path]
            assert needle in (ROOT / script).read_text(encoding="utf-8"), (path, script)
            continue
        plain = path.split("::")[0]
        if not (ROOT / plain).exists() and not plain.startswith(("specs/my_", "robots/", "my_")):
            missing.append(path)
    assert not missing, f"the README names paths that do not exist: {missing}"


def test_the_readme_promises_no_time_it_did_not_measure() -> None:
    """A duration for the fast loop comes from out/fast-loop.json (scripts/test --fast writes
    it), not from a promise like "in under 90 seconds"."""
    assert not re.search(r"\bunder \d+ (?:s|seconds|minutes)\b", README)
    assert "out/fast-loop.json" in README


def test_bring_your_own_robot_is_described_with_the_robot_the_page_uses() -> None:
    page = (ROOT / "docs" / "bring-your-own-robot.md").read_text(encoding="utf-8")
    assert "Laikago" in page
    for text in (README, (ROOT / "docs" / "index.md").read_text(encoding="utf-8")):
        assert "pybullet's Panda" not in text
        assert "pybullet's Laikago" in text


def test_the_readme_says_first_where_the_robospec_command_is_after_set_up() -> None:
    """`robospec: command not found` after scripts/demo: the README's first section (before
    any other) says the command is .venv/bin/robospec, or robospec in the activated
    environment."""
    first = README.split("\n## ", 1)[0]
    assert "`.venv/bin/robospec" in first
    assert "`source .venv/bin/activate`" in first
    assert first.index("scripts/demo") < first.index(".venv/bin/robospec")
