"""``python -m robospec.solve.replay SPEC [replay_trajectory's arguments]``: ManiSkill's
``mani_skill.trajectory.replay_trajectory`` with the spec's robot registered and loadable
headless, as ``robospec solve`` recorded it (ManiSkill's own command line knows only
ManiSkill's robots)."""

from __future__ import annotations

import sys
from collections.abc import Sequence


def main(argv: Sequence[str]) -> None:
    from robospec.maniskill.headless import headless_loading
    from robospec.output.register import register

    spec, *arguments = argv
    register(spec)
    from mani_skill.trajectory import replay_trajectory

    with headless_loading():
        replay_trajectory.main(replay_trajectory.parse_args(list(arguments)))


if __name__ == "__main__":
    main(sys.argv[1:])
