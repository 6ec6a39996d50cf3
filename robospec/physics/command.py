"""``robospec check`` end to end: options in, exit code and rendered report out."""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path

from robospec.diagnostics import Diagnostic, Location, error, has_errors
from robospec.diagnostics.codes import NO_CUDA_DEVICE, NO_RENDER_DEVICE, TASK_NOT_REGISTERED
from robospec.physics.batch import Options, RobotReport, check_paths
from robospec.physics.report import ProgressLine, render_json, render_text
from robospec.physics.sim import CPU, Backend
from robospec.physics.task_run import TaskRequest

COMMAND_LINE = "<command line>"


def run_check(
    paths: Sequence[Path],
    steps: int | None,
    fmt: str,
    gpu: bool,
    num_envs: int,
    render_dir: Path | None,
    plot_dir: Path | None = None,
    tasks: Sequence[str] = (),
    arguments: Sequence[str] = (),
    silence: frozenset[str] = frozenset(),
    solve: int = 0,
) -> tuple[int, str]:
    """``arguments``: the command line as typed (after ``robospec``), to locate ``--task``."""
    problems = _unavailable(gpu, render_dir)
    requests, task_problems = task_requests(tasks, arguments, solve)
    problems += task_problems
    if has_errors(problems):
        return 1, _render([], problems, fmt)
    backend = Backend("physx_cuda", num_envs) if gpu else CPU
    started = time.time()
    progress = ProgressLine()
    try:
        options = Options(steps, backend, render_dir, plot_dir and plot_dir.resolve(), requests)
        reports, extra = check_paths(paths, options, progress, silence=silence)
    finally:
        progress.close()
    extra = [*problems, *extra]
    failed = has_errors(extra) or any(r.failed for r in reports)
    text = _render(reports, extra, fmt)
    if fmt == "text" and plot_dir is not None:
        # the plots are drawn in the worker processes that simulate; what they wrote is what
        # this run left under DIR (a command that writes files says which)
        text += "".join(f"\nwrote {path}" for path in _written_since(plot_dir, started))
    return (1 if failed else 0), text


def _written_since(folder: Path, started: float) -> list[Path]:
    # a second's grace: some file systems keep modification times in whole seconds
    return sorted(
        path for path in folder.rglob("*.png") if path.stat().st_mtime >= int(started) - 1
    )


def task_requests(
    tasks: Sequence[str], arguments: Sequence[str], solve: int = 0
) -> tuple[tuple[TaskRequest, ...], list[Diagnostic]]:
    """The tasks ``--task`` names, folders expanded, each with where the command line names it;
    RS524 for a name the installed ManiSkill does not register."""
    if not tasks:
        return (), []
    from robospec.diagnostics.command_line import argument_location
    from robospec.diagnostics.suggest import did_you_mean
    from robospec.maniskill.tasks import installed_tasks

    scan = installed_tasks()
    requests: list[TaskRequest] = []
    problems: list[Diagnostic] = []
    for name in tasks:
        at = argument_location("--task", name, arguments)
        if name in scan.tasks:
            requests.append(TaskRequest(name, at, solve=solve))
        elif name in scan.families:
            requests.extend(
                TaskRequest(task, at, explicit=False, solve=solve) for task in scan.family(name)
            )
        else:
            suggestion = did_you_mean(name, [*scan.tasks, *scan.families])
            problems.append(
                error(
                    at,
                    TASK_NOT_REGISTERED,
                    f"--task {name}: ManiSkill registers no such task"
                    + (f" ({suggestion})" if suggestion else ""),
                    "name a task id (PickCube-v1) or a folder of tasks: "
                    + ", ".join(scan.families),
                )
            )
    return tuple(requests), problems


def _render(reports: Sequence[RobotReport], extra: Sequence[Diagnostic], fmt: str) -> str:
    return render_json(reports, extra) if fmt == "json" else render_text(reports, extra)


def _unavailable(gpu: bool, render_dir: Path | None) -> list[Diagnostic]:
    """What the machine lacks for the options asked for, before any robot is loaded, and what
    is wrong with its ManiSkill."""
    from robospec.maniskill.installed import installed, mixed_install_problem

    mixed = mixed_install_problem(installed())
    problems = [mixed] if mixed is not None else []
    if gpu:
        import torch

        if not torch.cuda.is_available():
            problems.append(
                error(
                    Location(COMMAND_LINE),
                    NO_CUDA_DEVICE,
                    "--gpu needs a CUDA device and this machine has none",
                    "run without --gpu: every check also runs on physx_cpu",
                )
            )
    if render_dir is not None:
        from robospec.physics.render import render_device_error

        reason = render_device_error()
        if reason is not None:
            problems.append(
                error(
                    Location(COMMAND_LINE),
                    NO_RENDER_DEVICE,
                    f"--render needs a render device: {reason}",
                    "render on a machine with a GPU; the other checks need none",
                )
            )
    return problems
