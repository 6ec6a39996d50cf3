"""``robospec solve SPEC --task TASK -n N -o DIR``: N demonstrations of TASK by ManiSkill's own
solution, planned by robospec for the spec's robot, in ManiSkill's trajectory format.

Before any episode: a located reason where the solution cannot apply (RS680 no solution robospec
runs for the task, RS681 no two-finger grasp check, RS682 a gripper or arm the solver cannot
drive, RS526 the task's objects beyond the robot's reach from where the task mounts it, with
the reach measured: its links end to end, and, for a solution that grasps from above, with its
grasp pointing straight down at the objects' height, over the seeds asked). Then the episodes
(seeds ``--seed`` on), spread over ``--num-procs`` processes as ManiSkill's run scripts spread
them, each writing its part, merged into ``DIR/TASK.h5`` and ``.json`` by ManiSkill's
``merge_trajectories``; each episode's success as the task judges it.
"""

from __future__ import annotations

import json
import multiprocessing
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import (
    BEYOND_REACH,
    NO_SOLUTION,
    NO_TWO_FINGER_GRIPPER,
    SOLVER_CANNOT_DRIVE,
    TASK_MEMBER_MISSING,
    TOO_FEW_SUCCESSES,
)
from robospec.solve.episodes import Episode
from robospec.solve.gripper import Closing

if TYPE_CHECKING:
    from multiprocessing.queues import Queue

    from mani_skill.envs.sapien_env import BaseEnv

TASK_OPTION = "--task"


@dataclass
class SolveReport:
    uid: str
    task: str
    episodes: list[Episode] = field(default_factory=list)
    trajectory: Path | None = None
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def success_rate(self) -> float:
        return sum(e.success for e in self.episodes) / len(self.episodes) if self.episodes else 0.0

    def as_dict(self) -> dict[str, Any]:
        return {
            "uid": self.uid,
            "task": self.task,
            "episodes": [e.as_dict() for e in self.episodes],
            "successes": sum(e.success for e in self.episodes),
            "success_rate": self.success_rate,
            "trajectory": str(self.trajectory) if self.trajectory else None,
            "diagnostics": [d.to_json() for d in self.diagnostics],
        }


@dataclass(frozen=True)
class Robot:
    """What the episodes need of the compiled spec, and where its sections are written."""

    spec: Path
    uid: str
    fingers: tuple[str, str]
    sections: dict[str, Location] = field(default_factory=dict)
    modes: tuple[str, ...] = ()
    # the spec's closed loops (a finger can move through one): each its two links, the point
    # where they meet in each one's frame, and the joints of its cycle
    loops: tuple[Closing, ...] = ()


def run_solve(
    spec: Path,
    task: str,
    count: int,
    out: Path | None,
    procs: int,
    seed: int,
    arguments: Sequence[str] = (),
    progress: bool = True,
) -> SolveReport:
    """Solve ``task`` ``count`` times; ``out``: where the trajectory goes (None: nowhere)."""
    from robospec.diagnostics.command_line import argument_location
    from robospec.solve.solutions import SOLUTIONS

    at_task = argument_location(TASK_OPTION, task, arguments)
    report = SolveReport(uid="", task=task)
    robot, problems = compile_robot(spec)
    report.diagnostics += problems
    if robot is None:
        return report
    report.uid = robot.uid
    if task not in SOLUTIONS:
        report.diagnostics.append(
            error(
                at_task,
                NO_SOLUTION,
                f"robospec runs no ManiSkill solution for {task}",
                f"tasks it solves: {', '.join(SOLUTIONS)}",
            )
        )
        return report
    seeds = list(range(seed, seed + count))
    refusal = preflight(robot, task, at_task, seeds)
    if refusal is not None:
        report.diagnostics.append(refusal)
        return report
    report.episodes, report.trajectory = _episodes(robot, task, seeds, out, procs, progress)
    return report


def compile_robot(spec: Path) -> tuple[Robot | None, list[Diagnostic]]:
    """The spec compiled and registered; RS681 when it declares no two-finger grasp check."""
    from robospec.diagnostics import has_errors
    from robospec.output.register import register
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    problems = [d for d in compiled.diagnostics if d.is_error]
    if has_errors(compiled.diagnostics) or compiled.robot is None or compiled.context is None:
        return None, problems
    resolved = compiled.robot
    if not resolved.grasping:
        where = compiled.context.key(("uid",))
        return None, [
            error(
                where,
                NO_TWO_FINGER_GRIPPER,
                f"'{resolved.uid}' has no two-finger gripper the solutions can close: the spec "
                "declares no grasp check (`grasping`)",
                "declare `grasping` with the two finger links (`robospec new` writes it for a "
                "gripper it recognises)",
            )
        ]
    named = dict(resolved.named_links)
    first, second = (
        str(named.get(finger.link, finger.link)) for finger in resolved.grasping[0].fingers
    )
    register(str(spec))
    context = compiled.context
    sections = {name: context.key((name,)) for name in compiled.context.spec.model_fields_set}
    modes = tuple(mode.name for mode in resolved.modes)
    loops = tuple(
        Closing(
            (str(named.get(a, a)), str(named.get(b, b))),
            (tuple(loop.poses[0][0]), tuple(loop.poses[1][0])),
            tuple(loop.joints),
        )
        for loop in resolved.loops
        for a, b in [loop.links]
    )
    return Robot(spec, resolved.uid, (first, second), sections, modes, loops), []


def preflight(
    robot: Robot, task: str, at_task: Location, seeds: Sequence[int] = (0,)
) -> Diagnostic | None:
    """Why the solution cannot apply to ``robot`` in ``task``, read from the scene the task
    builds (at ``seeds``, the episodes' resets): None when it can."""
    from robospec.solve.episodes import make_env
    from robospec.solve.gripper import MODE, NotSolvable, read_facts
    from robospec.solve.reach import beyond_downward_reach
    from robospec.solve.solutions import GRASPED_FROM_ABOVE

    if MODE not in robot.modes:
        return error(
            robot.sections.get("control_modes", robot.sections["uid"]),
            SOLVER_CANNOT_DRIVE,
            f"the solutions act in control mode {MODE}, which the spec does not offer",
            f"add a control mode {MODE} with absolute arm and gripper position controllers",
        )
    env = None
    try:
        env = make_env(robot.uid, task)
        env.reset(seed=0)
    except (AttributeError, NotImplementedError) as exc:  # the task calls what the agent lacks
        return error(
            robot.sections.get("uid", Location(str(robot.spec))),
            TASK_MEMBER_MISSING,
            f"{task} calls an agent member this robot does not define "
            f"({type(exc).__name__}: {exc})",
            f"list {task} under `tasks:` and run robospec validate: it names the member and "
            "the section that defines it",
        )
    try:
        base = cast("BaseEnv", env.unwrapped)
        reach, beyond = _beyond_chain_reach(base, task, at_task)
        if beyond is not None:
            return beyond
        try:
            facts = read_facts(base.agent, robot.fingers, robot.loops)
        except NotSolvable as exc:
            at = robot.sections.get(
                exc.section, robot.sections.get("uid", Location(str(robot.spec)))
            )
            return error(at, SOLVER_CANNOT_DRIVE, str(exc), exc.hint)
        if task in GRASPED_FROM_ABOVE and reach is not None:
            why = beyond_downward_reach(env, facts, list(seeds), reach)
            if why is not None:
                return error(
                    at_task,
                    BEYOND_REACH,
                    f"{task}: {why}",
                    "the task mounts every robot where it mounts the Panda; from there this "
                    "arm cannot reach down to most of the task's placements",
                )
        return None
    finally:
        env.close()


def _beyond_chain_reach(
    base: BaseEnv, task: str, at_task: Location
) -> tuple[float | None, Diagnostic | None]:
    """The reach of the arm that carries the tcp, its links end to end, from its base (one arm
    of two: its own base) over the links it carries; and RS526 where one of the task's objects
    lies beyond it."""
    import numpy as np

    from robospec.maniskill.reach import arm_base, chain_reach
    from robospec.solve.reach import dynamic_actors

    tcp = getattr(base.agent, "tcp", None)
    arm = arm_base(tcp) if tcp is not None and hasattr(tcp, "joint") else None
    if arm is None or arm.joint is None or arm.joint.parent_link is None:  # the root's
        root = base.agent.robot.pose.p[0].cpu().numpy()
        reach = chain_reach(base.agent.robot)
        where = "the robot's root"
    else:
        root = arm.pose.p[0].cpu().numpy()
        reach = chain_reach(base.agent.robot, arm.name)
        where = f"{arm.name} (the base of the tcp's arm)"
    farthest = max(
        (
            (name, float(np.linalg.norm(point - root)))
            for name, point in dynamic_actors(base).items()
        ),
        key=lambda item: item[1],
        default=None,
    )
    if farthest is None or reach is None or farthest[1] <= reach:
        return reach, None
    return reach, error(
        at_task,
        BEYOND_REACH,
        f"{task}: '{farthest[0]}' lies {farthest[1]:.2f} m from {where} where the "
        f"task mounts it, beyond its reach ({reach:.2f} m: its links end to end)",
        "the task mounts every robot where it mounts the Panda; this arm cannot reach "
        "its objects from there",
    )


def _episodes(
    robot: Robot, task: str, seeds: list[int], out: Path | None, procs: int, progress: bool
) -> tuple[list[Episode], Path | None]:
    import tempfile

    from tqdm import tqdm

    folder = out if out is not None else Path(tempfile.mkdtemp(prefix="robospec-solve-"))
    folder.mkdir(parents=True, exist_ok=True)
    bar = tqdm(total=len(seeds), desc=f"{robot.uid} {task}", disable=not progress, file=sys.stderr)
    procs = max(1, min(procs, len(seeds)))
    chunks = [seeds[i::procs] for i in range(procs)]
    done: list[Episode] = []

    def count(episode: Episode) -> None:
        done.append(episode)
        bar.update(1)
        bar.set_postfix(success=f"{sum(e.success for e in done) / len(done):.0%}")

    try:
        if procs == 1:
            from robospec.solve.episodes import record

            parts = [
                record(robot.uid, task, robot.fingers, seeds, folder, task, count, robot.loops)
            ]
        else:
            parts = _in_processes(robot, task, chunks, folder, count)
    finally:
        bar.close()
    trajectory = _merged(parts, folder / f"{task}.h5")
    if out is None:
        trajectory = None
    return sorted(done, key=lambda e: e.seed), trajectory


def _in_processes(
    robot: Robot, task: str, chunks: list[list[int]], folder: Path, count: Callable[[Episode], None]
):
    context = multiprocessing.get_context("spawn")
    queue = context.Queue()
    workers = [
        context.Process(
            target=_worker,
            args=(
                str(robot.spec),
                robot.uid,
                task,
                robot.fingers,
                chunk,
                str(folder),
                i,
                queue,
                robot.loops,
            ),
        )
        for i, chunk in enumerate(chunks)
    ]
    for worker in workers:
        worker.start()
    parts: list[Path] = []
    finished = 0
    while finished < len(workers):
        kind, value = queue.get()
        if kind == "episode":
            count(Episode(**value))
        elif kind == "done":
            parts.append(Path(value))
            finished += 1
        else:  # a worker that failed says why; the others' episodes still count
            finished += 1
            print(f"robospec solve: a worker failed: {value}", file=sys.stderr)
    for worker in workers:
        worker.join()
    return sorted(parts)


def _worker(
    spec: str,
    uid: str,
    task: str,
    fingers: tuple[str, str],
    seeds: list[int],
    folder: str,
    index: int,
    queue: Queue[tuple[str, object]],
    loops: tuple[Closing, ...] = (),
) -> None:
    from robospec.output.register import register
    from robospec.solve.episodes import record

    try:
        register(spec)
        path = record(
            uid,
            task,
            fingers,
            seeds,
            Path(folder),
            f"{task}.{index}",
            lambda e: queue.put(("episode", e.as_dict())),
            loops,
        )
        queue.put(("done", str(path)))
    except Exception as exc:  # reported by the parent
        queue.put(("failed", f"{type(exc).__name__}: {exc}"))


def _merged(parts: list[Path], target: Path) -> Path | None:
    """The parts as one trajectory (ManiSkill's merge_trajectories), the parts removed."""
    if not parts:
        return None
    if parts == [target]:
        return target
    from mani_skill.trajectory.merge_trajectory import merge_trajectories

    merge_trajectories(str(target), [str(p) for p in parts])
    for part in parts:
        part.unlink()
        part.with_suffix(".json").unlink()
    return target


def below_min_success(
    report: SolveReport, least: float | None, arguments: Sequence[str]
) -> Diagnostic | None:
    """RS683 when fewer episodes succeeded than ``--min-success`` asks."""
    from robospec.diagnostics.command_line import argument_location

    if least is None or not report.episodes or report.success_rate >= least:
        return None
    return error(
        argument_location("--min-success", f"{least:g}", arguments),
        TOO_FEW_SUCCESSES,
        f"{report.uid} {report.task}: {report.success_rate:.0%} of the episodes succeeded, "
        f"under --min-success {least:g}",
        "the table says which seeds failed; replay one (docs/solve.md) to see why",
    )


# -- the report ------------------------------------------------------------------------------


def render_report(report: SolveReport, fmt: str) -> str:
    if fmt == "json":
        return json.dumps(report.as_dict(), indent=2)
    from robospec.reporting import render

    lines = [render(report.diagnostics, 1, "text")] if report.diagnostics else []
    if report.episodes:
        lines += ["| seed | success | steps | note |", "| ---: | --- | ---: | --- |"]
        for e in report.episodes:
            note = e.error or ("" if e.planned else "a motion had no plan")
            lines.append(f"| {e.seed} | {'yes' if e.success else 'no'} | {e.steps} | {note} |")
        successes = sum(e.success for e in report.episodes)
        lines.append("")
        lines.append(
            f"{report.uid} {report.task}: {successes} of {len(report.episodes)} episodes "
            f"succeeded ({report.success_rate:.0%})"
        )
    if report.trajectory is not None:
        lines.append(f"wrote {report.trajectory} and {report.trajectory.with_suffix('.json')}")
    return "\n".join(lines)
