"""The docs site: generated pages are current, every diagnostic code has an example that really
produces it, the site builds with MkDocs in strict mode, and what the user guide shows (spec
snippets, commands and their output, generated code) is what robospec really does."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from conftest import DOCS, ROOT

from robospec.diagnostics import has_errors
from robospec.diagnostics.codes import CODES
from robospec.docgen import generated_pages, stale_pages
from robospec.docgen.code_examples import (
    EXPECTED_FILE,
    RESERVED_CODES,
    is_documented_only,
    load_code_examples,
)
from robospec.docgen.code_pages import module_docs
from robospec.pipeline import compile_spec

EXAMPLES = DOCS / "examples"
GUIDE_PAGES = ["index.md", "tutorial.md", "cli.md", "editors.md", "ci.md"]
REGENERATE = "run: python -m robospec.docgen --write docs"

# the passing example of RS055 still warns with RS055 until ManiSkill downloads the robot
PASS_MAY_WARN_WITH_OWN_CODE = {"RS055"}
# failing examples that also note what their spec's own section changed in the derived copy:
# a planar base is added (RS780) before the checks find that it does not belong there
FAIL_ALSO_NOTES = {"RS341": "RS780", "RS342": "RS780"}

# a fenced block, with the `<!-- ... -->` line before it if there is one: `<!-- generated:
# FILE -->` (an excerpt of a file robospec writes) or `<!-- not a spec -->` (YAML of other tools)
FENCE = re.compile(
    r"^(?:<!-- (?P<marker>[^>]*) -->\n)?( *)```(?P<lang>\w*)\n(?P<body>.*?)^\2```$", re.M | re.S
)
NOT_A_SPEC = "not a spec"


def fenced_blocks(page: str, language: str) -> list[tuple[str, str | None]]:
    """(body, the marker before it) of each block of ``language`` on ``page``."""
    text = (DOCS / page).read_text(encoding="utf-8")
    return [(m["body"], m["marker"]) for m in FENCE.finditer(text) if m["lang"] == language]


# -- generated pages


@pytest.mark.slow  # over a second: CI runs it, the fast loop does not
def test_generated_pages_equal_the_generator_output() -> None:
    pages = generated_pages(DOCS)
    assert stale_pages(DOCS, pages) == [], REGENERATE


def _python_refs_of_failing_examples() -> set[str]:
    """The top-level modules the code examples name in ``extends`` or a hook."""
    named = set()
    for spec in (EXAMPLES / "codes").rglob("*.*ml"):
        for found in re.findall(
            r"""["']([A-Za-z_][\w.]*):\w+["']""", spec.read_text("utf-8", errors="replace")
        ):
            named.add(found.split(".")[0])
    return named


@pytest.mark.slow
def test_generated_pages_do_not_depend_on_what_else_is_importable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A reader who follows the tutorial in the clone leaves a `my_robots` package there; a page
    made from an example that names a module which happens not to exist would change with it.
    Every top-level module the examples name that cannot be imported here is made importable
    (empty), and the pages must stay as they are."""
    import importlib.util

    absent = {m for m in _python_refs_of_failing_examples() if importlib.util.find_spec(m) is None}
    for module in absent | {"my_robots"}:
        (tmp_path / module).mkdir()
        (tmp_path / module / "__init__.py").write_text("", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert stale_pages(DOCS, generated_pages(DOCS)) == [], (
        "a page depends on a module not being importable: name a module inside an installed "
        f"package instead ({sorted(absent)})"
    )


def test_the_diagnostics_table_links_a_page_for_every_code() -> None:
    table = (DOCS / "diagnostics.md").read_text(encoding="utf-8")
    for code in CODES:
        assert f"| [{code}](codes/{code}.md) |" in table
        assert (DOCS / "codes" / f"{code}.md").is_file(), REGENERATE
        assert len(code) == 5 and code.startswith("RS") and code[2:].isdigit()


@pytest.mark.slow
def test_generated_pages_name_no_path_of_this_machine() -> None:
    for name, text in generated_pages(DOCS).items():
        assert str(ROOT) not in text, name
        assert str(Path.home()) not in text, name


def test_the_field_reference_has_every_field_of_the_schema() -> None:
    from robospec.schema import spec_schema

    reference = (DOCS / "reference.md").read_text(encoding="utf-8")
    schema = spec_schema()
    for name, model in [("Top level", schema), *schema["$defs"].items()]:
        section = reference.split(f"\n## {name}\n", 1)[1].split("\n## ", 1)[0]
        for field in model.get("properties", {}):
            assert f"| `{field}` |" in section, (name, field)


# -- one page per code, from examples that really produce the code


@pytest.mark.parametrize("code", list(CODES))
def test_each_code_has_a_failing_and_a_passing_example_or_a_documented_one(code: str) -> None:
    examples = load_code_examples(DOCS, code)
    if examples.failing is None and examples.passing is None:
        assert is_documented_only(code), (
            f"{code} has no example: add docs/examples/codes/{code}/fail.yaml and pass.yaml"
        )
        documented = (examples.about or "") + module_docs().get(code, "")
        assert documented.strip(), f"{code} needs docs/examples/codes/{code}/about.md"
        if code not in RESERVED_CODES and code not in module_docs():
            assert "```" in documented, f"{code}'s about.md needs an example"
        return
    assert examples.failing is not None, f"{code} has a passing example but no failing one"
    assert examples.passing is not None, f"{code} has a failing example but no passing one"
    failing = examples.failing
    also = {FAIL_ALSO_NOTES[code]} if code in FAIL_ALSO_NOTES else set()
    assert failing.codes == {code, *also}, [d.format_text() for d in failing.diagnostics]
    assert not also & failing.error_codes
    passing = examples.passing
    assert not passing.error_codes, [d.format_text() for d in passing.diagnostics]
    if code in PASS_MAY_WARN_WITH_OWN_CODE:
        assert code not in passing.error_codes
    else:
        assert code not in passing.codes, [d.format_text() for d in passing.diagnostics]


def _reporting_sources() -> list[Path]:
    """robospec's modules, less the code table and the docs generator (which name every code)."""
    return [
        p
        for p in (ROOT / "robospec").rglob("*.py")
        if p.name != "codes.py" and "docgen" not in p.parts
    ]


@pytest.mark.parametrize("code", sorted(RESERVED_CODES))
def test_a_reserved_code_is_reported_nowhere(code: str) -> None:
    for source in _reporting_sources():
        assert f'"{code}"' not in source.read_text(encoding="utf-8"), source


def test_every_example_folder_belongs_to_a_code() -> None:
    for entry in (EXAMPLES / "codes").iterdir():
        if entry.name != EXPECTED_FILE:
            assert entry.is_dir() and entry.name in CODES, entry


# a spec error, an error located in a description file beside the spec, and a warning located
# in ManiSkill's assets: the three ways a page's report names files
CLI_SAMPLES = ["RS201", "RS051", "RS309"]


@pytest.mark.parametrize("code", CLI_SAMPLES)
def test_a_code_page_shows_what_the_cli_prints_in_the_example_folder(code: str) -> None:
    page = (DOCS / "codes" / f"{code}.md").read_text(encoding="utf-8")
    shown = re.findall(r"```console\n\$ (robospec validate \S+)\n(.*?)\n```", page, re.S)
    assert [command for command, _ in shown] == [
        "robospec validate fail.yaml",
        "robospec validate pass.yaml",
    ]
    for command, output in shown:
        assert _run_console(command, EXAMPLES / "codes" / code) == output, command


# -- the site builds in strict mode


def _mkdocs(config: Path, site: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(config), "-d", str(site)],
        capture_output=True,
        text=True,
        timeout=120,
        # Material's banner about its successor is not a warning about these docs
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )


def _nav_pages(node: object, section: str = "") -> list[tuple[str, str]]:
    """(top-level nav section, page) for every page of mkdocs.yml's nav."""
    if isinstance(node, str):
        return [(section, node)]
    if isinstance(node, list):
        return [page for item in node for page in _nav_pages(item, section)]
    if isinstance(node, dict):
        return [
            page
            for title, child in node.items()
            for page in _nav_pages(child, section or str(title))
        ]
    return []


# written by tests/corpus.py --write from the corpus journeys (its words say how it is made)
GENERATED_BY_THE_CORPUS = {"robots.md"}


def test_user_pages_hold_no_developer_notes() -> None:
    """Which test proves what, and how to run it, is for the Development pages: a user page
    (and every diagnostic code's page) names no test file, no CI script, no repository tool."""
    config = _mkdocs_config()
    pages = [
        page
        for section, page in _nav_pages(config["nav"])
        if section != "Development" and page not in GENERATED_BY_THE_CORPUS
    ]
    pages += [f"codes/{p.name}" for p in (DOCS / "codes").glob("*.md")]
    notes = re.compile(
        r"tests/test_|tests/corpus|scripts/test|\.ci/|docs/examples/codes/expected|robospec\.docgen"
    )
    for page in pages:
        found = notes.search((DOCS / page).read_text(encoding="utf-8"))
        assert found is None, f"{page} has a developer note ({found.group()})"


def _mkdocs_config() -> dict[str, object]:
    from ruamel.yaml import YAML

    loaded = YAML(typ="safe", pure=True).load((ROOT / "mkdocs.yml").read_text("utf-8"))
    assert isinstance(loaded, dict)
    return loaded


def test_the_site_uses_material_offline_with_copy_buttons_and_dark_mode() -> None:
    theme = _mkdocs_config()["theme"]
    assert isinstance(theme, dict)
    assert theme["name"] == "material"
    assert theme["font"] is False  # Google's web fonts would be fetched from the network
    assert "content.code.copy" in theme["features"]
    assert {p["scheme"] for p in theme["palette"]} == {"default", "slate"}


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site as `mkdocs build --strict` writes it."""
    folder = tmp_path_factory.mktemp("site") / "site"
    result = _mkdocs(ROOT / "mkdocs.yml", folder)
    assert result.returncode == 0, result.stderr
    return folder


@pytest.mark.slow
def test_the_site_builds_in_strict_mode_and_loads_nothing_from_the_network(site: Path) -> None:
    assert (site / "tutorial" / "index.html").is_file()
    assert (site / "codes" / "RS201" / "index.html").is_file()
    outside = re.compile(r"<(?:script|link|img)\b[^>]*\b(?:src|href)=\"(?:https?:)?//", re.I)
    for page in site.rglob("*.html"):
        found = outside.search(page.read_text(encoding="utf-8"))
        assert found is None, f"{page.relative_to(site)} loads {found.group()}"
    # code is highlighted when the site is built (Pygments), not by a script from a CDN
    assert '<span class="nt">robospec</span>' in (site / "tutorial" / "index.html").read_text()


# Material's default primary colour (indigo): its header bar, painted only when its styles load
MATERIAL_HEADER = (0x40, 0x51, 0xB5)
SCREENSHOTS = ["index.html", "tutorial/index.html", "codes/RS011/index.html"]


def _chromium() -> str:
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    assert found, "Chromium is needed for the docs screenshots: scripts/setup installs it"
    return found


@pytest.mark.slow
@pytest.mark.parametrize("page", SCREENSHOTS)
def test_a_screenshot_of_the_page_shows_materials_theme(
    site: Path, page: str, tmp_path: Path
) -> None:
    """Headless Chromium renders the built page (from files, as offline): Material's header
    colour fills the top of the picture, and the page's text is dark on light, not the
    browser's unstyled default (a missing stylesheet shows black on white with no header)."""
    from PIL import Image

    shot = tmp_path / "page.png"
    subprocess.run(
        [
            _chromium(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            f"--user-data-dir={tmp_path / 'profile'}",
            "--hide-scrollbars",
            "--force-prefers-reduced-motion",
            "--window-size=1280,900",
            f"--screenshot={shot}",
            (site / page).as_uri(),
        ],
        capture_output=True,
        timeout=120,
        check=True,
    )
    image = Image.open(shot).convert("RGB")
    assert image.size == (1280, 900)
    header = [image.getpixel((x, 10)) for x in range(300, 1100, 50)]
    assert all(_near(pixel, MATERIAL_HEADER) for pixel in header), header
    body = image.crop((300, 100, 980, 890)).getcolors(1280 * 900)
    assert body is not None
    colours = sorted(body, reverse=True)
    assert _near(colours[0][1], (255, 255, 255)), colours[:3]  # the page, light
    assert len(colours) > 20  # text, highlighted code: more than a blank page


# what a reader sees of a page at 1280 x 900, measured in the page by Chromium once it has
# loaded: each table's header cells (shown, or past the edge of the table's scroll box or of
# the window), each picture (loaded, with pixels), each code block (its lines whole, or cut at
# its right edge, behind a scroll bar)
READER_SCRIPT = """<script>
window.addEventListener("load", () => {
  const content = document.querySelector(".md-content");
  const tables = [...content.querySelectorAll("table")].map((table) => {
    const box = table.getBoundingClientRect();
    const right = Math.min(box.left + table.clientWidth, window.innerWidth);
    return [...table.querySelectorAll("th")].map((th) => {
      const cell = th.getBoundingClientRect();
      return [th.textContent.trim(), cell.width > 0 && cell.right <= right + 1];
    });
  });
  const images = [...content.querySelectorAll("img")].map(
    (img) => [img.getAttribute("src"), img.complete && img.naturalWidth > 0]);
  const code = [...content.querySelectorAll("pre > code")].map(
    (block) => [block.textContent.split("\\n")[0], block.scrollWidth > block.clientWidth + 1]);
  document.body.setAttribute("data-reader", JSON.stringify({tables, images, code}));
});
</script>"""


def _what_a_reader_sees(site: Path, page: str, tmp_path: Path) -> dict[str, list[list]]:
    """The page, built, opened in headless Chromium at 1280 x 900 with :data:`READER_SCRIPT`
    added: what that script measured, read back from the page's DOM."""
    import html
    import json

    built = site / ("index.html" if page == "index.md" else f"{page[:-3]}/index.html")
    probe = built.with_name("_reader.html")  # beside it: its links and pictures resolve
    probe.write_text(
        built.read_text(encoding="utf-8").replace("</body>", READER_SCRIPT + "</body>"),
        encoding="utf-8",
    )
    try:
        result = subprocess.run(
            [
                _chromium(),
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--hide-scrollbars",
                f"--user-data-dir={tmp_path / 'profile'}",
                "--window-size=1280,900",
                "--virtual-time-budget=10000",
                "--dump-dom",
                probe.as_uri(),
            ],
            capture_output=True,
            text=True,
            timeout=120,
            check=True,
        )
    finally:
        probe.unlink()
    found = re.search(r'data-reader="([^"]*)"', result.stdout)
    assert found, f"the reader script did not run on {page}"
    return json.loads(html.unescape(found.group(1)))


# the pages a newcomer reads first (README's links), every column of whose tables must show
FIRST_PAGES = ("index.md", "tutorial.md", "bring-your-own-robot.md", "cli.md", "robots.md")


@pytest.mark.slow
@pytest.mark.parametrize(
    "page", [page for _, page in _nav_pages(_mkdocs_config()["nav"]) if page.endswith(".md")]
)
def test_a_reader_at_1280_px_sees_every_picture_and_whole_code_lines(
    site: Path, page: str, tmp_path: Path
) -> None:
    """And on the pages a newcomer reads first, every column of every table."""
    seen = _what_a_reader_sees(site, page, tmp_path)
    if page in FIRST_PAGES:
        hidden = [name for table in seen["tables"] for name, shown in table if not shown]
        assert not hidden, f"{page}: columns past the table's edge: {hidden}"
    broken = [src for src, loaded in seen["images"] if not loaded]
    assert not broken, f"{page}: pictures that did not load: {broken}"
    cut = [first for first, clipped in seen["code"] if clipped]
    assert not cut, f"{page}: code blocks cut at the right edge (lines over 80 columns): {cut}"


@pytest.mark.slow
@pytest.mark.parametrize("page", ["index.md", "tutorial.md"])
def test_the_home_page_and_the_tutorial_show_pictures_of_robots(
    site: Path, page: str, tmp_path: Path
) -> None:
    seen = _what_a_reader_sees(site, page, tmp_path)
    pictures = [src for src, loaded in seen["images"] if loaded and src.endswith(".png")]
    assert len(pictures) >= 2, seen["images"]


@pytest.mark.slow
def test_the_robots_table_shows_all_ten_columns_at_1280_px(site: Path, tmp_path: Path) -> None:
    """The journeys' table: register, build and check found were cut off at its right edge."""
    seen = _what_a_reader_sees(site, "robots.md", tmp_path)
    journeys = next(
        t for t in seen["tables"] if [name for name, _ in t][:2] == ["robot", "category"]
    )
    assert [name for name, _ in journeys][-3:] == ["register", "build", "check found"]
    assert all(shown for _, shown in journeys), journeys


def _near(pixel: tuple[int, ...], colour: tuple[int, int, int], within: int = 12) -> bool:
    return all(abs(a - b) <= within for a, b in zip(pixel, colour, strict=False))


def _site_copy(tmp_path: Path) -> Path:
    shutil.copytree(DOCS, tmp_path / "docs")
    shutil.copy(ROOT / "mkdocs.yml", tmp_path / "mkdocs.yml")
    return tmp_path / "mkdocs.yml"


@pytest.mark.slow
@pytest.mark.parametrize("target", ["no-such-page.md", "reference.md#no-such-model"])
def test_strict_mode_fails_on_a_broken_link(target: str, tmp_path: Path) -> None:
    config = _site_copy(tmp_path)
    page = tmp_path / "docs" / "cli.md"
    page.write_text(page.read_text() + f"\n[gone]({target})\n", encoding="utf-8")
    result = _mkdocs(config, tmp_path / "site")
    assert result.returncode != 0 and target.split("#")[-1] in result.stderr


@pytest.mark.slow
def test_strict_mode_fails_on_a_page_missing_from_the_nav(tmp_path: Path) -> None:
    config = _site_copy(tmp_path)
    (tmp_path / "docs" / "orphan.md").write_text("# Orphan\n", encoding="utf-8")
    result = _mkdocs(config, tmp_path / "site")
    assert result.returncode != 0 and "orphan.md" in result.stderr


# -- the user guide shows what robospec really does


def _example_specs() -> list[Path]:
    return sorted(p for p in (EXAMPLES / "tutorial").iterdir() if p.suffix in (".yaml", ".toml"))


@pytest.mark.parametrize("spec", _example_specs(), ids=lambda p: p.name)
def test_every_tutorial_example_validates(spec: Path) -> None:
    result = compile_spec(spec)
    assert not has_errors(result.diagnostics), [d.format_text() for d in result.diagnostics]


@pytest.mark.parametrize("page", GUIDE_PAGES)
def test_every_spec_snippet_of_the_guide_is_part_of_an_example_that_validates(page: str) -> None:
    specs = [
        *_example_specs(),
        *(ROOT / "specs").rglob("*.yaml"),
        *(ROOT / "specs").rglob("*.toml"),
    ]
    sources = {p: p.read_text(encoding="utf-8") for p in specs}
    for language, suffix in (("yaml", ".yaml"), ("toml", ".toml")):
        for body, marker in fenced_blocks(page, language):
            if marker == NOT_A_SPEC:
                continue
            lines = body.splitlines(keepends=True)
            found = [p for p in specs if p.suffix == suffix and _contains_lines(sources[p], lines)]
            assert found, f"{page}: this snippet is in no example spec:\n{body}"
            if "robospec: 1" in body and body.startswith("# yaml-language-server"):
                assert any(sources[p] == body for p in found), f"{page}: a whole spec must be one"
            assert any(not has_errors(compile_spec(p).diagnostics) for p in found), found


def _contains_lines(text: str, lines: list[str]) -> bool:
    """Whether ``lines`` occur in ``text`` as whole, consecutive lines."""
    all_lines = text.splitlines(keepends=True)
    size = len(lines)
    return any(all_lines[i : i + size] == lines for i in range(len(all_lines) - size + 1))


def _console_commands(page: str) -> list[tuple[str, str]]:
    """(command, expected output) for each `$ robospec ...` line of the page's console blocks."""
    found = []
    for body, _ in fenced_blocks(page, "console"):
        for chunk in re.split(r"^\$ ", body, flags=re.M)[1:]:
            command, _, output = chunk.partition("\n")
            found.append((command, output))
    return found


def _run_console(command: str, cwd: Path) -> str:
    args = shlex.split(command)
    assert args[0] == "robospec", command
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "100"}
    env["MS_ASSET_DIR"] = str(cwd / "no-maniskill-downloads")  # the same on every machine
    env.pop("FORCE_COLOR", None)
    result = subprocess.run(
        [sys.executable, "-m", "robospec.cli", *args[1:]],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=300,
        env=env,
    )
    return "\n".join(line for line in result.stdout.splitlines() if not _is_sapien_noise(line))


def _is_sapien_noise(line: str) -> bool:
    """SAPIEN's import-time complaints about Vulkan on a machine without a GPU."""
    return "vulkan" in line.lower() or line.strip().startswith("warn(")


TUTORIAL_FOLDER = "tutorial folder"


def _workdir(tmp_path: Path) -> Path:
    """The folder the tutorial has its reader make (its `<!-- tutorial folder -->` block, run
    from the clone, with ``tmp_path`` as the home folder): the commands run there."""
    (setup,) = [
        body for body, marker in fenced_blocks("tutorial.md", "sh") if marker == TUTORIAL_FOLDER
    ]
    home = tmp_path / "home"
    home.mkdir()
    subprocess.run(
        ["bash", "-euc", setup], cwd=ROOT, env={**os.environ, "HOME": str(home)}, check=True
    )
    (folder,) = home.iterdir()
    return folder


@pytest.mark.slow
def test_the_tutorial_runs_in_a_folder_of_its_own_and_leaves_the_clone_as_it_was(
    tmp_path: Path,
) -> None:
    before = _untracked(ROOT)
    cwd = _workdir(tmp_path)
    assert (cwd / "docs" / "examples" / "tutorial" / "my_panda.yaml").is_file()
    assert (cwd / "schemas" / "robospec.schema.json").is_file()
    # the tutorial's commands that write: build, schema, doc
    for command, _ in _console_commands("tutorial.md"):
        if " -o " in command and not command.startswith(SIMULATES):
            _run_console(command, cwd)
    assert (cwd / "my_robots" / "__init__.py").is_file()
    assert _untracked(ROOT) == before


def _untracked(root: Path) -> str:
    result = subprocess.run(
        ["git", "status", "--porcelain", "--untracked-files=all"],
        cwd=root,
        capture_output=True,
        text=True,
    )
    return result.stdout if result.returncode == 0 else ""


SIMULATES = "robospec check"  # runs SAPIEN: seconds, and the maniskill extra


def _searches_rest_pose(command: str) -> bool:
    """``robospec new`` searches the rest pose in ManiSkill where it is installed (unless
    ``--no-sim``): its output depends on the ManiSkill it runs on."""
    return command.startswith("robospec new ") and "--no-sim" not in command.split()


# a page whose commands run ManiSkill (in robospec's own process) is marked maniskill, so that
# CI's run on ManiSkill's nightly (-m maniskill, .ci/run) runs it too
GUIDE_PAGE_PARAMS = [
    pytest.param(
        page,
        id=page,
        marks=[pytest.mark.maniskill]
        if any(_searches_rest_pose(command) for command, _ in _console_commands(page))
        else [],
    )
    for page in GUIDE_PAGES
]


@pytest.mark.slow
@pytest.mark.parametrize("page", GUIDE_PAGE_PARAMS)
def test_every_command_of_the_guide_prints_what_the_guide_shows(page: str, tmp_path: Path) -> None:
    cwd = _workdir(tmp_path)
    for command, expected in _console_commands(page):
        if not command.startswith(SIMULATES):  # the test below runs those
            assert _run_console(command, cwd) == expected.rstrip("\n"), command


@pytest.mark.usefixtures("maniskill")
def test_every_check_command_of_the_guide_prints_what_the_guide_shows(tmp_path: Path) -> None:
    cwd = _workdir(tmp_path)
    commands = [
        (command, expected)
        for page in GUIDE_PAGES
        for command, expected in _console_commands(page)
        if command.startswith(SIMULATES)
    ]
    assert commands
    for command, expected in commands:
        assert _run_console(command, cwd) == expected.rstrip("\n"), command


def test_generated_code_shown_in_the_tutorial_is_what_build_writes(tmp_path: Path) -> None:
    cwd = _workdir(tmp_path)
    blocks = [
        (body, marker.removeprefix("generated: "))
        for body, marker in fenced_blocks("tutorial.md", "python")
        if marker and marker.startswith("generated: ")
    ]
    assert blocks
    _run_console("robospec build docs/examples/tutorial/my_panda.yaml -o my_robots", cwd)
    for body, file in blocks:
        assert body in (cwd / file).read_text(encoding="utf-8"), textwrap.shorten(body, 80)


def test_every_tutorial_example_carries_the_schema_modeline() -> None:
    for spec in _example_specs():
        if spec.suffix in (".yaml", ".yml"):
            assert spec.read_text().startswith("# yaml-language-server: $schema="), spec
        elif spec.suffix == ".toml":
            assert spec.read_text().startswith("#:schema "), spec


def test_reference_values_read_back_as_the_schema_holds_them() -> None:
    """Defaults and examples are shown as YAML flow text; reading that text back as YAML must
    give the schema's value, or the reference would show a spec something else."""
    from ruamel.yaml import YAML

    from robospec.docgen.reference_page import yaml_flow
    from robospec.schema import spec_schema

    values: list[object] = []

    def collect(node: object) -> None:
        if isinstance(node, dict):
            values.extend(node.get("examples", []))
            if "default" in node:
                values.append(node["default"])
            for child in node.values():
                collect(child)
        elif isinstance(node, list):
            for child in node:
                collect(child)

    collect(spec_schema())
    assert len(values) > 50
    reader = YAML(typ="safe", pure=True)
    for value in values:
        assert reader.load(yaml_flow(value)) == value, yaml_flow(value)
