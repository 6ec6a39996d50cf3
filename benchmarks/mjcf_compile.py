"""Compiling an MJCF with MuJoCo and writing it as a URDF (``description: {mjcf: FILE,
loader: mujoco}``, robospec.derive.mujoco_urdf), per model, cold and cached.

Three figures per model, each in fresh processes:

- MuJoCo's compile alone (``compiled_model``: includes written in place, ``MjModel``), then
  compile + URDF + OBJ writing (``compile_urdf``) into a fresh, empty cache folder: what the
  route costs the first time a spec names the file;
- ``robospec.register(spec)`` with a fresh cache (cold: the spec compiled, the MJCF compiled
  and written, the agent module generated) and with the cache a first run filled (cached:
  robospec's cache entry is trusted and nothing is compiled).

Times are taken inside the child, after its imports (MuJoCo's, ManiSkill's), so that the
figures are the route's own and not Python's start-up. Target: the cached registration of each
model under 1 s (the cache's point: a second import pays no compile).
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from measure import PYTHON, ROOT, child_env, run
from section import Section

TITLE = "Compiling an MJCF with MuJoCo (loader: mujoco), cold and cached"
CACHED_TARGET_S = 1.0

sys.path.insert(0, str(ROOT / "tests"))

# key -> (distribution, file inside it, fix_root_link); no distribution: ManiSkill's assets
MODELS: dict[str, tuple[str | None, str, bool]] = {
    "zoo_humanoid": (None, "robots/humanoid/humanoid.xml", False),
    "dmc_rodent": ("dm-control", "dm_control/locomotion/walkers/assets/rodent.xml", False),
    "dmc_jaco_arm": ("dm-control", "dm_control/third_party/kinova/jaco_arm.xml", True),
    "gymr_shadow_hand": (
        "gymnasium-robotics",
        "gymnasium_robotics/envs/assets/hand/reach.xml",
        True,
    ),
}

_SPEC = """\
robospec: 1
uid: {uid}
description: {{mjcf: "{path}", loader: mujoco}}
loader: {{fix_root_link: {fixed}}}
groups: {{all: "*"}}
controllers:
  all: {{type: pd_joint_pos, joints: all, lower: null, upper: null, stiffness: 100,
         damping: 10, normalize_action: false}}
control_modes:
  pd_joint_pos: {{all: all}}
"""

_COMPILE = """\
import json, sys, time
from pathlib import Path
import mujoco
from robospec.derive.document import Source
from robospec.derive.mjcf_files import compiled_model
from robospec.derive.mujoco_urdf import compile_urdf
path = sys.argv[1]
data = Path(path).read_bytes()
started = time.perf_counter()
model = compiled_model(data, path)
compiled_s = time.perf_counter() - started
started = time.perf_counter()
done = compile_urdf(Source(path, path, "mjcf", data))
written_s = time.perf_counter() - started
assert done.text is not None, [str(d) for d in done.diagnostics]
print(json.dumps({"mujoco": compiled_s, "compile_urdf": written_s, "bodies": model.nbody - 1,
                  "links": done.text.count("<link "), "objs": done.text.count(".obj\\"")}))
"""

_REGISTER = """\
import json, sys, time
import mani_skill.envs
import robospec
started = time.perf_counter()
robospec.register(sys.argv[1])
print(json.dumps({"register": time.perf_counter() - started}))
"""


@dataclass(frozen=True)
class _Row:
    key: str
    facts: dict[str, float]
    mujoco: list[float]
    compile_urdf: list[float]
    cold: list[float]
    cached: list[float]


def _model_path(key: str) -> Path:
    from corpus import install_folder

    from robospec.resolve.paths import maniskill_assets_dir

    distribution, inside, _ = MODELS[key]
    if distribution is None:
        assets = maniskill_assets_dir()
        assert assets is not None, "ManiSkill's assets: run scripts/setup"
        return assets / inside
    return install_folder(distribution) / inside


def _spec(key: str, folder: Path) -> Path:
    fixed = MODELS[key][2]
    spec = folder / f"{key}.yaml"
    text = _SPEC.format(
        uid=f"bench_{key}", path=_model_path(key).as_posix(), fixed=str(fixed).lower()
    )
    spec.write_text(text, encoding="utf-8")
    return spec


def _timed(args: list[str], env: dict[str, str]) -> dict[str, float]:
    done = run(args, env)
    assert done.returncode == 0, done.output[-3000:]
    return json.loads(done.output.strip().splitlines()[-1])


def _median(values: list[float]) -> str:
    return f"{statistics.median(values):.3f}"


def _spread(values: list[float]) -> str:
    return f"{min(values):.3f}–{max(values):.3f}"


def measure(repeat: int = 3, only: list[str] | None = None) -> Section:
    from corpus import CorpusMissing

    keys = [key for key in MODELS if only is None or key in only]
    rows: list[_Row] = []
    skipped: list[str] = []
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="robospec-bench-mjcf-") as scratch:
        folder = Path(scratch)
        for key in keys:
            try:
                path = _model_path(key)
            except CorpusMissing:
                skipped.append(key)
                continue
            if not path.is_file():
                skipped.append(key)
                continue
            spec = _spec(key, folder)
            compile_args = [PYTHON, "-c", _COMPILE, str(path)]
            register_args = [PYTHON, "-c", _REGISTER, str(spec)]
            warm = str(folder / f"{key}-warm")
            # the warm-up: bytecode caches, the OS file cache, and the cache the cached runs hit
            _timed(register_args, child_env(ROBOSPEC_CACHE_DIR=warm))
            facts: dict[str, float] = {}
            mujoco, written, cold, cached = [], [], [], []
            for round_ in range(repeat):
                fresh = str(folder / f"{key}-cold-{round_}")
                got = _timed(compile_args, child_env(ROBOSPEC_CACHE_DIR=fresh))
                mujoco.append(got["mujoco"])
                written.append(got["compile_urdf"])
                facts = got
                shutil.rmtree(fresh, ignore_errors=True)
                fresh = str(folder / f"{key}-register-{round_}")
                cold.append(_timed(register_args, child_env(ROBOSPEC_CACHE_DIR=fresh))["register"])
                shutil.rmtree(fresh, ignore_errors=True)
                cached.append(_timed(register_args, child_env(ROBOSPEC_CACHE_DIR=warm))["register"])
            rows.append(_Row(key, facts, mujoco, written, cold, cached))
    load_after = os.getloadavg()[0]
    meets = all(statistics.median(row.cached) < CACHED_TARGET_S for row in rows)
    lines = [
        f"| `{row.key}` | {int(row.facts['bodies'])} | {int(row.facts['links'])} | "
        f"{int(row.facts['objs'])} | {_median(row.mujoco)} | {_median(row.compile_urdf)} "
        f"({_spread(row.compile_urdf)}) | {_median(row.cold)} ({_spread(row.cold)}) | "
        f"{_median(row.cached)} ({_spread(row.cached)}) |"
        for row in rows
    ]
    missing = f"\n\nNot measured (their package is not installed): {', '.join(skipped)}." * bool(
        skipped
    )
    verdict = "met" if meets else "**missed**"
    body = f"""`benchmarks/mjcf_compile.py`: each model's MJCF as `loader: mujoco` compiles it,
median (spread) of {repeat} fresh processes per figure, in seconds, timed inside the child after
its imports. *MuJoCo*: `compiled_model` alone; *compile + write*: `compile_urdf` (MuJoCo's
compile, the URDF, the OBJ files of its meshes) into an empty cache folder; *register cold*:
`robospec.register(spec)` with an empty cache; *cached*: the same with the cache a first run
filled, the spec's cache entry trusted.

| model | bodies | links | OBJs | MuJoCo s | compile + write s | register cold s | cached s |
| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |
{chr(10).join(lines)}

Machine load (1-minute load average) {load_before:.1f} before the run and {load_after:.1f} after,
on {os.cpu_count()} cores shared with other work: the spreads are that load's.{missing}

Target: every model's cached registration under {CACHED_TARGET_S:.0f} s: {verdict}.
"""
    return Section(TITLE, body, meets)


if __name__ == "__main__":
    section = measure(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
    print(section.markdown())
    sys.exit(0 if section.meets_target else 1)
