"""A description's own keyframes as ``robospec new`` copies them: inside the joints' limits.

A file's keyframe may put a joint a hair past its own range (an MJCF ``<key>`` whose knee sits at
-2.794 against a lower limit of -2.775), which ``validate`` rejects (RS304) — and ``new`` never
writes what ``validate`` rejects. Each value past a limit is clamped onto it, and the scaffold's
comment says which joint moved by how much. Clamping always makes a key valid: the description
readers refuse an empty range (RS052) and drop a key whose values are not all numbers.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from robospec.description.facts import RobotDescription


@dataclass(frozen=True)
class FittedKeyframe:
    qpos: dict[str, float]  # every joint of the key -> its value within the joint's limits
    moved: tuple[tuple[str, float, float], ...] = ()  # (joint, as written, as copied)

    def note(self) -> str | None:
        """What the comment on the copied keyframe says (None when it is copied as written)."""
        if not self.moved:
            return None
        moves = ", ".join(
            f"{joint} {written:g} -> {copied:g} (moved {abs(copied - written):.3g})"
            for joint, written, copied in self.moved
        )
        return f"the file's values clamped into the joints' limits: {moves}"


def fit_to_limits(description: RobotDescription, qpos: Mapping[str, float]) -> FittedKeyframe:
    """The keyframe ``qpos`` with each joint value clamped into that joint's limits."""
    fitted: dict[str, float] = {}
    moved: list[tuple[str, float, float]] = []
    for name, value in qpos.items():
        joint = description.joint(name)
        low = -math.inf if joint is None or joint.lower is None else joint.lower
        high = math.inf if joint is None or joint.upper is None else joint.upper
        fitted[name] = min(max(value, low), high)
        if fitted[name] != value:
            moved.append((name, value, fitted[name]))
    return FittedKeyframe(fitted, tuple(moved))
