"""The main job, end to end: build the example specs into a package, import it (which registers
the agents, and on a machine without a rendering device makes ManiSkill load them without
visuals), and run each generated robot in ManiSkill with ``render_backend="none"``.

    python -m robospec.demo.tour [SPECS...] [-o OUT] [--steps N]

It prints how many warnings the specs have (``robospec validate`` shows them), then a table: per
robot, what it ran and what became of it. A robot whose state goes NaN gets a note: ManiSkill's
own agent for the same description, run the same way (robospec's specs of ManiSkill's robots
reproduce its problems faithfully, and the note says when ManiSkill's agent does the same), and
the cause when robospec knows it (PhysX mimic joints from URDF ``<mimic>`` tags, normalized
actions over infinite limits). What ManiSkill and SAPIEN print meanwhile (one loader warning per
collision mesh of a Unitree G1) is gathered and told at the end, each distinct message once,
with a count, the robots that said it and what it means.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from robospec.maniskill.upstream_output import UpstreamMessage, captured_output


@dataclass
class Said:
    """A message of ManiSkill or SAPIEN over the whole run, and the robots it was said for."""

    message: UpstreamMessage
    count: int = 0
    robots: list[str] = field(default_factory=list)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("specs", nargs="*", default=["specs"], type=Path)
    parser.add_argument("-o", "--out", default=Path("out/robospec_agents"), type=Path)
    parser.add_argument("--steps", default=20, type=int)
    args = parser.parse_args(argv)

    from robospec.diagnostics import has_errors
    from robospec.output.package import build_package
    from robospec.pipeline import compile_all
    from robospec.reporting import render

    started = time.perf_counter()
    compiled, diagnostics = compile_all(args.specs)
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    if has_errors(diagnostics):
        print(render(diagnostics, len(compiled), "text"))
        return 1
    # warnings are told by `robospec validate`, with their excerpts; here, how many of which
    print(_warnings_line(diagnostics, len(compiled), args.specs))
    result = build_package(compiled, args.out, check=False)
    if has_errors(result.diagnostics):
        print(render(result.diagnostics, len(compiled), "text"))
        return 1
    modules = [n for n in result.files if n.endswith(".py") and not n.startswith("_")]
    print(f"built {args.out}/ in {time.perf_counter() - started:.2f} s: {len(modules)} modules")

    said: dict[tuple[str, str, str], Said] = {}
    with captured_output() as output:
        import mani_skill.envs  # noqa: F401  (registers the environments)

        sys.path.insert(0, str(args.out.resolve().parent))
        package = importlib.import_module(args.out.name)
    _gather(said, output.messages(), "while importing")
    robots = {item.robot.uid: item for item in compiled if item.robot is not None}
    print(f"imported {args.out.name}: {len(package.AGENTS)} agents registered")
    print(f"\n{args.steps} random actions in each robot's default control mode, on physx_cpu:")
    rows: list[tuple[str, ...]] = [
        ("robot", "modes", "default mode", "actions", "what became of it")
    ]
    notes: list[str] = []
    for uid in package.AGENTS:
        with captured_output() as output:
            ran = _run(uid, args.steps)
        _gather(said, output.messages(), uid)
        outcome = ran.outcome()
        if ran.nan_step is not None:
            notes.append(_nan_note(robots.get(uid), ran, args.steps, said, set(package.AGENTS)))
            outcome += f" [{len(notes)}]"
        rows.append((uid, str(ran.modes), ran.mode, str(ran.action_size), outcome))
    print(_table(rows))
    for number, note in enumerate(notes, 1):
        print(f"[{number}] {note}")
    if said:
        print("\nManiSkill and SAPIEN said, each message once:")
        for entry in said.values():
            robots_said = ", ".join(entry.robots[:3]) + (
                f" and {len(entry.robots) - 3} more" if len(entry.robots) > 3 else ""
            )
            counted = replace(entry.message, count=entry.count)
            print(f"  {counted.describe()} [{robots_said}]")
    return 0


def _warnings_line(diagnostics: list[Any], files: int, specs: list[Path]) -> str:
    codes = Counter(d.code for d in diagnostics)
    if not codes:
        return f"{files} spec(s) valid, no warnings"
    counted = ", ".join(f"{code} x{n}" for code, n in codes.most_common())
    where = " ".join(str(path) for path in specs)
    return (
        f"{files} spec(s) valid; {sum(codes.values())} warning(s) ({counted}): "
        f"`robospec validate {where}` shows each"
    )


def _table(rows: list[tuple[str, ...]]) -> str:
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    lines = []
    for row in rows:
        cells = [
            cell.rjust(w) if i in (1, 3) else cell.ljust(w)
            for i, (cell, w) in enumerate(zip(row, widths, strict=False))
        ]
        lines.append("  ".join([*cells, row[-1]]).rstrip())
    return "\n".join(lines)


@dataclass
class Run:
    """What one robot did in ``steps`` random actions of its default control mode."""

    modes: int
    mode: str
    action_shape: tuple[int, ...]
    joints: tuple[str, ...]
    moved: list[float]  # the largest change of each joint's position
    nan_step: int | None = None
    nan_joints: tuple[str, ...] = ()
    controllers: list[tuple[str, Any]] = field(default_factory=list)

    @property
    def action_size(self) -> int:
        return int(np.prod(self.action_shape)) if self.action_shape else 0

    def outcome(self) -> str:
        if self.nan_step is not None:
            return f"state NaN at step {self.nan_step} ({len(self.nan_joints)} joints)"
        if not self.moved:
            return "no joints to move"
        worst = max(range(len(self.moved)), key=self.moved.__getitem__)
        return f"finite; most moved {self.joints[worst]} ({self.moved[worst]:.3g})"


def _run(uid: str, steps: int) -> Run:
    import gymnasium as gym

    # plain gym.make, as a user writes it: the package's import made it work without a
    # rendering device
    env: Any = gym.make(
        "Empty-v1",
        robot_uids=uid,
        obs_mode="state",
        sim_backend="physx_cpu",
        render_backend="none",
    )
    try:
        env.reset(seed=0)
        agent = env.unwrapped.agent
        robot = agent.robot
        joints = tuple(j.name for j in robot.get_active_joints())
        start = robot.get_qpos()[0].cpu().numpy().astype(np.float64)
        rng = np.random.default_rng(0)
        space = env.action_space
        parts = getattr(agent.controller, "controllers", None)
        run = Run(
            len(agent.supported_control_modes),
            agent.control_mode,
            tuple(space.shape),
            joints,
            [0.0] * len(joints),
            controllers=list(parts.items()) if parts else [(agent.control_mode, agent.controller)],
        )
        for step in range(steps):
            env.step(rng.uniform(space.low, space.high).astype(np.float32))
            qpos = robot.get_qpos()[0].cpu().numpy().astype(np.float64)
            bad = ~np.isfinite(qpos)
            if bad.any():
                run.nan_step = step + 1
                run.nan_joints = tuple(n for n, b in zip(joints, bad, strict=True) if b)
                break
            run.moved = list(np.maximum(run.moved, np.abs(qpos - start)))
        return run
    finally:
        env.close()


def _nan_note(
    item: Any, ran: Run, steps: int, said: dict[tuple[str, str, str], Said], ours: set[str]
) -> str:
    """Why a robot went NaN: ManiSkill's own agent for the same description, run as the
    robot was (it goes NaN too when the robot reproduces it faithfully), and the cause when
    robospec knows it."""
    from robospec.physics.nan_cause import nan_cause

    uid = item.robot.uid if item is not None else "?"
    parts = []
    twin = _upstream_twin(item, ours) if item is not None else None
    if twin is not None:
        with captured_output() as output:
            theirs = _run(twin, steps)
        _gather(said, output.messages(), twin)
        if theirs.nan_step is not None:
            parts.append(
                f"ManiSkill's own agent '{twin}', with the same description, goes NaN too "
                f"(step {theirs.nan_step}): {uid} reproduces ManiSkill's behaviour"
            )
        else:
            parts.append(f"ManiSkill's own agent '{twin}' stays finite: {theirs.outcome()}")
    known = (
        nan_cause(item.context, ran.mode, ran.controllers)
        if item is not None and item.context is not None
        else None
    )
    if known is None:
        parts.append("why: robospec cannot tell; `robospec check` looks at every mode")
    else:
        parts.append(f"why: {known.cause} (`robospec check` says how to mend it)")
    return f"{uid}: " + "; ".join(parts)


def _upstream_twin(item: Any, ours: set[str]) -> str | None:
    """The uid of the ManiSkill agent (not one of ``ours``) that loads the same description
    file as ``item``'s robot, if ManiSkill registers one."""
    from mani_skill import format_path
    from mani_skill.agents.registration import REGISTERED_AGENTS

    robot = item.robot
    if robot is None or robot.description.kind != "maniskill_assets":
        return None
    mine = Path(robot.description.absolute).resolve()
    for uid, entry in sorted(REGISTERED_AGENTS.items()):
        cls = entry.agent_cls
        path = getattr(cls, "urdf_path", None) or getattr(cls, "mjcf_path", None)
        if uid not in ours and path and Path(format_path(str(path))).resolve() == mine:
            return str(uid)
    return None


def _gather(
    said: dict[tuple[str, str, str], Said], messages: list[UpstreamMessage], who: str
) -> None:
    for message in messages:
        key = (message.source, message.level, message.text)
        entry = said.setdefault(key, Said(message))
        entry.count += message.count
        if who not in entry.robots:
            entry.robots.append(who)


if __name__ == "__main__":
    sys.exit(main())
