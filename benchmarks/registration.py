"""Import-time registration of every example spec, cold cache and warm cache, against
`import mani_skill.envs` alone."""

from __future__ import annotations

import shutil
import tempfile

from measure import PYTHON, child_env, interleaved
from section import Section

TITLE = "Import-time registration of every example spec"
TARGET_WARM_OVERHEAD = 0.10
REGISTER = "import mani_skill.envs, robospec; robospec.register('specs/')"


def measure(repeat: int) -> Section:
    cold_caches: list[str] = []

    def cold() -> tuple[list[str], dict[str, str]]:
        # a fresh, empty cache folder in every run, so that every spec compiles
        cold_caches.append(tempfile.mkdtemp(prefix="robospec-bench-cold-"))
        return [PYTHON, "-c", REGISTER], child_env(ROBOSPEC_CACHE_DIR=cold_caches[-1])

    warm_cache = tempfile.mkdtemp(prefix="robospec-bench-warm-")
    try:
        # the warm-up round fills the warm cache; the measured rounds hit it
        samples = interleaved(
            {
                "baseline": lambda: ([PYTHON, "-c", "import mani_skill.envs"], child_env()),
                "cold": cold,
                "warm": lambda: (
                    [PYTHON, "-c", REGISTER],
                    child_env(ROBOSPEC_CACHE_DIR=warm_cache),
                ),
            },
            repeat,
        )
    finally:
        for folder in [warm_cache, *cold_caches]:
            shutil.rmtree(folder, ignore_errors=True)
    for sample in samples.values():
        _check(sample.returncode, sample.output)
    baseline, cold_run, warm = samples["baseline"], samples["cold"], samples["warm"]
    base = baseline.median
    cold_median, cold_spread = cold_run.median, cold_run.spread
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
