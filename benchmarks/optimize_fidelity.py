"""What `robospec optimize` and its fast profile change in how a robot behaves, measured side by
side in one run against the robot as written.

1. **Link-pose divergence**: each robot (specs/maniskill: the Panda, the Allegro hand, Fetch,
   the Unitree G1) as written, optimized and fast, in ``Empty-v1`` on physx_cpu (the fast one
   with the sim config its spec recommends), under the same uniformly random actions: the
   largest distance between a link's position in the variant and in the original, over every
   link both have and every step, and at the last step. A fixed robot steps without the floor,
   as `robospec check` runs it (mounted where its task puts it, it would not reach through
   it). Free-rooted robots fall under random actions, and where a falling robot lands is
   chaos: their figures say how far two simulations part, not how wrong one is.
2. **check's step responses**: `robospec check SPEC -f json` on each variant of the
   manipulation robots (the Panda, the Allegro hand): each controller's rise time, overshoot,
   settling time and steady-state error, as check measures them (check simulates a spec with
   the sim config it recommends).
3. **Task success**: ManiSkill's motion-planning solutions for the Panda
   (``mani_skill.examples.motionplanning.panda.solutions``: PickCube, StackCube) over a fixed
   set of seeds, the Panda registered as ``panda`` (``override: true``) in each variant in
   turn, physx_cpu, ``pd_joint_pos``. The planner (mplib) plans on the URDF the agent loads
   (the optimized one, with the SRDF written beside it), so this is the whole pipeline a user
   of the optimized robot runs. Target: each variant's success rate within 5 points of the
   original's on each task.

mplib 0.1.1, the planner ManiSkill 3.0.1 pins, is built against numpy 1 and crashes (a
segmentation fault in ``ArticulatedModel``) under numpy 2, which this environment has for
everything else. The motion-planning worker therefore runs with numpy 1.26.4 first on its
path: ``scripts/setup`` installs it into ``.venv/numpy1`` (``pip install --target``), or
``ROBOSPEC_NUMPY1`` names such a folder. Without one the task success part is not measured,
and the report says why.

    python benchmarks/optimize_fidelity.py --divergence --steps N ORIGINAL OPTIMIZED FAST ...
    python benchmarks/optimize_fidelity.py --motion-planning TASK[,TASK...] --seeds N SPEC

are the workers; each prints JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from measure import PYTHON, ROOT, child_env, run
from section import Section

TITLE = "Fidelity: robospec optimize and its fast profile against the robot as written"
SPECS = ROOT / "specs" / "maniskill"
DIVERGENCE_ROBOTS = ("panda", "allegro_hand_right", "fetch", "unitree_g1")
CHECK_ROBOTS = ("panda", "allegro_hand_right")
TASKS = ("PickCube-v1", "StackCube-v1")
VARIANTS = ("original", "optimized", "fast")
SUCCESS_POINTS = 5.0  # the largest difference in success rate allowed, in percentage points
NUMPY1 = "numpy1"  # the folder under the environment's prefix holding numpy 1 for mplib


def measure(
    seeds: int = 50,
    steps: int = 100,
    samples: int = 10_000,
    robots: tuple[str, ...] = DIVERGENCE_ROBOTS,
    check_robots: tuple[str, ...] = CHECK_ROBOTS,
    tasks: tuple[str, ...] = TASKS,
) -> Section:
    with tempfile.TemporaryDirectory(prefix="robospec-bench-fidelity-") as folder:
        work = Path(folder)
        notes: list[str] = []
        variants = {
            name: _variants(SPECS / f"{name}.yaml", work, samples, notes) for name in robots
        }
        variants = {name: paths for name, paths in variants.items() if paths is not None}
        lines = [*_divergence_part(variants, steps, notes)]
        lines += ["", *_check_part({n: variants[n] for n in check_robots if n in variants})]
        success_lines, met = _success_part(work, seeds, samples, tasks, notes)
        lines += ["", *success_lines]
        if notes:
            lines += ["", "Not measured:", "", *notes]
        return Section(TITLE, "\n".join(lines), meets_target=met)


# -- the variants ------------------------------------------------------------------------------


def _variants(spec: Path, work: Path, samples: int, notes: list[str]) -> dict[str, Path] | None:
    """The spec as written, optimized and fast, each with its own uid."""
    uid = _uid_of(spec)
    out = {"original": spec}
    for variant, profile in (("optimized", "default"), ("fast", "fast")):
        target = work / variant / f"{spec.stem}.yaml"
        done = _optimize(spec, target, profile, f"{uid}_{variant}", samples)
        if done.returncode != 0:
            notes.append(f"- `{spec.stem}` ({variant}): optimize failed: {_last(done)}")
            return None
        out[variant] = target
    return out


def _optimize(
    spec: Path, out: Path, profile: str, uid: str, samples: int
) -> subprocess.CompletedProcess[str]:
    command = [PYTHON, "-m", "robospec", "optimize", str(spec), "-o", str(out), "--uid", uid]
    command += ["--profile", profile, "--samples", str(samples), "-f", "json"]
    return subprocess.run(command, capture_output=True, text=True, cwd=ROOT, env=child_env())


def _uid_of(spec: Path) -> str:
    from robospec.pipeline import compile_spec

    compiled = compile_spec(spec)
    return compiled.robot.uid if compiled.robot is not None else spec.stem


# -- 1. link-pose divergence -------------------------------------------------------------------


def _divergence_part(
    variants: dict[str, dict[str, Path]], steps: int, notes: list[str]
) -> list[str]:
    lines = [
        "| robot | variant | links compared | largest link divergence (m) | at the last step (m) "
        "| largest joint divergence (rad or m) |",
        "| --- | --- | ---: | ---: | ---: | ---: |",
    ]
    if not variants:
        return lines
    args = [PYTHON, str(Path(__file__)), "--divergence", "--steps", str(steps)]
    for paths in variants.values():
        args += [str(paths[v]) for v in VARIANTS]
    result = run(args, child_env())
    rows = [json.loads(line) for line in result.output.splitlines() if line.startswith("{")]
    if result.returncode != 0 or len(rows) != len(variants):
        notes.append(f"- divergence: the worker failed: {_tail(result.output)}")
        return lines
    for name, row in zip(variants, rows, strict=True):
        if "reason" in row:
            notes.append(f"- `{name}` divergence: {row['reason']}")
            continue
        for variant in VARIANTS[1:]:
            figures = row[variant]
            lines.append(
                f"| `{name}` | {variant} | {figures['links']} | {figures['largest']:.2g} | "
                f"{figures['last']:.2g} | {figures['joints']:.2g} |"
            )
    lines += [
        "",
        f"Each variant against the robot as written in `Empty-v1` (physx_cpu), {steps} steps of "
        "the same uniformly random actions (seed 0) in the first control mode, the fast "
        "robot with the sim config its spec recommends; a fixed robot without the floor, as "
        "`robospec check` runs it. A link's divergence is the distance between its positions "
        "in the two simulations. Free-rooted robots (the G1) fall, and where they land is "
        "chaos.",
    ]
    return lines


def _divergence_worker(groups: list[tuple[Path, ...]], steps: int) -> None:
    import gymnasium  # noqa: F401  (ManiSkill's environments need it imported first)
    import mani_skill.envs  # noqa: F401
    import numpy as np
    from stepping import failure_reason, random_actions

    import robospec
    from robospec.maniskill.headless import make_empty_env

    cache = tempfile.mkdtemp(prefix="robospec-bench-fidelity-")
    for group in groups:
        try:
            envs = {}
            for variant, spec in zip(VARIANTS, group, strict=True):
                (uid,) = robospec.register(str(spec), cache_dir=cache)
                envs[variant] = make_empty_env(uid, sim_config=robospec.sim_config_for(uid))
        except Exception as exc:  # a robot that cannot load here is listed, not fatal
            print(json.dumps({"reason": failure_reason(exc)}), flush=True)
            continue
        actions = random_actions(envs["original"].action_space, steps)
        traces = {variant: _trace(env, actions) for variant, env in envs.items()}
        base_links, base_joints = traces["original"]
        row: dict[str, Any] = {}
        for variant in VARIANTS[1:]:
            links, joints = traces[variant]
            shared = sorted(set(links) & set(base_links))
            gaps = np.stack(
                [np.linalg.norm(links[n] - base_links[n], axis=-1) for n in shared], axis=1
            )
            joint_gap = np.abs(joints - base_joints)
            row[variant] = {
                "links": len(shared),
                "largest": float(np.nanmax(gaps)),
                "last": float(np.nanmax(gaps[-1])),
                "joints": float(np.nanmax(joint_gap)),
            }
        print(json.dumps(row), flush=True)
        for env in envs.values():
            env.close()


def _trace(env: Any, actions: Any) -> tuple[dict[str, Any], Any]:
    """Each link's position and the joint positions after every step (the joints: those the
    original robot has, in its order; every variant keeps them)."""
    import numpy as np

    env.reset(seed=0)
    robot = env.unwrapped.agent.robot
    if robot._objs[0].root.joint.type == "fixed":
        # as robospec check does: a fixed robot is mounted where its task puts it, and at the
        # origin of Empty-v1 its fingers would reach through the floor (the Allegro hand's
        # joints then leave their limits, past 1,000 rad in 100 steps, as written or not)
        env.unwrapped.ground.remove_from_scene()
    links: dict[str, list[Any]] = {link.name: [] for link in robot.links}
    joints = []
    for action in actions:
        env.step(action)
        for link in robot.links:
            links[link.name].append(link.pose.p[0].cpu().numpy().astype(np.float64))
        joints.append(robot.get_qpos()[0].cpu().numpy().astype(np.float64))
    return {name: np.stack(p) for name, p in links.items()}, np.stack(joints)


# -- 2. check's step responses -----------------------------------------------------------------

_FIGURES = ("rise_time", "overshoot", "settling_time", "steady_state_error")


def _check_part(variants: dict[str, dict[str, Path]]) -> list[str]:
    lines = [
        "| robot | controller | as written | optimized | fast |",
        "| --- | --- | --- | --- | --- |",
    ]
    # one `robospec check` for every spec: its worker imports ManiSkill once for them all
    every = _step_responses([paths[v] for paths in variants.values() for v in VARIANTS])
    for name, paths in variants.items():
        figures = {variant: every.get(str(paths[variant]), {}) for variant in VARIANTS}
        for controller in figures["original"]:
            cells = [_figures(figures[v].get(controller)) for v in VARIANTS]
            lines.append(f"| `{name}` | `{controller}` | " + " | ".join(cells) + " |")
    lines += [
        "",
        "`robospec check`'s step response of each position and velocity controller "
        "(`checks.step_response`: a small step of the drive targets from the first keyframe), "
        "the slowest joint's: rise time, overshoot, settling time, steady-state error. Check "
        "runs each variant with the sim config its spec recommends.",
    ]
    return lines


def _step_responses(specs: list[Path]) -> dict[str, dict[str, dict[str, float]]]:
    """Each spec's step responses (by the spec's path as given): controller -> figures."""
    if not specs:
        return {}
    done = subprocess.run(
        [PYTHON, "-m", "robospec", "check", *map(str, specs), "-f", "json"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=child_env(),
    )
    try:
        report = json.loads(done.stdout)
    except json.JSONDecodeError:
        return {}
    out: dict[str, dict[str, dict[str, float]]] = {}
    for robot in report.get("robots", []):
        figures = out.setdefault(str(robot.get("spec")), {})
        for finding in robot.get("findings", []):
            if finding.get("check") == "step_response" and finding.get("metrics"):
                # "arm (arm_pos)": the controller; a controller in several modes is one row
                subject = str(finding.get("subject"))
                controller = subject.partition("(")[2].rstrip(")") or subject
                figures.setdefault(controller, {k: finding["metrics"].get(k) for k in _FIGURES})
    return out


def _figures(values: dict[str, float] | None) -> str:
    if not values or any(values.get(k) is None for k in _FIGURES):
        return "—"
    return (
        f"{values['rise_time']:.2f} s, {values['overshoot']:.1%}, "
        f"{values['settling_time']:.2f} s, {values['steady_state_error']:.2g}"
    )


# -- 3. task success ---------------------------------------------------------------------------


def numpy1_path() -> str | None:
    """The folder to put first on the motion-planning worker's path so that mplib 0.1.1 gets
    numpy 1: "" when this environment's numpy is 1 already, None when none is found."""
    import numpy

    if int(numpy.__version__.split(".")[0]) < 2:
        return ""
    given = os.environ.get("ROBOSPEC_NUMPY1")
    for folder in (Path(given) if given else None, Path(sys.prefix) / NUMPY1):
        if folder is not None and (folder / "numpy" / "__init__.py").is_file():
            return str(folder)
    return None


def _success_part(
    work: Path, seeds: int, samples: int, tasks: tuple[str, ...], notes: list[str]
) -> tuple[list[str], bool]:
    lines = [
        "| task | seeds | as written | optimized | fast | same outcome as written "
        "(optimized, fast) |",
        "| --- | ---: | ---: | ---: | ---: | --- |",
    ]
    overlay = numpy1_path()
    if overlay is None:
        notes.append(
            "- task success: mplib 0.1.1 (ManiSkill's motion planner) crashes under numpy 2 "
            "and no numpy 1 was found for it: run `scripts/setup` (it installs numpy 1.26.4 "
            "into .venv/numpy1) or set ROBOSPEC_NUMPY1 to a folder holding numpy 1"
        )
        return lines, False
    specs = _panda_variants(work, samples, notes)
    if specs is None:
        return lines, False
    met = True
    planned = {}
    for variant in VARIANTS:  # a process each: each registers its Panda as `panda`
        found = _plan(tasks, seeds, specs[variant], overlay, notes)
        if found is None:
            return lines, False
        planned[variant] = found
    for task in tasks:
        outcomes = {variant: planned[variant][task] for variant in VARIANTS}
        rates = {v: 100.0 * sum(o) / len(o) for v, o in outcomes.items()}
        same = [
            sum(a == b for a, b in zip(outcomes[v], outcomes["original"], strict=True))
            for v in VARIANTS[1:]
        ]
        met = met and all(abs(rates[v] - rates["original"]) <= SUCCESS_POINTS for v in VARIANTS[1:])
        lines.append(
            f"| {task} | {seeds} | {rates['original']:.0f} % | {rates['optimized']:.0f} % | "
            f"{rates['fast']:.0f} % | {same[0]}, {same[1]} of {seeds} |"
        )
    lines += [
        "",
        "ManiSkill's motion-planning solutions for the Panda "
        f"({', '.join(t.removesuffix('-v1') for t in tasks)}), seeds 0 "
        f"to {seeds - 1}, the Panda registered as `panda` in each variant in turn (physx_cpu, "
        "`pd_joint_pos`, the sim config its spec recommends). Target: each variant within "
        f"{SUCCESS_POINTS:g} points of the robot as written, on each task: "
        + ("**met**." if met else "**missed**."),
    ]
    return lines, met


def _panda_variants(work: Path, samples: int, notes: list[str]) -> dict[str, Path] | None:
    """The Panda's spec as ManiSkill's tasks and their solutions need it, as written, optimized
    and fast: uid ``panda``, replacing ManiSkill's own agent (the tasks place and reset a robot
    by its uid), and extending ManiSkill's Panda class for the one helper no spec declares
    (``build_grasp_pose``, which the solutions call); everything else is the spec's."""
    text = (SPECS / "panda.yaml").read_text(encoding="utf-8")
    text = re.sub(
        r"(?m)^uid: .*$",
        "uid: panda\noverride: true\nextends: mani_skill.agents.robots.panda.panda:Panda",
        text,
        count=1,
    )
    original = work / "planning" / "panda.yaml"
    original.parent.mkdir(parents=True, exist_ok=True)
    original.write_text(text, encoding="utf-8")
    specs = {"original": original}
    for variant, profile in (("optimized", "default"), ("fast", "fast")):
        out = work / "planning" / variant / "panda.yaml"
        done = _optimize(original, out, profile, "panda", samples)
        if done.returncode != 0:
            notes.append(f"- task success ({variant}): optimize failed: {_last(done)}")
            return None
        specs[variant] = out
    return specs


def _plan(
    tasks: tuple[str, ...], seeds: int, spec: Path, overlay: str, notes: list[str]
) -> dict[str, list[bool]] | None:
    """Each task's outcome per seed, with ``spec``'s Panda."""
    env = child_env()
    if overlay:
        env["PYTHONPATH"] = os.pathsep.join(
            [overlay, *filter(None, [env.get("PYTHONPATH", "")]), str(ROOT)]
        )
    args = [PYTHON, str(Path(__file__)), "--motion-planning", ",".join(tasks)]
    result = run([*args, "--seeds", str(seeds), str(spec)], env)
    rows = [json.loads(line) for line in result.output.splitlines() if line.startswith("{")]
    found = {row["task"]: [bool(s) for s in row["success"]] for row in rows}
    if result.returncode != 0 or set(found) != set(tasks):
        notes.append(f"- task success ({spec.parent.name}): {_tail(result.output)}")
        return None
    return found


def _motion_planning_worker(tasks: list[str], seeds: int, spec: Path) -> None:
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401
    from mani_skill.examples.motionplanning.panda.solutions import solvePickCube, solveStackCube

    import robospec
    from robospec.maniskill.headless import headless_loading

    solutions = {"PickCube-v1": solvePickCube, "StackCube-v1": solveStackCube}
    (uid,) = robospec.register(str(spec), cache_dir=tempfile.mkdtemp())
    for task in tasks:
        with headless_loading():
            env = gym.make(
                task,
                robot_uids=uid,
                obs_mode="none",
                control_mode="pd_joint_pos",
                render_mode=None,
                sim_backend="physx_cpu",
                render_backend="none",
                sim_config=robospec.sim_config_for(uid),
            )
        success = []
        for seed in range(seeds):
            result = solutions[task](env, seed=seed, debug=False, vis=False)
            # -1: the planner found no plan, which is the robot's failure too
            success.append(bool(result != -1 and result[-1]["success"].item()))
        env.close()
        print(json.dumps({"task": task, "spec": str(spec), "success": success}), flush=True)


# -- helpers -----------------------------------------------------------------------------------


def _last(done: subprocess.CompletedProcess[str]) -> str:
    text = (done.stdout + done.stderr).strip().splitlines()
    errors = [line for line in text if "error[" in line]
    return (errors or text or ["(no output)"])[0][:200]


def _tail(output: str) -> str:
    lines = [line for line in output.strip().splitlines() if line.strip()]
    return (lines[-1] if lines else "(no output)")[:200]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--divergence", action="store_true")
    parser.add_argument("--motion-planning", metavar="TASKS")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("specs", nargs="*", type=Path)
    args = parser.parse_args()
    if args.divergence:
        size = len(VARIANTS)
        groups = [tuple(args.specs[i : i + size]) for i in range(0, len(args.specs), size)]
        _divergence_worker(groups, args.steps)
    elif args.motion_planning:
        (spec,) = args.specs
        _motion_planning_worker(args.motion_planning.split(","), args.seeds, spec)
    else:
        print(measure(args.seeds, args.steps).markdown())


if __name__ == "__main__":
    main()
