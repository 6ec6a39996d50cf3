"""The main job, end to end: build the example specs into a package, import it (which registers
the agents), and run each generated robot in a headless ManiSkill environment.

    python -m robospec.maniskill.demo [SPECS...] [-o OUT] [--steps N]
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path


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
    print(
        f"built {args.out}/ in {time.perf_counter() - started:.2f} s: "
        + ", ".join(sorted(n for n in result.files if n.endswith(".py")))
    )

    import mani_skill.envs  # noqa: F401  (registers the environments)
    import numpy as np

    from robospec.maniskill.headless import make_empty_env

    sys.path.insert(0, str(args.out.resolve().parent))
    package = importlib.import_module(args.out.name)
    for uid, cls in package.AGENTS.items():
        env = make_empty_env(uid)
        env.reset(seed=0)
        agent = env.unwrapped.agent
        rng = np.random.default_rng(0)
        space = env.action_space
        for _ in range(args.steps):
            env.step(rng.uniform(space.low, space.high).astype(np.float32))
        qpos = agent.robot.get_qpos()[0].numpy()
        print(
            f"{uid} ({cls.__module__}.{cls.__name__}): {len(agent.supported_control_modes)} "
            f"control modes, default {agent.control_mode}, action shape {space.shape}; "
            f"{args.steps} random steps on physx_cpu -> qpos {[round(float(q), 3) for q in qpos]}, "
            f"finite={bool(np.isfinite(qpos).all())}"
        )
        env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
