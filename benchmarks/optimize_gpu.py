"""`env.step` throughput and GPU memory on physx_cuda: robots as written, optimized by `robospec
optimize` and by its fast profile, at 1,024 and 4,096 parallel environments.

On the GPU, PhysX preallocates its contact and patch buffers (ManiSkill's ``GPUMemoryConfig``)
and every pair of shapes within the sum of their contact offsets fills them: fewer contacts is
what the fast profile's offsets and primitive shapes save there, in time and in how much of
those buffers a scene needs. Each (robot, variant, number of environments) runs in a process of
its own (PhysX sets up one GPU system per process), in ``Empty-v1`` with state observations, no
renderer, the sim config the spec recommends (``robospec.sim_config_for``) over ManiSkill's
defaults, uniformly random actions: steps per second (environment steps: ``env.step`` calls
times environments), the process's GPU memory (NVML, after the steps) and whether PhysX said
a buffer overflowed (it prints "... buffer overflow detected": contacts were then dropped).

One command, under ten minutes on one GPU with the default robots:

    .venv/bin/python benchmarks/run.py --only optimize_gpu

On a machine without a CUDA device (``torch.cuda.is_available()`` false) the section says so
and measures nothing; it is not a missed target. Target (when measured): at 4,096
environments, the fast profile steps at least as fast as the robot as written.

    python benchmarks/optimize_gpu.py --worker --envs N --steps S SPEC

is the worker; it prints one JSON object.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from measure import PYTHON, ROOT, child_env, run
from section import Section

TITLE = "GPU: robospec optimize and its fast profile on physx_cuda"
SPECS = ROOT / "specs" / "maniskill"
ROBOTS = ("unitree_g1", "allegro_hand_right")
ENVS = (1024, 4096)
VARIANTS = ("original", "optimized", "fast")
WORKER_TIMEOUT = 240  # s: one robot, one variant, one size, build and steps
OVERFLOW = "overflow detected"  # PhysX: "Contact buffer overflow detected", "Patch buffer ..."


def cuda_device() -> str | None:
    """The CUDA device's name, or None where there is none (or torch cannot see it)."""
    try:
        import torch
    except ImportError:
        return None
    if not torch.cuda.is_available():
        return None
    return str(torch.cuda.get_device_name(0))


def measure(
    envs: tuple[int, ...] = ENVS,
    steps: int = 100,
    samples: int = 10_000,
    robots: tuple[str, ...] = ROBOTS,
) -> Section:
    device = cuda_device()
    if device is None:
        return Section(
            TITLE,
            "Not measured: this machine has no CUDA device (`torch.cuda.is_available()` is "
            "false). On a machine with one, `.venv/bin/python benchmarks/run.py --only "
            f"optimize_gpu` steps {', '.join(robots)} as written, optimized and fast at "
            f"{' and '.join(f'{n:,}' for n in envs)} environments on physx_cuda.",
        )
    with tempfile.TemporaryDirectory(prefix="robospec-bench-gpu-") as folder:
        work = Path(folder)
        notes: list[str] = []
        lines = [
            "| robot | environments | variant | env steps/s | × as written | GPU memory (MiB) "
            "| buffer overflow |",
            "| --- | ---: | --- | ---: | ---: | ---: | --- |",
        ]
        met = True
        for robot in robots:
            variants = _variants(SPECS / f"{robot}.yaml", work, samples, notes)
            if variants is None:
                met = False
                continue
            for count in envs:
                rows = {v: _step(variants[v], count, steps, notes, robot) for v in VARIANTS}
                base = rows["original"]
                for variant in VARIANTS:
                    row = rows[variant]
                    if row is None:
                        continue
                    ratio = row["rate"] / base["rate"] if base else float("nan")
                    lines.append(
                        f"| `{robot}` | {count:,} | {variant} | {row['rate']:,.0f} | "
                        f"{ratio:.2f} | {_mib(row.get('memory'))} | "
                        f"{'yes' if row['overflow'] else 'no'} |"
                    )
                fast = rows["fast"]
                if count == max(envs) and (
                    base is None or fast is None or fast["rate"] < base["rate"]
                ):
                    met = False
        lines += [
            "",
            f"On {device}: each robot, variant and number of environments in a process of its "
            f"own, `Empty-v1` on physx_cuda with ManiSkill's default GPU buffers and the sim "
            f"config the spec recommends, {steps} steps of uniformly random actions after a "
            "warm-up. *Env steps/s*: `env.step` calls per second times environments. *GPU "
            "memory*: the process's, from NVML, after the steps. *Buffer overflow*: PhysX "
            "reported its contact or patch buffer full (contacts were dropped; a larger "
            "`gpu_memory_config` is needed). Target: at "
            f"{max(envs):,} environments the fast profile at least as fast as the robot as "
            "written: " + ("**met**." if met else "**missed**."),
        ]
        if notes:
            lines += ["", "Not measured:", "", *notes]
        return Section(TITLE, "\n".join(lines), meets_target=met)


def _variants(spec: Path, work: Path, samples: int, notes: list[str]) -> dict[str, Path] | None:
    out = {"original": spec}
    for variant, profile in (("optimized", "default"), ("fast", "fast")):
        target = work / variant / f"{spec.stem}.yaml"
        command = [PYTHON, "-m", "robospec", "optimize", str(spec), "-o", str(target)]
        command += [
            "--profile",
            profile,
            "--samples",
            str(samples),
            "--uid",
            f"{spec.stem}_{variant}",
        ]
        done = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, env=child_env())
        if done.returncode != 0:
            notes.append(
                f"- `{spec.stem}` ({variant}): optimize failed: {_tail(done.stdout + done.stderr)}"
            )
            return None
        out[variant] = target
    return out


def _step(
    spec: Path, count: int, steps: int, notes: list[str], robot: str
) -> dict[str, Any] | None:
    args = [PYTHON, str(Path(__file__)), "--worker", "--envs", str(count), "--steps", str(steps)]
    try:
        result = run(["timeout", str(WORKER_TIMEOUT), *args, str(spec)], child_env())
    except OSError as exc:
        notes.append(f"- `{robot}` at {count:,}: {exc}")
        return None
    rows = [json.loads(line) for line in result.output.splitlines() if line.startswith("{")]
    if result.returncode != 0 or not rows:
        why = "timed out" if result.returncode == 124 else _tail(result.output)
        notes.append(f"- `{robot}` ({spec.parent.name}) at {count:,} environments: {why}")
        return None
    row = rows[-1]
    row["overflow"] = OVERFLOW in result.output.lower()
    return row


def _worker(spec: Path, count: int, steps: int) -> None:
    import gymnasium  # noqa: F401  (ManiSkill's environments need it imported first)
    import mani_skill.envs  # noqa: F401
    import torch

    import robospec
    from robospec.maniskill.headless import make_empty_env

    (uid,) = robospec.register(str(spec), cache_dir=tempfile.mkdtemp())
    torch.cuda.init()
    before = _device_memory()
    env = make_empty_env(
        uid,
        num_envs=count,
        sim_backend="physx_cuda",
        sim_config=robospec.sim_config_for(uid),
    )
    space = env.unwrapped.single_action_space
    low = torch.as_tensor(space.low, device="cuda").clamp(min=-torch.pi)
    high = torch.as_tensor(space.high, device="cuda").clamp(max=torch.pi)
    generator = torch.Generator(device="cuda").manual_seed(0)

    def action() -> torch.Tensor:
        noise = torch.rand((count, *low.shape), device="cuda", generator=generator)
        return low + noise * (high - low)

    env.reset(seed=0)
    for _ in range(5):  # warm-up: GPU kernels compiled and buffers touched
        env.step(action())
    torch.cuda.synchronize()
    started = time.perf_counter()
    for _ in range(steps):
        env.step(action())
    torch.cuda.synchronize()
    seconds = time.perf_counter() - started
    memory = _gpu_memory()
    if memory is None and before is not None and (after := _device_memory()) is not None:
        memory = after - before  # the device's, grown by this process: alone on it, the same
    print(json.dumps({"rate": count * steps / seconds, "memory": memory}), flush=True)
    env.close()


def _nvml_device() -> Any:
    """NVML's handle of the device torch calls cuda:0, or None (no NVML, or the device is
    named by UUID in CUDA_VISIBLE_DEVICES)."""
    try:
        import pynvml

        pynvml.nvmlInit()
        first = os.environ.get("CUDA_VISIBLE_DEVICES", "0").split(",")[0] or "0"
        return pynvml.nvmlDeviceGetHandleByIndex(int(first))
    except Exception:
        return None


def _gpu_memory() -> int | None:
    """This process's GPU memory in bytes, from NVML (PhysX's buffers are not torch's, so
    torch's own counters miss them); None where NVML does not list the process (another pid
    namespace, as in many containers)."""
    handle = _nvml_device()
    if handle is None:
        return None
    import pynvml

    try:
        for process in pynvml.nvmlDeviceGetComputeRunningProcesses(handle):
            if process.pid == os.getpid() and process.usedGpuMemory is not None:
                return int(process.usedGpuMemory)
    except pynvml.NVMLError:
        return None
    return None


def _device_memory() -> int | None:
    """The device's used memory in bytes (NVML), or None."""
    handle = _nvml_device()
    if handle is None:
        return None
    import pynvml

    try:
        return int(pynvml.nvmlDeviceGetMemoryInfo(handle).used)
    except pynvml.NVMLError:
        return None


def _mib(value: int | None) -> str:
    return "—" if value is None else f"{value / 2**20:,.0f}"


def _tail(output: str) -> str:
    lines = [line for line in output.strip().splitlines() if line.strip()]
    return (lines[-1] if lines else "(no output)")[:200]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--worker", action="store_true")
    parser.add_argument("--envs", type=int, default=1024)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("specs", nargs="*", type=Path)
    args = parser.parse_args()
    if args.worker:
        (spec,) = args.specs
        _worker(spec, args.envs, args.steps)
    else:
        print(measure(steps=args.steps).markdown())
        sys.exit(0)


if __name__ == "__main__":
    main()
