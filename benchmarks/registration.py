"""Import-time registration of every example spec, cold cache and warm cache, against
`import mani_skill.envs` alone."""

from __future__ import annotations

import tempfile

from measure import PYTHON, child_env, sample
from section import Section

TITLE = "Import-time registration of every example spec"
TARGET_WARM_OVERHEAD = 0.10
REGISTER = "import mani_skill.envs, robospec; robospec.register('specs/')"


def measure(repeat: int) -> Section:
    baseline = sample([PYTHON, "-c", "import mani_skill.envs"], child_env(), repeat)
    # cold: every run gets a fresh, empty cache folder, so every spec compiles
    cold_times = []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory(prefix="robospec-bench-cold-") as cache:
            cold = sample([PYTHON, "-c", REGISTER], child_env(ROBOSPEC_CACHE_DIR=cache), 1, False)
            _check(cold.returncode, cold.output)
            cold_times.append(cold.median)
    with tempfile.TemporaryDirectory(prefix="robospec-bench-warm-") as cache:
        # the warm-up run fills the cache; the measured runs hit it
        warm = sample([PYTHON, "-c", REGISTER], child_env(ROBOSPEC_CACHE_DIR=cache), repeat)
        _check(warm.returncode, warm.output)
    cold_median = sorted(cold_times)[len(cold_times) // 2]
    cold_spread = f"{min(cold_times):.2f}–{max(cold_times):.2f}"
    base = baseline.median
    cold_overhead = (cold_median - base) / base
    warm_overhead = (warm.median - base) / base
    register = "+ `robospec.register('specs/')`"
    body = f"""
| what | median s | spread s | over `import mani_skill.envs` |
| --- | ---: | ---: | ---: |
| `import mani_skill.envs` | {base:.2f} | {baseline.spread} | — |
| {register}, cold cache | {cold_median:.2f} | {cold_spread} | {cold_overhead * 100:+.0f}% |
| {register}, warm cache | {warm.median:.2f} | {warm.spread} | {warm_overhead * 100:+.0f}% |

Cold: `ROBOSPEC_CACHE_DIR` is a fresh empty folder in every run, so every spec under `specs/` is
compiled (loaded, validated against its URDF/MJCF, emitted). Warm: the cache holds every spec
(the first run after a change pays the cold price once). Registering from a warm cache adds
**{warm_overhead * 100:.1f}%** (target: < {TARGET_WARM_OVERHEAD * 100:.0f}%).
"""
    return Section(TITLE, body, warm_overhead < TARGET_WARM_OVERHEAD)


def _check(returncode: int, output: str) -> None:
    if returncode != 0:
        raise RuntimeError(f"robospec.register('specs/') failed:\n{output[-2000:]}")
