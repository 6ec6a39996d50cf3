"""Time to sample a robot's collision matrix (robospec.optimize.collision_matrix): the stage of
`robospec optimize` and `robospec new` that finds the link pairs that never collide.

A fresh process per run, as `robospec optimize` pays it: import SAPIEN, load the URDF into a
bare scene, put the robot in N random configurations and count its links' contacts in each.
Target: the Panda's 1,000 samples in under 5 s ("a few seconds"); 10,000 (optimize's default)
and the G1's 10,000 are shown beside it.
"""

from __future__ import annotations

from measure import PYTHON, child_env, sample
from section import Section

from robospec.resolve.paths import maniskill_assets_dir

TITLE = "Sampling a robot's collision matrix"
ROBOTS = {"panda": "robots/panda/panda_v2.urdf", "unitree_g1": "robots/g1_humanoid/g1.urdf"}
# (robot, samples): the target's case first
CASES = (("panda", 1_000), ("panda", 10_000), ("unitree_g1", 10_000))
TARGET = ("panda", 1_000)
TARGET_S = 5.0

_PROGRAM = """\
import sys
from robospec.optimize.collision_matrix import sample_collision_matrix
matrix = sample_collision_matrix(sys.argv[1], samples=int(sys.argv[2]), seed=3)
print(len(matrix.never), len(matrix.sometimes))
"""


def measure(repeat: int = 5, cases: tuple[tuple[str, int], ...] = CASES) -> Section:
    assets = maniskill_assets_dir()
    assert assets is not None, "ManiSkill's assets: run scripts/setup"
    env = child_env()
    rows = []
    meets = True
    for robot, samples in cases:
        args = [PYTHON, "-c", _PROGRAM, str(assets / ROBOTS[robot]), str(samples)]
        done = sample(args, env, repeat)
        assert done.returncode == 0, done.output
        if (robot, samples) == TARGET:
            meets = done.median < TARGET_S
        never, sometimes = done.output.split()[-2:]
        rows.append(
            f"| `{robot}` | {samples:,} | {never} | {sometimes} | {done.median:.2f} | "
            f"{done.spread} |"
        )
    verdict = "met" if meets else "**missed**"
    body = f"""`benchmarks/collision_matrix.py`: `sample_collision_matrix` (seed 3) in a fresh
process, median of {repeat} runs after a warm-up: SAPIEN imported, the URDF loaded into a bare
scene, then one PhysX contact pass per random configuration.

| robot | samples | never pairs | sometimes pairs | median s | spread s |
| --- | ---: | ---: | ---: | ---: | ---: |
{chr(10).join(rows)}

Target: the Panda's {TARGET[1]:,} samples in under {TARGET_S:.0f} s: {verdict}.
"""
    return Section(TITLE, body, meets)


if __name__ == "__main__":
    import sys

    section = measure(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
    print(section.markdown())
    sys.exit(0 if section.meets_target else 1)
