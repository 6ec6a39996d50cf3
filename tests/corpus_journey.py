"""The journey a user takes with a robot description robospec has never seen, step by step:

``inspect`` → ``new`` → ``validate`` → ``check`` → ``robospec.register`` + ``gym.make`` + 50
random steps → ``build`` + import, each in a child process (a crash or a segfault in one step
is a result, not the end of the run), with the spec exactly as ``new`` wrote it. An arm whose
scaffold declares a two-finger grasp check then runs ManiSkill's solutions of
:data:`SOLVED_TASKS` (``robospec solve``, :data:`SOLVE_EPISODES` seeds each): a measurement,
not a step that passes or fails (:class:`Pick`).

What each step printed is kept as data (outcome, diagnostics with their files named relative
to the package or the spec, what crashed), so that tests/test_corpus.py can judge it and
tests/corpus_page.py can write it down; nothing here names a path of this machine.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from corpus import ARM, Robot, install_folder, locate

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
GYM_CHILD = HERE / "corpus_maniskill.py"

# the steps, in the order a user takes them; "register" and "build" run in one child process
STEPS = ("inspect", "new", "validate", "check", "register", "build")
PASSED, FAILED, CRASHED, NOT_RUN = "passed", "failed", "crashed", "not run"
# random control steps, in check (its --steps) and after gym.make
RANDOM_STEPS = 50
BUILD_PACKAGE = "corpus_agents"

# what an arm with a gripper does with ManiSkill's solutions of these tasks, over this many seeds
# (0, 1, ...) each: issue 37's measure (at least 90% of 20 seeds); about half a second an
# episode for the Panda here, after seconds of start
SOLVED_TASKS = ("PickCube-v1", "PushCube-v1", "StackCube-v1")
SOLVE_EPISODES = 20

# seconds a step may take before it counts as hung: expanding xacro, loading a humanoid and
# stepping it on a busy CPU take a while
TIMEOUTS = {
    "inspect": 120,
    "new": 300,
    "validate": 120,
    "check": 600,
    "build": 120,
    "child": 600,
    "solve": 300,
}

TRACEBACK = "Traceback (most recent call last):"


@dataclass(frozen=True)
class Found:
    """A diagnostic as a step reported it, its file named without this machine's folders."""

    file: str
    line: int
    column: int
    code: str
    severity: str
    message: str
    hint: str | None

    @property
    def located(self) -> bool:
        return bool(self.file) and self.line >= 1 and self.column >= 1

    @property
    def is_error(self) -> bool:
        return self.severity == "error"

    def text(self) -> str:
        return f"{self.file}:{self.line}:{self.column}: {self.severity}[{self.code}] {self.message}"


@dataclass
class Step:
    name: str
    outcome: str = NOT_RUN
    found: list[Found] = field(default_factory=list)
    crash: str | None = None  # what a crashed step died of: the exception, the signal, a hang
    problem: str | None = None  # why a failed step failed, where no diagnostic says it
    seconds: float = 0.0

    @property
    def errors(self) -> list[Found]:
        return [f for f in self.found if f.is_error]


@dataclass
class Pick:
    """What ``robospec solve --task TASK`` made of the scaffold: episodes and successes, or the
    refusal's codes (no episode), or what crashed."""

    episodes: int = 0
    successes: int = 0
    # each episode the task did not judge a success: (seed, why: the solver's note, or "" when
    # the solution ran to its end)
    failures: list[tuple[int, str]] = field(default_factory=list)
    refused: list[Found] = field(default_factory=list)
    crash: str | None = None
    seconds: float = 0.0


@dataclass(frozen=True)
class Hold:
    """An MJCF robot's keyframe hold in ``check`` (robospec.physics.mujoco_hold): the largest
    joint drift in ManiSkill and in MuJoCo under the file's own servos (None: MuJoCo did not
    hold it, ``why``), of the keyframe ManiSkill let drift most."""

    keyframe: str
    maniskill: float
    maniskill_joint: str
    mujoco: float | None
    mujoco_joint: str | None
    why: str


@dataclass
class Journey:
    robot: Robot
    steps: dict[str, Step]
    uid: str | None = None
    # each of SOLVED_TASKS' results; empty: no arm with a grasp check, or its journey stopped
    picks: dict[str, Pick] = field(default_factory=dict)
    hold: Hold | None = None  # None: not an MJCF robot, or check did not hold a keyframe

    def step(self, name: str) -> Step:
        return self.steps[name]

    @property
    def passed(self) -> bool:
        return all(step.outcome == PASSED for step in self.steps.values())

    @property
    def crashes(self) -> list[Step]:
        return [step for step in self.steps.values() if step.outcome == CRASHED]


# -- running one command


@dataclass(frozen=True)
class Ran:
    returncode: int | None  # None: killed after its timeout
    stdout: str
    stderr: str
    seconds: float


def _run(args: list[str], cwd: Path, timeout: float) -> Ran:
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": "120", "PYTHONFAULTHANDLER": "1"}
    env.pop("FORCE_COLOR", None)
    start = time.monotonic()
    try:
        done = subprocess.run(
            args, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env, check=False
        )
    except subprocess.TimeoutExpired as hung:
        out = hung.stdout.decode(errors="replace") if isinstance(hung.stdout, bytes) else ""
        err = hung.stderr.decode(errors="replace") if isinstance(hung.stderr, bytes) else ""
        return Ran(None, out, err, time.monotonic() - start)
    return Ran(done.returncode, done.stdout, done.stderr, time.monotonic() - start)


def _robospec(cwd: Path, step: str, *args: str) -> Ran:
    return _run([sys.executable, "-m", "robospec.cli", *args], cwd, TIMEOUTS[step])


def crash_of(ran: Ran, timeout: float) -> str | None:
    """What a command died of, or None when it ended as a command should (exit 0 or 1, and no
    traceback on either stream)."""
    if ran.returncode is None:
        return f"hung: killed after {timeout:.0f} s"
    if ran.returncode < 0:
        return f"killed by {signal.Signals(-ran.returncode).name}"
    for text in (ran.stderr, ran.stdout):
        if TRACEBACK in text or "Fatal Python error" in text:
            return f"traceback: {exception_line(text)}"
    if ran.returncode not in (0, 1):
        return f"exit status {ran.returncode}"
    return None


def exception_line(text: str) -> str:
    """The ``Type: message`` line that ends the last traceback in ``text``."""
    if "Fatal Python error" in text:
        return text[text.index("Fatal Python error") :].splitlines()[0]
    tail = text.rsplit(TRACEBACK, 1)[-1].splitlines()
    ends = [line for line in tail if line and not line[0].isspace()]
    return ends[0][:300] if ends else "(no exception line)"


def _json_documents(*texts: str) -> list[dict[str, Any]]:
    """The JSON objects a command printed (--format json) on stdout and stderr, skipping
    whatever SAPIEN or ManiSkill printed around them: ``inspect`` prints its facts on stdout
    and its diagnostics on stderr."""
    decoder = json.JSONDecoder()
    documents = []
    for text in texts:
        end = 0
        for match in re.finditer(r"^\{", text, re.M):
            if match.start() < end:
                continue  # inside the document just read
            try:
                document, end = decoder.raw_decode(text, match.start())
            except ValueError:
                continue
            if isinstance(document, dict):
                documents.append(document)
    return documents


# -- naming files without this machine's folders


def display_path(file: str, cwd: Path, folders: list[Path]) -> str:
    """``file`` relative to the first of ``folders`` that holds it (the journey's folder, then
    the folder packages install into), else its name alone."""
    path = Path(file) if os.path.isabs(file) else cwd / file
    path = Path(os.path.normpath(path))
    for folder in folders:
        if path.is_relative_to(folder):
            return path.relative_to(folder).as_posix()
    return path.name


def scrub(text: str, folders: list[Path]) -> str:
    """``text`` with the folders of this machine it names left out (a message that quotes a
    file names it from the package on), and any other temporary file by its name."""
    for folder in folders:
        text = text.replace(f"{folder}{os.sep}", "")
    temporary = re.escape(tempfile.gettempdir().rstrip(os.sep))
    return re.sub(rf"{temporary}/(?:[^\s'\"/]+/)*", "", text)


def _found(items: Any, cwd: Path, folders: list[Path], quoted: list[Path]) -> list[Found]:
    """Diagnostics from a report: files named from ``folders``, and the folders of
    ``quoted`` left out of messages and hints."""
    found = []
    for item in items or []:
        hint = item.get("hint")
        found.append(
            Found(
                file=display_path(str(item.get("file") or ""), cwd, folders),
                line=int(item.get("line") or 0),
                column=int(item.get("column") or 0),
                code=str(item.get("code")),
                severity=str(item.get("severity")),
                message=scrub(str(item.get("message")), quoted),
                hint=None if hint is None else scrub(str(hint), quoted),
            )
        )
    return found


# -- the journey


def run_journey(robot: Robot, workdir: Path) -> Journey:
    """Take ``robot`` through every step in ``workdir`` (a folder of its own)."""
    workdir.mkdir(parents=True, exist_ok=True)
    description = locate(robot)
    # where files are named from: the journey's folder, then the packages' folder; messages
    # may also quote the interpreter (sys.prefix) or robospec's checkout
    folders = [workdir.resolve(), install_folder(robot.distribution)]
    quoted = [*folders, Path(sys.prefix).resolve(), ROOT]
    journey = Journey(robot, {name: Step(name) for name in STEPS})
    spec_name = f"{robot.key}.yaml"

    def cli(name: str, *args: str) -> tuple[Step, list[dict[str, Any]]]:
        step = journey.steps[name]
        ran = _robospec(workdir, name, *args)
        step.seconds = ran.seconds
        documents = _json_documents(ran.stdout, ran.stderr)
        for document in documents:
            step.found += _found(_all_diagnostics(document), workdir, folders, quoted)
        crash = crash_of(ran, TIMEOUTS[name])
        step.crash = None if crash is None else scrub(crash, quoted)
        if step.crash:
            step.outcome = CRASHED
        elif ran.returncode == 0:
            step.outcome = PASSED
        else:
            step.outcome = FAILED
        return step, documents

    cli("inspect", "inspect", str(description), "--format", "json")
    cli("new", "new", str(description), "-o", spec_name, "--format", "json")
    if not (workdir / spec_name).is_file():
        return journey
    validate, _ = cli("validate", "validate", spec_name, "--format", "json")
    if validate.outcome != PASSED:
        return journey
    _, reports = cli("check", "check", spec_name, "--steps", str(RANDOM_STEPS), "--format", "json")
    _read_uid(journey, reports)
    journey.hold = _read_hold(reports)
    build, _ = cli("build", "build", spec_name, "-o", BUILD_PACKAGE, "--format", "json")
    _run_in_maniskill(journey, workdir, spec_name, folders, quoted, built=build.outcome == PASSED)
    if robot.category == ARM and journey.step("register").outcome == PASSED:
        if "grasping" in _spec_sections(workdir / spec_name):
            for task in SOLVED_TASKS:
                solved = _solve(workdir, spec_name, task, folders, quoted)
                journey.picks[task] = solved
                if not solved.episodes:
                    break  # refused (or crashed) at the first task: the others would be too
    return journey


def _spec_sections(spec: Path) -> set[str]:
    from ruamel.yaml import YAML

    data = YAML(typ="safe").load(spec.read_text(encoding="utf-8"))
    return set(data) if isinstance(data, dict) else set()


def _solve(
    workdir: Path, spec_name: str, task: str, folders: list[Path], quoted: list[Path]
) -> Pick:
    """``robospec solve`` of ``task`` with the scaffold, as a user runs it."""
    ran = _robospec(
        workdir,
        "solve",
        "solve",
        spec_name,
        "--task",
        task,
        "-n",
        str(SOLVE_EPISODES),
        "--format",
        "json",
    )
    pick = Pick(seconds=ran.seconds)
    crash = crash_of(ran, TIMEOUTS["solve"])
    if crash is not None:
        pick.crash = scrub(crash, quoted)
        return pick
    for document in _json_documents(ran.stdout):
        if "episodes" in document:
            episodes = document.get("episodes") or []
            pick.episodes = len(episodes)
            pick.successes = sum(bool(e.get("success")) for e in episodes)
            pick.failures = [
                (int(e.get("seed", 0)), _episode_note(e)) for e in episodes if not e.get("success")
            ]
            found = _found(document.get("diagnostics"), workdir, folders, quoted)
            pick.refused = [f for f in found if f.is_error]
    return pick


def _all_diagnostics(document: dict[str, Any]) -> list[dict[str, Any]]:
    """A report's diagnostics: the top level's and (for check) each robot's."""
    items = list(document.get("diagnostics") or [])
    for robot in document.get("robots") or []:
        items.extend(robot.get("diagnostics") or [])
    return items


def _read_uid(journey: Journey, reports: list[dict[str, Any]]) -> None:
    for report in reports:
        for robot in report.get("robots") or []:
            journey.uid = robot.get("uid") or journey.uid


def _read_hold(reports: list[dict[str, Any]]) -> Hold | None:
    """The keyframe hold MuJoCo judged whose ManiSkill drift is largest (check's JSON)."""
    holds = []
    for report in reports:
        for robot in report.get("robots") or []:
            for finding in robot.get("findings") or []:
                values = finding.get("metrics") or {}
                if finding.get("check") != "keyframe_hold" or "mujoco" not in values:
                    continue
                mujoco = values.get("mujoco_max_joint_drift")
                holds.append(
                    Hold(
                        str(finding.get("subject")),
                        _number(values.get("max_joint_drift")),
                        str(values.get("joint")),
                        None if mujoco is None else _number(mujoco),
                        values.get("mujoco_joint"),
                        str(values.get("mujoco")),
                    )
                )
    return max(holds, key=lambda hold: hold.maniskill, default=None)


def _number(value: Any) -> float:
    return float(value)  # check's JSON writes an infinite drift as "inf", which float reads


def _run_in_maniskill(
    journey: Journey,
    workdir: Path,
    spec_name: str,
    folders: list[Path],
    quoted: list[Path],
    *,
    built: bool,
) -> None:
    """register + gym.make + random steps, then the built package's import, in one child: one
    import of ManiSkill (seconds) serves both."""
    result_file = workdir / "maniskill.json"
    args = [sys.executable, str(GYM_CHILD), spec_name, str(RANDOM_STEPS), result_file.name]
    if built:
        args.append(BUILD_PACKAGE)
    ran = _run(args, workdir, TIMEOUTS["child"])
    crash = crash_of(ran, TIMEOUTS["child"])
    try:
        result = json.loads(result_file.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        result = {}
    journey.uid = result.get("uid") or journey.uid
    for name, key in (("register", "register"), ("build", "built")):
        step = journey.steps[name]
        if name == "build" and not built:
            continue  # robospec build failed or crashed: its step says so already
        part = result.get(key)
        if not isinstance(part, dict):
            # the child died before it could write this part down
            step.outcome = CRASHED
            step.crash = scrub(crash or "ended without a result", quoted)
            continue
        step.seconds += float(part.get("seconds") or 0.0)
        step.found += _found(part.get("diagnostics"), workdir, folders, quoted)
        if part.get("outcome") == PASSED:
            step.outcome = PASSED
        else:
            step.outcome = FAILED
            step.problem = scrub(str(part.get("error")), quoted)


def _episode_note(episode: dict[str, Any]) -> str:
    """Why an episode failed, as ``robospec solve``'s table says it."""
    if episode.get("error"):
        return str(episode["error"])
    return "" if episode.get("planned", True) else "a motion had no plan"


def run_corpus(
    robots: list[Robot], work: Path, workers: int | None = None, progress: IO[str] | None = None
) -> list[Journey]:
    """Every robot's journey, ``workers`` at a time (default: the CPUs this process may use,
    or ``ROBOSPEC_CORPUS_WORKERS``), in the corpus's order."""
    if workers is None:
        workers = int(os.environ.get("ROBOSPEC_CORPUS_WORKERS") or 0) or _cpus()

    def one(robot: Robot) -> Journey:
        journey = run_journey(robot, work / robot.key)
        if progress is not None:
            seconds = sum(step.seconds for step in journey.steps.values())
            outcomes = " ".join(f"{s.name}={s.outcome}" for s in journey.steps.values())
            for task, pick in journey.picks.items():  # what solving adds, said apart
                outcomes += f" {task}={pick.successes}/{pick.episodes} ({pick.seconds:.0f} s)"
                seconds += pick.seconds
            print(f"{robot.key}: {outcomes} ({seconds:.0f} s)", file=progress, flush=True)
        return journey

    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        return list(pool.map(one, robots))


def _cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1
