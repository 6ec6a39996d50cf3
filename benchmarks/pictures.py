"""Time to draw a robot card's pictures: `robospec doc SPEC -o CARD --images`.

A fresh process per run, as a user starts it, on a machine without a GPU (MuJoCo's renderer
through Mesa's EGL, llvmpipe): compile the spec, place the robot at each keyframe, draw it from
the three standard views and each camera's view alone and at the table, draw the cameras'
segmentation pictures and judge them, write the PNGs and the card. Robospec's mesh cache is
warm (the unmeasured warm-up run fills it, as any first run does); the first run on a machine
also reads and simplifies every mesh, which the table shows apart. Target: under 5 s per robot.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from measure import PYTHON, ROOT, child_env, run, sample
from section import Section

TITLE = "Drawing a robot card's pictures without a GPU"
SPECS = {
    "panda": ROOT / "specs" / "maniskill" / "panda.yaml",
    "panda_wristcam": ROOT / "specs" / "maniskill" / "panda_wristcam.yaml",
    "unitree_g1 (head camera)": ROOT
    / "specs"
    / "maniskill"
    / "unitree_g1_simplified_upper_body_with_head_camera.yaml",
}
TARGET_S = 5.0


def measure(repeat: int = 5, only: list[str] | None = None) -> Section:
    rows = []
    meets = True
    with tempfile.TemporaryDirectory(prefix="robospec-bench-pictures-") as work:
        for name, spec in SPECS.items():
            if only and name not in only:
                continue
            cache = Path(work) / f"cache-{len(rows)}"
            env = child_env(ROBOSPEC_CACHE_DIR=str(cache))
            card = Path(work) / f"card-{len(rows)}.md"
            args = [PYTHON, "-m", "robospec", "doc", str(spec), "-o", str(card), "--images"]
            cold = run(args, env)  # an empty cache: every mesh read and simplified
            assert cold.returncode == 0, cold.output
            warm = sample(args, env, repeat, warm_up=False)
            assert warm.returncode == 0, warm.output
            pictures = len(list(card.parent.glob(f"{card.stem}_images/*/*.png")))
            ok = warm.median < TARGET_S
            meets = meets and ok
            rows.append(
                f"| {name} | {pictures} | {warm.median:.2f} | {warm.spread} | "
                f"{cold.seconds:.2f} | {warm.peak_rss_kib / 1024:.0f} |"
            )
    verdict = "met" if meets else "**missed**"
    body = f"""`benchmarks/pictures.py`: `robospec doc SPEC -o CARD --images` in a fresh process
(median of {repeat} runs with robospec's mesh cache warm; the first run, with an empty cache,
apart), on this machine's CPU: MuJoCo's renderer through Mesa's EGL (llvmpipe), no GPU. It
compiles the spec, draws the robot from three views at each keyframe and each camera's view
alone and at a table (320x240 and the camera's own size), judges the cameras from
segmentation pictures, and writes the PNGs and the card.

| robot | pictures | median s | spread s | first run (empty cache) s | peak MiB |
| --- | ---: | ---: | ---: | ---: | ---: |
{chr(10).join(rows)}

Target: under {TARGET_S:.0f} s per robot with the cache warm: {verdict}.
"""
    return Section(TITLE, body, meets)


if __name__ == "__main__":
    import sys

    section = measure(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
    print(section.markdown())
    sys.exit(0 if section.meets_target else 1)
