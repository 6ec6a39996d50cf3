"""RS524, RS525, RS526, RS527, RS528: ``robospec check --task``, the robot in a ManiSkill task,
reset and stepped as users run it (RS524: ``--task`` names no task ManiSkill registers).

For each task asked for (``--task PickCube-v1``, several allowed; ``--task tabletop`` for a
folder of them): ``gym.make(TASK, robot_uids=UID, obs_mode="state", sim_backend="physx_cpu",
render_backend="none")``, ``reset(seed=0)``, then :data:`STEPS` random actions. What goes wrong
is a located diagnostic:

- RS528: the task calls an agent member the spec does not define (the scan of ManiSkill's source
  says which, :mod:`robospec.maniskill.tasks`; a run that fails on one says so too), at the task
  in the spec's ``tasks:`` or at its ``uid``, with the section that defines it;
- RS525: the task cannot run with this robot: it needs several robots, or assets ManiSkill has
  not downloaded (at the ``--task`` argument);
- RS526: the task's objects lie beyond the robot's reach from where the task loads it;
- RS527: the task crashed inside ManiSkill or SAPIEN, or its state went NaN.

A task that cannot run with any robot robospec registers, in the headless scene check runs
(``render_backend="none"``), is not counted against the robot: it needs several robots, assets
ManiSkill has not downloaded (a data group too: TurnFaucet-v1's ``partnet_mobility_faucet``), a
robot of its own (PickCubeSO100-v1 sets ``robot_uids`` itself), or render bodies a scene without
rendering lacks (PushT-v1). Asked for by its folder it is skipped with the reason; by name it is
RS525.
"""

from __future__ import annotations

import math
import traceback
from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

import numpy as np

from robospec.diagnostics import Location, error
from robospec.diagnostics.codes import (
    BEYOND_REACH,
    TASK_CANNOT_RUN,
    TASK_CRASH,
    TASK_MEMBER_MISSING,
)
from robospec.maniskill.crash import USER, from_exception, root_cause
from robospec.maniskill.reach import chain_reach
from robospec.physics.check_run import CheckRun
from robospec.physics.findings import Finding, Status, metrics

if TYPE_CHECKING:
    import gymnasium as gym
    from mani_skill.envs.sapien_env import BaseEnv

    from robospec.maniskill.tasks import Scan

NAME = "task"
SOLVE = "solve"  # check --solve: the finding of a task's solution
MIN_SUCCESS = 0.9  # check --solve fails a task solved in fewer of its episodes
STEPS = 50
SEVERAL_ROBOTS = "agents"


@dataclass(frozen=True)
class TaskRequest:
    """One task to run: its id, where the command line asked for it, and whether by name
    (False: as part of a folder, ``--task tabletop``)."""

    id: str
    at: Location
    explicit: bool = True
    solve: int = 0  # check --solve N: episodes of ManiSkill's solution after the random steps


def check(run: CheckRun, tasks: tuple[TaskRequest, ...]) -> list[Finding]:
    from robospec.maniskill.tasks import installed_tasks

    scan = installed_tasks()
    findings = []
    for request in tasks:
        found = _task(run, request, scan)
        findings.append(found)
        if request.solve and found.status == Status.PASS:
            findings.append(_solve(run, request))
    return findings


def _solve(run: CheckRun, request: TaskRequest) -> Finding:
    """``check --solve N``: N episodes of ManiSkill's solution (``robospec solve``); a FAIL
    under :data:`MIN_SUCCESS`, or where the solution cannot apply (its reason)."""
    from pathlib import Path

    from robospec.solve.command import below_min_success, run_solve

    run.phase(f"solving {request.id}")
    report = run_solve(
        Path(run.context.robot.spec_path), request.id, request.solve, None, 1, 0, progress=False
    )
    short = below_min_success(report, MIN_SUCCESS, ())
    diagnostics = tuple(report.diagnostics) + ((short,) if short is not None else ())
    if not report.episodes:
        return Finding(SOLVE, None, request.id, Status.FAIL, "not solvable", {}, diagnostics)
    successes = sum(e.success for e in report.episodes)
    summary = f"ManiSkill's solution: {successes} of {len(report.episodes)} episodes succeeded"
    status = Status.FAIL if short is not None else Status.PASS
    values = metrics(success_rate=report.success_rate, episodes=len(report.episodes))
    return Finding(SOLVE, None, request.id, status, summary, values, diagnostics)


def _where(run: CheckRun, task: str) -> Location:
    """The spec's ``tasks:`` entry naming ``task`` (or its folder), else its uid."""
    spec = run.context.spec
    for index, name in enumerate(spec.tasks):
        if name == task:
            return run.at(("tasks", index))
    return run.at(("tasks",) if spec.tasks else ("uid",))


def _task(run: CheckRun, request: TaskRequest, scan: Scan | None) -> Finding:
    from robospec.checks.member_names import defined_members
    from robospec.checks.task_members import mend

    task = request.id
    needed = scan.needed(task) if scan is not None and task in scan.tasks else ()
    if SEVERAL_ROBOTS in needed:
        return _cannot(run, request, "it needs several robots at once (robot_uids a tuple)")
    missing_assets = _missing_assets(task)
    if missing_assets:
        ids = " ".join(missing_assets)
        return _cannot(
            run,
            request,
            f"it needs assets ManiSkill has not downloaded ({ids})",
            f"download them (python -m mani_skill.utils.download_asset {ids}), then run it again",
        )
    run.phase(f"running task {task}")
    if run.context.spec.extends is None:
        defined = {name for name, _ in defined_members(run.context)}
        missing = [m for m in needed if m not in defined]
        if missing:
            diagnostics = tuple(
                error(
                    _where(run, task),
                    TASK_MEMBER_MISSING,
                    f"{task} calls agent.{member}: {mend(member, run.context.spec)}",
                    f"without it {task} fails at reset with ManiSkill's NotImplementedError or "
                    "AttributeError (robospec check did not run it)",
                )
                for member in missing
            )
            summary = "missing " + ", ".join(f"agent.{m}" for m in missing)
            return Finding(NAME, None, task, Status.FAIL, summary, {}, diagnostics)
    return _run(run, request)


def _cannot(run: CheckRun, request: TaskRequest, why: str, hint: str | None = None) -> Finding:
    if not request.explicit:
        return Finding(NAME, None, request.id, Status.SKIP, f"not run: {why}")
    diagnostic = error(
        request.at,
        TASK_CANNOT_RUN,
        f"--task {request.id}: {why}",
        hint or "run the robot in a task for one robot (--task tabletop runs those of the folder)",
    )
    return Finding(NAME, None, request.id, Status.FAIL, f"cannot run: {why}", {}, (diagnostic,))


def _missing_assets(task: str) -> list[str]:
    from mani_skill.utils.registration import REGISTERED_ENVS

    spec = REGISTERED_ENVS.get(task)
    if spec is None:
        return []
    return [asset for asset in spec.asset_download_ids or [] if not _downloaded(asset)]


def _downloaded(asset: str, seen: frozenset[str] = frozenset()) -> bool:
    """Whether ManiSkill has ``asset``: a data source, or a group of them (TurnFaucet-v1 names
    the group ``partnet_mobility_faucet``: every source in it)."""
    from mani_skill.utils.assets.data import DATA_GROUPS, is_data_source_downloaded

    if asset in DATA_GROUPS and asset not in seen:
        return all(_downloaded(a, seen | {asset}) for a in DATA_GROUPS[asset])
    try:
        return bool(is_data_source_downloaded(asset))
    except Exception:  # an asset id this ManiSkill does not know: let the task say
        return True


def _cannot_run_here(exc: BaseException) -> tuple[str, str | None] | None:
    """Why a task that raised could never run with a robot robospec registers, in the headless
    scene check runs (``render_backend="none"``) — the robot is not at fault: the task picks
    its own robot, asks to download assets, or reads render bodies such a scene has none of.
    None for any other crash (RS527)."""
    root = root_cause(exc)
    text = str(root)
    if isinstance(root, TypeError) and "multiple values for keyword argument 'robot_uids'" in text:
        return "it is made for one robot of its own (the task sets robot_uids itself)", (
            "run the robot in a task that takes robot_uids (PickCube-v1 rather than "
            "PickCubeSO100-v1)"
        )
    files = [frame.filename for frame in traceback.extract_tb(root.__traceback__)]
    if any(f.replace("\\", "/").endswith("mani_skill/utils/download_asset.py") for f in files):
        return "it needs assets ManiSkill has not downloaded (it asked to download them)", (
            "download them (python -m mani_skill.utils.download_asset TASK_ID), then run it again"
        )
    if isinstance(root, AttributeError) and "render" in (getattr(root, "name", "") or "").lower():
        return (
            "it reads render bodies that a scene without rendering lacks "
            f"({type(root).__name__}: {text}); robospec check runs tasks headless "
            '(render_backend="none")',
            "run it where it renders: gym.make with a render backend on a machine with a GPU",
        )
    return None


def _run(run: CheckRun, request: TaskRequest) -> Finding:
    import gymnasium as gym
    import torch

    from robospec.maniskill.headless import headless_loading

    task = request.id
    env = None
    stage = "gym.make"
    try:
        with headless_loading():
            env = gym.make(
                task,
                robot_uids=run.uid,
                obs_mode="state",
                sim_backend="physx_cpu",
                render_backend="none",
            )
            stage = "reset"
            env.reset(seed=0)
        reach = _reach(run, env, request)
        if reach is not None:
            return reach
        stage = "step"
        space = env.action_space
        space.seed(0)
        unwrapped = cast("BaseEnv", env.unwrapped)
        agent = unwrapped.agent
        for step in range(STEPS):
            env.step(torch.as_tensor(np.asarray(space.sample()), dtype=torch.float32))
            qpos = agent.robot.get_qpos().cpu().numpy()
            if not np.isfinite(qpos).all():
                diagnostic = error(
                    _where(run, task),
                    TASK_CRASH,
                    f"{task}: random actions made the robot's state NaN at step {step + 1}",
                    "run robospec check without --task: its random_actions findings name the cause",
                )
                return Finding(
                    NAME, None, task, Status.FAIL, f"NaN at step {step + 1}", {}, (diagnostic,)
                )
        summary = f"reset and {STEPS} random steps: state finite"
        return Finding(NAME, None, task, Status.PASS, summary, metrics(steps=STEPS))
    except Exception as exc:  # upstream's crash becomes a diagnostic
        cannot = _cannot_run_here(exc)
        if cannot is not None:
            return _cannot(run, request, *cannot)
        return _crashed(run, task, stage, exc)
    finally:
        if env is not None:
            env.close()


def _crashed(run: CheckRun, task: str, stage: str, exc: Exception) -> Finding:
    """A task that raised: a member it calls that the agent lacks is RS330 with its mend;
    anything else RS527 at ManiSkill's frame."""
    from robospec.checks.task_members import mend

    member = _missing_member(exc)
    crash = from_exception(exc)
    if member is not None:
        diagnostic = error(
            _where(run, task),
            TASK_MEMBER_MISSING,
            f"{task} calls agent.{member}: {mend(member, run.context.spec)} (at {stage} it raised "
            f"{type(exc).__name__})",
            f"raised {crash.where()}" if crash.frame else None,
        )
    else:
        # the hint follows whose code raised: a hook of the spec's is the user's to mend
        own = crash.frame is not None and crash.frame.owner == USER
        diagnostic = error(
            _where(run, task),
            TASK_CRASH,
            f"{task} crashed at {stage} with this robot: {crash.what}, {crash.where()}",
            "mend the hook named: the task called it"
            if own
            else "the frame named is where ManiSkill or SAPIEN raised; run robospec check "
            "without --task to see whether the robot alone runs",
        )
    return Finding(NAME, None, task, Status.FAIL, f"crashed at {stage}", {}, (diagnostic,))


def _missing_member(exc: BaseException) -> str | None:
    """The agent member a task called that the agent does not have: ``AttributeError``'s
    name, or the ``BaseAgent`` method that raised ``NotImplementedError``."""
    if isinstance(exc, AttributeError):
        name = getattr(exc, "name", None)
        obj = getattr(exc, "obj", None)
        if name and obj is not None and type(obj).__name__ not in ("Actor", "Link", "Pose"):
            from mani_skill.agents.base_agent import BaseAgent

            if isinstance(obj, BaseAgent):
                return str(name)
        return None
    if isinstance(exc, NotImplementedError):
        tb = exc.__traceback__
        last = None
        while tb is not None:
            if tb.tb_frame.f_code.co_filename.endswith("base_agent.py"):
                last = tb.tb_frame.f_code.co_name
            tb = tb.tb_next
        return last
    return None


def _reach(run: CheckRun, env: gym.Env, request: TaskRequest) -> Finding | None:
    """RS526 when every object of the task lies beyond the robot's reach from its root: the
    sum of its links' offsets along the longest chain (as the task placed it)."""
    base = cast("BaseEnv", env.unwrapped)
    robot = base.agent.robot
    root = robot.pose.p[0].cpu().numpy()
    reach = chain_reach(robot)
    objects = []
    for name, actor in base.scene.actors.items():
        body = actor._objs[0] if actor._objs else None
        kinematic = getattr(actor, "px_body_type", "dynamic") != "dynamic"
        if body is None or kinematic or name == "ground":
            continue
        p = actor.pose.p[0].cpu().numpy()
        objects.append((name, float(np.linalg.norm(p - root))))
    if not objects or reach is None or not math.isfinite(reach):
        return None
    nearest = min(objects, key=lambda item: item[1])
    if nearest[1] <= reach:
        return None
    diagnostic = error(
        request.at,
        BEYOND_REACH,
        f"--task {request.id}: its nearest object, '{nearest[0]}', lies {nearest[1]:.2f} m from "
        f"the robot's root where the task places it, beyond its reach ({reach:.2f} m: its "
        "links end to end)",
        "this task cannot be done by this robot as mounted there; run it in a task made for "
        "its size",
    )
    summary = f"'{nearest[0]}' {nearest[1]:.2f} m away, reach {reach:.2f} m"
    return Finding(NAME, None, request.id, Status.FAIL, summary, {}, (diagnostic,))
