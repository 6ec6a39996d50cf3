"""Robots nobody here wrote (issue 13): the corpus of tests/corpus.py, each robot taken through
the journey a user takes — inspect, new, validate, check, register + gym.make + random steps,
build + import — with the spec exactly as ``robospec new`` writes it (tests/corpus_journey.py).

Every robot passes, or ``validate``/``check`` stops it with a located reason; nothing crashes;
each robot ends its journey as the reviewed table of tests/corpus.py (``EXPECTED_STOPS``) says;
and docs/robots.md is what the journeys did. The journeys run once per session, several robots
at a time (``ROBOSPEC_CORPUS_WORKERS``, default: the CPUs), each step in a child process.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import tomllib
from conftest import ROOT
from corpus import (
    BY_KEY,
    CATEGORIES,
    CORPUS,
    EXPECTED_STOPS,
    FORMATS,
    ROBOTS_PAGE,
    WRITE_COMMAND,
    CorpusMissing,
    distribution_version,
    locate,
    picture_path,
)
from corpus_journey import FAILED, PASSED, STEPS, Journey, Step, run_corpus
from corpus_page import render_page
from picture_truth import picture_faults, placement_errors, sapien_truth

pytestmark = pytest.mark.minutes  # the journeys: a quarter of an hour of CI

ROBOT_KEYS = [robot.key for robot in CORPUS]
# the steps ManiSkill runs a robot in, where a description it cannot load fails
LOADING_STEPS = ("register", "build")
# the steps that must stop a robot ManiSkill cannot load, with located diagnostics
STOPPING_STEPS = ("inspect", "new", "validate", "check")


# -- the corpus itself (no ManiSkill: the fast loop runs these)


def test_the_corpus_has_25_robots_from_3_packages_in_every_category_and_format() -> None:
    assert len(CORPUS) >= 25
    assert len(BY_KEY) == len(CORPUS), "two robots share a key"
    assert len({robot.distribution for robot in CORPUS}) >= 3
    assert {robot.category for robot in CORPUS} == set(CATEGORIES)
    assert {robot.format for robot in CORPUS} == set(FORMATS)


def test_the_corpus_extra_pins_the_packages_the_corpus_names() -> None:
    """The corpus extra of pyproject.toml (installed with dependencies) and
    scripts/corpus-files.txt (description-only, installed without) pin them all."""
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    extra = pyproject["project"]["optional-dependencies"]["corpus"]
    files = (ROOT / "scripts" / "corpus-files.txt").read_text(encoding="utf-8").splitlines()
    extra += [line.split("#")[0].strip() for line in files if line.split("#")[0].strip()]
    pins = dict(requirement.split("==") for requirement in extra)
    assert set(pins) == {robot.distribution for robot in CORPUS}
    for name, version in pins.items():
        assert distribution_version(name) == version, f"{name}: run scripts/setup"


@pytest.mark.parametrize("key", ROBOT_KEYS)
def test_each_robot_is_found_where_its_package_installs_it(key: str) -> None:
    try:
        path = locate(BY_KEY[key])
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    assert path.is_file() and path.as_posix().endswith(BY_KEY[key].path)


def test_the_expected_stops_name_corpus_robots_steps_that_stop_and_codes() -> None:
    assert set(EXPECTED_STOPS) <= set(BY_KEY)
    for key, stop in EXPECTED_STOPS.items():
        assert stop.step in STOPPING_STEPS, key
        assert stop.codes and all(code.startswith("RS") for code in stop.codes), key
        assert stop.reason, key


def test_the_solving_section_says_each_tasks_successes_failed_seeds_and_refusals() -> None:
    """docs/robots.md's section on ManiSkill's solutions, from the journeys' records of each
    task (no ManiSkill: the page is written from data)."""
    from corpus_journey import Found, Pick
    from corpus_page import render_rows

    def journey(key: str, picks: dict[str, Pick]) -> Journey:
        steps = {name: Step(name, PASSED) for name in STEPS}
        return Journey(BY_KEY[key], steps, picks=picks)

    refusal = Found("x.yaml", 3, 1, "RS526", "error", "PickCube-v1: 'cube' lies 0.62 m", "far")
    rows = render_rows(
        [
            journey(
                "pb_panda",
                {
                    "PickCube-v1": Pick(20, 19, [(1, "a motion had no plan")]),
                    "PushCube-v1": Pick(20, 20),
                },
            ),
            journey("rtb_px100", {"PickCube-v1": Pick(refused=[refusal])}),
            journey("pb_kuka_iiwa", {}),
        ]
    )
    # its own section, not columns: the journeys' table stays within a 1280-pixel page
    assert "| check found |\n" in rows
    section = rows.split("## Solving the tasks")[1]
    assert "| robot | PickCube-v1 | PushCube-v1 | StackCube-v1 |" in section
    assert "| Franka Panda | 19 of 20 | 20 of 20 | — |" in section
    assert "| Interbotix PincherX 100 | refused: [RS526](codes/RS526.md) | — | — |" in section
    assert "KUKA" not in section
    assert "- **Franka Panda**, PickCube-v1: seed 1: a motion had no plan" in section
    assert "PushCube-v1: seed" not in section  # nothing failed there
    assert "- **Interbotix PincherX 100**, PickCube-v1: refused" in section
    assert "`x.yaml:3:1: error[RS526] PickCube-v1: 'cube' lies 0.62 m`" in section


# -- the journeys


@pytest.fixture(scope="module")
def corpus_work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where the journeys run: ``<key>/<key>.yaml`` is the spec ``robospec new`` wrote."""
    return tmp_path_factory.mktemp("corpus")


def _selected_robots(session: pytest.Session) -> list[str]:
    """The robots the session's tests of this module judge: every one where a test judges
    the whole corpus (the page), else those of the tests ``-k`` left (one robot's journey
    takes minutes; the corpus's, a quarter of an hour of both cores)."""
    keys: set[str] = set()
    for item in session.items:
        module = getattr(item, "module", None)
        if module is None or module.__name__ != __name__:
            continue
        if "journeys" not in getattr(item, "fixturenames", ()):
            continue
        callspec = getattr(item, "callspec", None)
        if callspec is None or "key" not in callspec.params:
            return ROBOT_KEYS
        keys.add(callspec.params["key"])
    return [key for key in ROBOT_KEYS if key in keys]


@pytest.fixture(scope="module")
def journeys(
    maniskill: object, corpus_work: Path, request: pytest.FixtureRequest
) -> dict[str, Journey]:
    """The journeys of the robots the session's tests judge, run once for the module."""
    robots = [BY_KEY[key] for key in _selected_robots(request.session)]
    try:
        done = run_corpus(robots, corpus_work)
    except CorpusMissing as missing:
        pytest.fail(str(missing), pytrace=False)
    return {journey.robot.key: journey for journey in done}


def _says(step: Step) -> str:
    """A step's outcome and its reasons, for an assertion's message."""
    reasons = [step.crash or step.problem or ""] + [f.text() for f in step.errors]
    return f"{step.name} {step.outcome}: " + "; ".join(r for r in reasons if r)


@pytest.mark.parametrize("key", ROBOT_KEYS)
def test_each_robot_ends_its_journey_as_the_reviewed_table_says(
    journeys: dict[str, Journey], key: str
) -> None:
    """A robot the table does not list passes every step; one it lists passes every step
    before its stop and fails there with exactly the listed error codes."""
    journey = journeys[key]
    stop = EXPECTED_STOPS.get(key)
    if stop is None:
        stopped = [step for step in journey.steps.values() if step.outcome != PASSED]
        assert not stopped, [_says(step) for step in stopped]
        return
    for name in STEPS[: STEPS.index(stop.step)]:
        assert journey.step(name).outcome == PASSED, _says(journey.step(name))
    step = journey.step(stop.step)
    assert step.outcome == FAILED, _says(step)
    assert {found.code for found in step.errors} == stop.codes, _says(step)


@pytest.mark.parametrize("key", ROBOT_KEYS)
def test_no_step_of_the_journey_crashes(journeys: dict[str, Journey], key: str) -> None:
    """No traceback, no signal, no hang, in any step: a description robospec or ManiSkill
    cannot take is a diagnostic."""
    crashes = journeys[key].crashes
    assert not crashes, [_says(step) for step in crashes]


@pytest.mark.parametrize("key", ROBOT_KEYS)
def test_the_scaffold_validates_or_the_description_is_refused_at_its_element(
    journeys: dict[str, Journey], key: str
) -> None:
    journey = journeys[key]
    new = journey.step("new")
    if new.outcome == FAILED:
        assert new.errors, _says(new)
        for found in new.errors:
            assert found.located and found.file == journey.robot.path, found.text()
    else:
        assert journey.step("validate").outcome == PASSED, _says(journey.step("validate"))


@pytest.mark.parametrize("key", ROBOT_KEYS)
def test_every_step_that_stops_a_robot_says_where(journeys: dict[str, Journey], key: str) -> None:
    for name in STOPPING_STEPS:
        step = journeys[key].step(name)
        if step.outcome == FAILED:
            assert step.errors, _says(step)
            assert all(found.located for found in step.errors), _says(step)


@pytest.mark.parametrize("key", ROBOT_KEYS)
def test_a_robot_that_passes_check_registers_runs_and_builds(
    journeys: dict[str, Journey], key: str
) -> None:
    """What ManiSkill cannot load or step, validate or check must have stopped: a robot they
    let through registers, makes a headless CPU environment with no other call, takes 50 random
    steps with a finite state, and builds into a package whose import registers it."""
    journey = journeys[key]
    if journey.step("check").outcome != PASSED:
        return  # stopped: the tests above judge how
    for name in LOADING_STEPS:
        assert journey.step(name).outcome == PASSED, _says(journey.step(name))


# robots whose picture — the description as MuJoCo reads it — shows them otherwise than
# ManiSkill loads them, each with why: their picture test must fail (strict) until robospec
# mends or reports the difference, and then says to take the robot off this list
PICTURED_OTHERWISE = {
    # links placed alike (placement_errors is empty) yet the drawing covers less of SAPIEN's
    # robot than the bound asks: found on CI on 2026-12-02, the cause not yet found
    "pb_panda": "94% of the robot drawn where SAPIEN puts it, its links placed alike: unexplained",
    "erd_go2": "91% of the robot drawn where SAPIEN puts it, its links placed alike: unexplained",
}


@pytest.mark.parametrize(
    "key",
    [
        pytest.param(key, marks=pytest.mark.xfail(strict=True, reason=PICTURED_OTHERWISE[key]))
        if key in PICTURED_OTHERWISE
        else key
        for key in ROBOT_KEYS
    ],
)
def test_each_robots_picture_shows_it_where_sapien_puts_it(
    journeys: dict[str, Journey], corpus_work: Path, key: str
) -> None:
    """docs/images/robots/<key>.png, drawn from the scaffold at its rest keyframe (tests/corpus.py
    --write), shows every link where SAPIEN puts it: the robot's pixels lie where each of its
    links' origins lands (tests/picture_truth.py). A robot ManiSkill cannot load has no truth
    to hold its picture to; one whose scaffold does not validate has no picture."""
    journey = journeys[key]
    picture = picture_path(key)
    if journey.step("validate").outcome != PASSED:
        assert not picture.is_file(), f"{picture.name}: drawn from a spec that does not validate"
        return
    assert picture.is_file(), f"no {picture.name}: run {WRITE_COMMAND}"
    if journey.step("register").outcome != PASSED:
        return
    truth = sapien_truth(corpus_work / key / f"{key}.yaml")
    assert placement_errors(truth) == {}
    assert picture_faults(truth, picture) == []


def test_the_robots_page_shows_what_the_journeys_did(journeys: dict[str, Journey]) -> None:
    page = render_page([journeys[key] for key in ROBOT_KEYS])
    written = ROBOTS_PAGE.read_text(encoding="utf-8") if ROBOTS_PAGE.is_file() else ""
    assert written == page, f"docs/robots.md is out of step with the journeys: run {WRITE_COMMAND}"
    assert str(ROOT) not in page and str(Path.home()) not in page
