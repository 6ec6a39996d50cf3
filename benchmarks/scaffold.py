"""How long ``robospec new`` takes per robot: with the simulated refinement (the rest pose
searched and the gains measured and tuned in ManiSkill: the default) and with the analytic gains
alone (``--no-sim``), on the corpus of robots nobody here wrote (tests/corpus.py) that ``new``
scaffolds. Targets: an arm in under 30 s with the refinement, and the analytic gains alone in
under 2 s.

Each figure is a fresh ``robospec new`` process, as a user runs it; the refinement is measured
once per robot (it loads ManiSkill: tens of seconds), ``--no-sim`` ``repeat`` times.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from measure import PYTHON, ROOT, child_env, run
from section import Section

TITLE = "Scaffolding a robot: robospec new with and without the simulated refinement"
ARM_TARGET = 30.0  # s, an arm with the refinement
ANALYTIC_TARGET = 2.0  # s, the analytic gains alone

sys.path.insert(0, str(ROOT / "tests"))


@dataclass(frozen=True)
class Timed:
    key: str
    category: str
    refined: float | None  # s; None: not measured
    analytic: float
    ok: bool


def measure(repeat: int = 3, only: list[str] | None = None, refine: bool = True) -> Section:
    """``only``: corpus keys (default: every robot ``new`` scaffolds); ``refine``: also time the
    default (simulated) run."""
    from corpus import CORPUS, CorpusMissing, locate

    robots = [r for r in CORPUS if only is None or r.key in only]
    rows: list[Timed] = []
    with tempfile.TemporaryDirectory(prefix="robospec-bench-new-") as folder:
        env = child_env(ROBOSPEC_CACHE_DIR=str(Path(folder) / "cache"))
        for robot in robots:
            try:
                path = locate(robot)
            except CorpusMissing:
                continue
            out = Path(folder) / f"{robot.key}.yaml"
            args = [PYTHON, "-m", "robospec.cli", "new", str(path), "-o", str(out), "--force"]
            first = run([*args, "--no-sim"], env)  # warms the caches, and tells who loads
            if first.returncode != 0:
                continue  # the description stops new (docs/robots.md says why)
            analytic = statistics.median(
                run([*args, "--no-sim"], env).seconds for _ in range(repeat)
            )
            refined = run(args, env) if refine else None
            rows.append(
                Timed(
                    robot.key,
                    robot.category,
                    refined.seconds if refined is not None else None,
                    analytic,
                    refined is None or refined.returncode == 0,
                )
            )
    return _section(rows, repeat)


def _section(rows: list[Timed], repeat: int) -> Section:
    lines = [
        f"`robospec new` on the {len(rows)} corpus robot(s) it scaffolds: wall time of a fresh "
        f"process, the analytic gains alone (`--no-sim`, median of {repeat}) and with the "
        "simulated refinement (the default: the rest pose searched in ManiSkill, then the gains "
        "measured and tuned there; one run). Targets: an arm with the refinement under "
        f"{ARM_TARGET:g} s, the analytic gains alone under {ANALYTIC_TARGET:g} s.",
        "",
        "| robot | category | --no-sim s | default s |",
        "| --- | --- | ---: | ---: |",
    ]
    for row in rows:
        refined = f"{row.refined:.1f}" if row.refined is not None else "—"
        lines.append(f"| {row.key} | {row.category} | {row.analytic:.2f} | {refined} |")
    arms = [r.refined for r in rows if r.category == "arm" and r.refined is not None]
    analytic = [r.analytic for r in rows]
    refined_all = [r.refined for r in rows if r.refined is not None]
    lines.append("")
    if analytic:
        lines.append(f"Median, `--no-sim`: {statistics.median(analytic):.2f} s.")
    if refined_all:
        lines.append(f"Median with the refinement: {statistics.median(refined_all):.1f} s.")
    if arms:
        lines.append(f"Median for an arm with the refinement: {statistics.median(arms):.1f} s.")
    meets = (
        bool(analytic)
        and statistics.median(analytic) < ANALYTIC_TARGET
        and (not arms or statistics.median(arms) < ARM_TARGET)
        and all(r.ok for r in rows)
    )
    return Section(TITLE, "\n".join(lines) + "\n", meets)
