"""The zoo's pictures in docs/zoo.md are current: each is drawn from exactly what the spec and
ManiSkill's assets say now. Current means the hash of the picture's inputs (the description,
its visual meshes, the first keyframe, the view, robospec's drawing version) is the one recorded
beside the pictures when they were drawn — robust across machines, whose OpenGL draws slightly
different pixels. And each shows the robot where the simulation puts it: a slow test loads the
robot in ManiSkill and finds, in the checked-in picture, the robot's pixels where each of
SAPIEN's link origins lands (tests/picture_truth.py)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import DOCS, MANISKILL_VERSION, ROOT
from picture_truth import picture_faults, placement_errors, sapien_truth

from robospec.docgen.gallery import (
    PAGE_FOLDER,
    PAGE_PICTURES,
    WRITE_COMMAND,
    ZOO_FOLDER,
    ZOO_PAGE,
    gallery_markdown,
    page_inputs,
    recorded_inputs,
    recorded_page_inputs,
    render_inputs,
    with_gallery,
    zoo_gallery,
    zoo_specs,
)
from robospec.pipeline import compile_spec

SPECS = zoo_specs(ROOT)
# the pictures are drawn from ManiSkill 3.0.1's assets, which the nightly may change
ASSETS_PINNED = MANISKILL_VERSION != "nightly"


def test_every_zoo_spec_has_a_picture_and_the_page_shows_them_all() -> None:
    recorded = recorded_inputs(DOCS)
    assert sorted(recorded) == sorted(spec.stem for spec in SPECS)
    for name in recorded:
        assert (DOCS / ZOO_FOLDER / f"{name}.png").is_file(), name
    page = (DOCS / ZOO_PAGE).read_text(encoding="utf-8")
    assert with_gallery(page, zoo_gallery(DOCS, sorted(recorded))) == page
    for name in recorded:
        assert f"(<images/zoo/{name}.png>)" in page


@pytest.mark.skipif(not ASSETS_PINNED, reason="drawn from ManiSkill 3.0.1's assets")
@pytest.mark.parametrize("spec", SPECS, ids=[spec.stem for spec in SPECS])
def test_a_zoo_picture_is_drawn_from_what_the_spec_and_its_assets_say_now(spec: Path) -> None:
    recorded = recorded_inputs(DOCS)
    assert render_inputs(compile_spec(spec)) == recorded.get(spec.stem), (
        f"docs/images/zoo/{spec.stem}.png is stale: run {WRITE_COMMAND}"
    )


@pytest.mark.skipif(not ASSETS_PINNED, reason="drawn from ManiSkill 3.0.1's assets")
def test_the_pages_own_pictures_are_drawn_from_what_their_specs_say_now_and_shown() -> None:
    """The home page and the tutorial show robots drawn by doc --images: the tutorial's own
    robot, and what its hand camera sees, current as the zoo's pictures are."""
    assert page_inputs(ROOT) == recorded_page_inputs(DOCS), f"stale: run {WRITE_COMMAND}"
    tutorial = (DOCS / "tutorial.md").read_text(encoding="utf-8")
    for name in PAGE_PICTURES:
        assert (DOCS / PAGE_FOLDER / f"{name}.png").is_file(), name
        assert f"(images/pages/{name}.png)" in tutorial, name
    home = (DOCS / "index.md").read_text(encoding="utf-8")
    shown = re.findall(r"!\[[^\]]*\]\((images/[^)]+\.png)\)", home)
    assert len(shown) >= 4 and all((DOCS / picture).is_file() for picture in shown), shown


def test_a_camera_view_hashes_the_camera_and_a_gallery_view_as_it_always_did() -> None:
    spec = compile_spec(ROOT / "docs" / "examples" / "tutorial" / "my_panda.yaml")
    assert render_inputs(spec) == render_inputs(spec, "three_quarter")
    assert render_inputs(spec, "table:hand_camera") != render_inputs(spec)


def test_the_inputs_hash_changes_with_the_keyframe_and_not_with_the_gains(tmp_path: Path) -> None:
    spec = ROOT / "specs" / "maniskill" / "panda.yaml"
    text = spec.read_text().replace("../../schemas", str(ROOT / "schemas"))
    base = render_inputs(compile_spec(spec))
    stiffer = tmp_path / "stiffer.yaml"
    stiffer.write_text(text.replace("stiffness: 1e3", "stiffness: 2e3"))
    assert render_inputs(compile_spec(stiffer)) == base
    moved = tmp_path / "moved.yaml"
    moved.write_text(text.replace("qpos: {arm: [0, pi/8,", "qpos: {arm: [0.5, pi/8,"))
    assert render_inputs(compile_spec(moved)) != base


def test_a_gallery_is_a_table_of_pictures_with_their_captions() -> None:
    text = gallery_markdown([("a", "a.png"), ("b", "b.png")], columns=3)
    assert text.splitlines()[2] == "| ![a](<a.png>)<br>`a` | ![b](<b.png>)<br>`b` |   |"


@pytest.mark.slow
@pytest.mark.skipif(not ASSETS_PINNED, reason="drawn from ManiSkill 3.0.1's assets")
@pytest.mark.parametrize("spec", SPECS, ids=[spec.stem for spec in SPECS])
def test_a_zoo_picture_shows_each_link_where_sapien_puts_it(maniskill: object, spec: Path) -> None:
    truth = sapien_truth(spec)
    assert placement_errors(truth) == {}
    assert picture_faults(truth, DOCS / ZOO_FOLDER / f"{spec.stem}.png") == []
