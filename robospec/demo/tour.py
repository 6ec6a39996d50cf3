"""The main job, end to end: build the example specs into a package, import it (which registers
the agents, and on a machine without a rendering device makes ManiSkill load them without
visuals), and run each generated robot in ManiSkill with ``render_backend="none"``.

    python -m robospec.demo.tour [SPECS...] [-o OUT] [--steps N]

It prints what ``robospec validate`` counts (warnings and notes, by code), then a table: per
robot, what it ran and its verdict, judged as ``robospec check`` judges random actions
(:func:`robospec.physics.random_actions.runaways`, by the spec's ``checks.random_actions``): a
state gone NaN, or a joint past its limit or faster than the bound, is a failure, said with
its units. A robot that misbehaves is run once more as ManiSkill's own agent for the same
description: where that agent does the same (robospec's specs of ManiSkill's robots reproduce
its behaviour faithfully, tests/test_equivalence.py), the verdict says so, apart from the
robots that fail on their own. The table is in that order: robots that run fine, robots that
behave as ManiSkill's own, then failures, by uid within each. Numbered notes, wrapped, say
why, with the cause when robospec knows it (PhysX mimic joints from URDF ``<mimic>`` tags,
normalized actions over infinite limits). What ManiSkill and SAPIEN print meanwhile is told
once per distinct message, with a count and what it means; last, what was built and what to
do next, with the commands as they run from here (``.venv/bin/robospec`` where the
environment is not activated).
"""

from __future__ import annotations

import argparse
import importlib
import os
import shutil
import sys
import textwrap
import time
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from robospec.maniskill.upstream_output import UpstreamMessage, captured_output

if TYPE_CHECKING:
    from collections.abc import Mapping

    from gymnasium import spaces
    from mani_skill.agents.base_agent import BaseAgent
    from mani_skill.agents.controllers.base_controller import BaseController
    from mani_skill.envs.sapien_env import BaseEnv

    from robospec.model.check_settings import RandomActions
    from robospec.physics.random_actions import Runaway
    from robospec.pipeline import CompiledSpec

WIDTH = 100  # the notes are wrapped to it
# the verdicts, in the table's order
OK, AS_MANISKILL, FAILS = "ok", "as ManiSkill", "fails"
VERDICTS = (OK, AS_MANISKILL, FAILS)


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

    robospec = command("robospec")
    specs = " ".join(str(path) for path in args.specs)
    compiled = _build(args.specs, args.out, f"{robospec} validate {specs}")
    if compiled is None:
        return 1
    said: dict[tuple[str, str, str], Said] = {}
    with captured_output() as output:
        import mani_skill.envs  # noqa: F401  (registers the environments)

        sys.path.insert(0, str(args.out.resolve().parent))
        package = importlib.import_module(args.out.name)
    _gather(said, output.messages(), "while importing")
    robots = {item.robot.uid: item for item in compiled if item.robot is not None}
    print(f"imported {args.out.name}: {len(package.AGENTS)} agents registered")

    verdicts = _verdicts(package.AGENTS, robots, args.steps, said)
    print()
    _print_verdicts(verdicts, robots, args.steps, robospec)
    _print_said(said)
    print()
    print(next_steps(args.out, len(package.AGENTS), verdicts, robots, robospec, specs))
    return 0


def _build(specs: list[Path], out: Path, validate: str) -> list[CompiledSpec] | None:
    """The specs compiled and built into the package ``out``, saying how many warnings of
    which codes they have; None (the errors printed) when they do not compile or build."""
    from robospec.diagnostics import has_errors
    from robospec.output.package import build_package
    from robospec.pipeline import compile_all
    from robospec.reporting import render

    started = time.perf_counter()
    compiled, diagnostics = compile_all(specs)
    for item in compiled:
        diagnostics.extend(item.diagnostics)
    if has_errors(diagnostics):
        print(render(diagnostics, len(compiled), "text"))
        return None
    # warnings are told by `robospec validate`, with their excerpts; here, how many of which
    print(warnings_line(diagnostics, len(compiled), validate))
    result = build_package(compiled, out, check=False)
    if has_errors(result.diagnostics):
        print(render(result.diagnostics, len(compiled), "text"))
        return None
    modules = [n for n in result.files if n.endswith(".py") and not n.startswith("_")]
    print(f"built {out}/ in {time.perf_counter() - started:.2f} s: {len(modules)} modules")
    return compiled


def _verdicts(
    agents: Mapping[str, type[BaseAgent]],
    robots: dict[str, CompiledSpec],
    steps: int,
    said: dict[tuple[str, str, str], Said],
) -> list[Verdict]:
    """Each agent run and judged, in the table's order; one that misbehaves beside ManiSkill's
    own agent for the same description (each of those run once)."""
    verdicts = []
    twins: dict[str, Run] = {}  # ManiSkill's agents, each run once
    for uid in agents:
        item = robots.get(uid)
        settings = _settings(item)
        with captured_output() as output:
            ran = _run(uid, steps, settings)
        _gather(said, output.messages(), uid)
        twin = _upstream_twin(item, set(agents)) if ran.misbehaved else None
        if twin is not None and twin not in twins:
            with captured_output() as output:
                twins[twin] = _run(twin, steps, settings)
            _gather(said, output.messages(), twin)
        verdicts.append(judge(uid, ran, twin, twins.get(twin) if twin else None))
    verdicts.sort(key=lambda v: (VERDICTS.index(v.verdict), v.uid))
    return verdicts


def _print_verdicts(
    verdicts: list[Verdict], robots: dict[str, CompiledSpec], steps: int, robospec: str
) -> None:
    """The table of verdicts, then the numbered notes on each robot that is not ok."""
    print(
        textwrap.fill(
            f"{steps} random actions in each robot's default control mode, on physx_cpu, "
            "judged as robospec check judges them (checks.random_actions): robots that run "
            "fine, then those that behave as ManiSkill's own agent does, then failures; by "
            "uid within each:",
            WIDTH,
        )
    )
    rows: list[tuple[str, ...]] = [
        ("robot", "modes", "default mode", "actions", "verdict", "what became of it")
    ]
    notes: list[str] = []
    for verdict in verdicts:
        outcome = verdict.ran.outcome()
        if verdict.verdict != OK:
            notes.append(_note(verdict, robots.get(verdict.uid), robospec))
            outcome += f" [{len(notes)}]"
        ran = verdict.ran
        rows.append(
            (verdict.uid, str(ran.modes), ran.mode, str(ran.action_size), verdict.verdict, outcome)
        )
    print(_table(rows))
    for number, note in enumerate(notes, 1):
        print(_wrapped(f"[{number}] ", note))


def _print_said(said: dict[tuple[str, str, str], Said]) -> None:
    """What ManiSkill and SAPIEN printed over the run, each message once."""
    if said:
        print("\nManiSkill and SAPIEN said, each message once:")
        for entry in said.values():
            robots_said = ", ".join(entry.robots[:3]) + (
                f" and {len(entry.robots) - 3} more" if len(entry.robots) > 3 else ""
            )
            counted = replace(entry.message, count=entry.count)
            print(_wrapped("  ", f"{counted.describe()} [{robots_said}]"))


# -- what is said ---------------------------------------------------------------------------


def command(name: str) -> str:
    """How to call the console script ``name`` from here: by its name where that is the one
    on PATH, else by its path beside this Python (a virtual environment's ``bin/`` that is not
    activated: ``.venv/bin/robospec``, relative to the current folder when inside it)."""
    beside = Path(sys.executable).parent / name
    if not beside.is_file():
        return name if name != "robospec" else f"{sys.executable} -m robospec"
    found = shutil.which(name)
    if found is not None and Path(found).resolve() == beside.resolve():
        return name
    relative = os.path.relpath(beside)
    return relative if not relative.startswith("..") else str(beside)


def warnings_line(diagnostics: list[Any], files: int, validate: str) -> str:
    """How many warnings and notes the specs have, as ``robospec validate`` counts them, and
    of which codes."""
    from robospec.reporting.summary import summary

    codes = Counter(d.code for d in diagnostics)
    if not codes:
        return f"{files} spec(s) valid, no warnings"
    counts = summary(diagnostics, files)
    notes = f" and {counts['notes']} note(s)" if counts["notes"] else ""
    counted = ", ".join(f"{code} x{n}" for code, n in codes.most_common())
    return (
        f"{files} spec(s) valid; {counts['warnings']} warning(s){notes} ({counted}): "
        f"`{validate}` shows each"
    )


def next_steps(
    out: Path,
    agents: int,
    verdicts: list[Verdict],
    robots: dict[str, Any],
    robospec: str,
    specs: str,
) -> str:
    """The demo's last word: what was built, and the three things to do next."""
    failing = [v for v in verdicts if v.verdict != OK]
    # the table's last: a failure of its own rather than one that reproduces ManiSkill's
    worst = failing[-1] if failing else None
    item = robots.get(worst.uid) if worst is not None else None
    built = textwrap.fill(
        f"Built {out}/: {agents} agents, registered by `import {out.name}` (with "
        f"{out.resolve().parent} on sys.path). Next:",
        WIDTH,
    )
    steps = [
        (f"{robospec} validate {specs}", "the warnings and notes above, each at its line"),
        (f"{robospec} check {specs}", "robospec check's physics checks, mode by mode"),
        (f"{command('mkdocs')} serve", "the docs site: the tutorial, then a robot of your own"),
    ]
    if worst is not None and item is not None:
        steps[1] = (
            f"{robospec} check {item.display}",
            f"why {worst.uid} {'fails' if worst.verdict == FAILS else 'misbehaves'}, mode by "
            "mode, with each cause",
        )
    lines = [built]
    for run, what in steps:
        lines += [f"  {run}", _wrapped("      ", what)]
    return "\n".join(lines)


def _wrapped(lead: str, text: str) -> str:
    return textwrap.fill(
        text,
        WIDTH,
        initial_indent=lead,
        subsequent_indent=" " * len(lead) + "    ",
        break_long_words=False,
        break_on_hyphens=False,
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


# -- running and judging --------------------------------------------------------------------


@dataclass
class Run:
    """What one robot did in ``steps`` random actions of its default control mode, measured
    as ``robospec check`` measures random actions (arrays of shape ``(J,)``)."""

    modes: int
    mode: str
    action_shape: tuple[int, ...]
    joints: tuple[str, ...]
    prismatic: tuple[bool, ...]
    settings: RandomActions  # the checks.random_actions it is judged by
    past_limit: np.ndarray  # how far past its limit and the tolerance each joint went
    top_speed: np.ndarray
    top_root_speed: float = 0.0  # a floating robot's centre of mass
    nan_step: int | None = None
    nan_joints: tuple[str, ...] = ()
    controllers: list[tuple[str, BaseController]] = field(default_factory=list)

    @property
    def action_size(self) -> int:
        return int(np.prod(self.action_shape)) if self.action_shape else 0

    def runaways(self) -> list[Runaway]:
        from robospec.physics.random_actions import runaways

        return runaways(self.past_limit, self.top_speed, self.top_root_speed, self.settings)

    @property
    def misbehaved(self) -> bool:
        return self.nan_step is not None or bool(self.runaways())

    @property
    def trouble(self) -> str | None:
        """``nan``, ``runaway`` or None: what kind of failure (a twin must share it)."""
        if self.nan_step is not None:
            return "nan"
        return "runaway" if self.runaways() else None

    def trouble_said(self) -> str:
        """The failure in a few words: ``NaN at step 5``, ``joint_12.0 580 rad past its
        limit``."""
        if self.nan_step is not None:
            return f"NaN at step {self.nan_step}"
        found = self.runaways()
        return found[0].brief(self.joints, self.prismatic) if found else "nothing"

    def outcome(self) -> str:
        if self.nan_step is not None:
            return f"state NaN at step {self.nan_step} ({len(self.nan_joints)} joints)"
        found = self.runaways()
        if found:
            return "runs away: " + found[0].brief(self.joints, self.prismatic)
        if not self.joints:
            return "no joints to move"
        fastest = int(np.argmax(self.top_speed))
        unit = "m/s" if self.prismatic[fastest] else "rad/s"
        return f"fastest {self.joints[fastest]} at {self.top_speed[fastest]:.3g} {unit}"


@dataclass(frozen=True)
class Verdict:
    uid: str
    ran: Run
    verdict: str  # OK, AS_MANISKILL or FAILS
    twin: str | None = None  # ManiSkill's agent for the same description
    twin_ran: Run | None = None


def judge(uid: str, ran: Run, twin: str | None, twin_ran: Run | None) -> Verdict:
    """``ran``'s verdict: ok; as ManiSkill where ManiSkill's own agent for the same
    description, run the same way, fails the same way; else a failure of its own."""
    if not ran.misbehaved:
        return Verdict(uid, ran, OK)
    same = twin_ran is not None and twin_ran.trouble == ran.trouble
    return Verdict(uid, ran, AS_MANISKILL if same else FAILS, twin, twin_ran)


def _settings(item: CompiledSpec | None) -> RandomActions:
    """The ``checks.random_actions`` of the robot's spec (its defaults without one)."""
    if item is not None and item.context is not None:
        return item.context.spec.checks.random_actions
    from robospec.model.check_settings import RandomActions

    return RandomActions()


def _run(uid: str, steps: int, settings: RandomActions) -> Run:
    import gymnasium as gym

    from robospec.physics.random_actions import limit_excess
    from robospec.physics.sim import centre_of_mass_speed, has_fixed_root

    # plain gym.make, as a user writes it: the package's import made it work without a
    # rendering device
    env = gym.make(
        "Empty-v1",
        robot_uids=uid,
        obs_mode="state",
        sim_backend="physx_cpu",
        render_backend="none",
    )
    try:
        env.reset(seed=0)
        agent = cast("BaseEnv", env.unwrapped).agent
        robot = agent.robot
        active = robot.get_active_joints()
        joints = tuple(j.name for j in active)
        limits = robot.get_qlimits()[0].cpu().numpy().astype(np.float64)
        lower = limits[:, 0] - settings.joint_limit_tolerance
        upper = limits[:, 1] + settings.joint_limit_tolerance
        free = not has_fixed_root(robot)
        rng = np.random.default_rng(0)
        space = cast("spaces.Box", env.action_space)
        parts = getattr(agent.controller, "controllers", None)
        run = Run(
            len(agent.supported_control_modes),
            agent.control_mode,
            tuple(space.shape),
            joints,
            tuple(j.type[0] == "prismatic" for j in active),
            settings,
            np.zeros(len(joints)),
            np.zeros(len(joints)),
            controllers=list(parts.items()) if parts else [(agent.control_mode, agent.controller)],
        )
        for step in range(steps):
            env.step(rng.uniform(space.low, space.high).astype(np.float32))
            qpos = robot.get_qpos().cpu().numpy().astype(np.float64)
            qvel = robot.get_qvel().cpu().numpy().astype(np.float64)
            bad = ~(np.isfinite(qpos) & np.isfinite(qvel)).all(axis=0)
            if bad.any():
                run.nan_step = step + 1
                run.nan_joints = tuple(n for n, b in zip(joints, bad, strict=True) if b)
                break
            run.past_limit = np.maximum(run.past_limit, limit_excess(qpos, lower, upper))
            run.top_speed = np.maximum(run.top_speed, np.abs(qvel).max(axis=0))
            if free:
                speed = float(centre_of_mass_speed(robot, 1).max())
                run.top_root_speed = max(run.top_root_speed, speed)
        return run
    finally:
        env.close()


def _note(verdict: Verdict, item: CompiledSpec | None, robospec: str) -> str:
    """Why a robot misbehaved: what check counts it for, what ManiSkill's own agent for the
    same description did, and the cause when robospec knows it."""
    from robospec.physics.nan_cause import nan_cause

    ran, uid = verdict.ran, verdict.uid
    parts = []
    if ran.nan_step is None:
        said = "; ".join(r.said(ran.joints, ran.prismatic) for r in ran.runaways())
        parts.append(f"runs away under random actions, which robospec check fails: {said}")
    if verdict.twin is not None and verdict.twin_ran is not None:
        theirs = verdict.twin_ran
        if verdict.verdict == AS_MANISKILL:
            did = "goes NaN too" if theirs.nan_step is not None else "runs away too"
            parts.append(
                f"ManiSkill's own agent '{verdict.twin}', with the same description, {did} "
                f"({theirs.trouble_said()}): {uid} reproduces ManiSkill's behaviour"
            )
        else:
            parts.append(f"ManiSkill's own agent '{verdict.twin}' does not: {theirs.outcome()}")
    if ran.nan_step is not None:
        known = (
            nan_cause(item.context, ran.mode, ran.controllers)
            if item is not None and item.context is not None
            else None
        )
        if known is None:
            parts.append("why: robospec cannot tell; robospec check looks at every mode")
        else:
            parts.append(f"why: {known.brief}")
    where = item.display if item is not None else uid
    parts.append(f"`{robospec} check {where}` says how to mend it")
    return f"{uid}: " + "; ".join(parts)


def _upstream_twin(item: CompiledSpec | None, ours: set[str]) -> str | None:
    """The uid of the ManiSkill agent (not one of ``ours``) that loads the same description
    file as ``item``'s robot, if ManiSkill registers one: the one whose uid ends the robot's
    where there are several."""
    from mani_skill import format_path
    from mani_skill.agents.registration import REGISTERED_AGENTS

    robot = item.robot if item is not None else None
    if robot is None or robot.description.kind != "maniskill_assets":
        return None
    mine = Path(robot.description.absolute).resolve()
    same = []
    for uid, entry in sorted(REGISTERED_AGENTS.items()):
        cls = entry.agent_cls
        path = getattr(cls, "urdf_path", None) or getattr(cls, "mjcf_path", None)
        if uid not in ours and path and Path(format_path(str(path))).resolve() == mine:
            same.append(str(uid))
    # of several agents on one description (the G1's upper body, its right arm), the one the
    # robot is named after (rs_<uid>)
    named = [uid for uid in same if robot.uid.endswith(uid)]
    return max(named, key=len) if named else (same[0] if same else None)


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
