"""The main job, end to end: build the example specs into a package, import it (which registers
the agents, and on a machine without a rendering device makes ManiSkill load them without
visuals), and run each generated robot in ManiSkill with ``render_backend="none"``.

    python -m robospec.maniskill.demo [SPECS...] [-o OUT] [--steps N]

It prints one line per robot: what it ran and what became of the robot. What ManiSkill and
SAPIEN print meanwhile (one loader warning per collision mesh of a Unitree G1) is gathered and
told at the end, each distinct message once, with a count, the robots that said it and what it
means. A robot whose state goes NaN is told with the cause when robospec knows it (PhysX mimic
joints from URDF ``<mimic>`` tags, normalized actions over infinite limits).
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

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
    print(render(diagnostics, len(compiled), "text"))
    if has_errors(diagnostics):
        return 1
    result = build_package(compiled, args.out, check=False)
    if has_errors(result.diagnostics):
        print(render(result.diagnostics, len(compiled), "text"))
        return 1
    modules = sorted(n for n in result.files if n.endswith(".py") and not n.startswith("_"))
    print(f"built {args.out}/ in {time.perf_counter() - started:.2f} s: " + ", ".join(modules))

    said: dict[tuple[str, str, str], Said] = {}
    with captured_output() as output:
        import mani_skill.envs  # noqa: F401  (registers the environments)

        sys.path.insert(0, str(args.out.resolve().parent))
        package = importlib.import_module(args.out.name)
    _gather(said, output.messages(), "while importing")
    contexts = {item.robot.uid: item.context for item in compiled if item.robot is not None}
    print(f"imported {args.out.name}: {len(package.AGENTS)} agents registered")
    for uid, cls in package.AGENTS.items():
        with captured_output() as output:
            ran = _run(uid, args.steps)
        _gather(said, output.messages(), uid)
        print(f"{uid} ({cls.__module__}.{cls.__name__}): {ran.describe(args.steps)}")
        if ran.nan_step is not None:
            print("    " + _why_nan(contexts.get(uid), ran))
    if said:
        print("\nManiSkill and SAPIEN said, each message once:")
        for entry in said.values():
            robots = ", ".join(entry.robots[:3]) + (
                f" and {len(entry.robots) - 3} more" if len(entry.robots) > 3 else ""
            )
            counted = replace(entry.message, count=entry.count)
            print(f"  {counted.describe()} [{robots}]")
    return 0


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

    def describe(self, steps: int) -> str:
        head = (
            f"{self.modes} control modes, default {self.mode}, action shape {self.action_shape}; "
            f"{steps} random steps on physx_cpu"
        )
        if self.nan_step is not None:
            return (
                f"{head}: the state went NaN at step {self.nan_step} ({', '.join(self.nan_joints)})"
            )
        if not self.moved:
            return f"{head}: no joints to move"
        worst = max(range(len(self.moved)), key=self.moved.__getitem__)
        return (
            f"{head}: every joint finite, the most moved {self.joints[worst]} "
            f"({self.moved[worst]:.3g})"
        )


def _run(uid: str, steps: int) -> Run:
    import gymnasium as gym
    import numpy as np

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


def _why_nan(context: Any, ran: Run) -> str:
    from robospec.physics.nan_cause import nan_cause

    known = nan_cause(context, ran.mode, ran.controllers) if context is not None else None
    if known is None:
        return "why: robospec cannot tell; `robospec check` looks at every mode"
    return f"why: {known.cause} (`robospec check` says how to mend it)"


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
