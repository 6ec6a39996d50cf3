"""RS521: the robot starts inside the ground.

The checks run the robot where users run it: ManiSkill's ``Empty-v1``, its ground at height 0,
the robot loaded at the origin (``Empty-v1`` places every robot there) or put at a keyframe's
pose. For each start — every keyframe, and the robot as loaded — this check finds the lowest
point of every link that can move (for a fixed robot: every link but its root and what is
welded to it) and reports the links that reach more than 5 mm below the ground. PhysX pushes
them out from the first step, and a light link pushed out of the ground flies: ManiSkill's own
Allegro hands, loaded at the origin, throw their fingers to thousands of radians within a few
steps.

A keyframe that starts inside the ground is an error at its pose. The robot as loaded is an
error only when the spec has no keyframe (the load is then the only start there is); with
keyframes it is a warning — ManiSkill's tasks and its demo put a robot at its keyframe, and
the other checks start from those, not from the load (random actions "from load" are skipped).
Every other finding from a start inside the ground says so.

Passing: the Panda's ``rest`` keyframe: its base stands on the ground, nothing else reaches it.
Failing: ``allegro_hand_right_touch`` (ManiSkill's and the spec's alike): it has no keyframe,
and loaded at the origin its fingers reach 10 cm into the ground (RS521 at ``uid``; its holds and
random actions then blow up, and say why).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robospec.diagnostics import Severity, error, warning
from robospec.diagnostics.codes import STARTS_IN_GROUND
from robospec.physics import statics
from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics
from robospec.physics.sim import Sim
from robospec.resolve.resolved import ResolvedKeyframe

NAME = "ground"
DEPTH = 0.005  # m below the ground that counts as inside it (contacts settle by millimetres)
LIFT_MARGIN = 0.01  # m: a pose suggested to clear the ground clears it by this much


@dataclass(frozen=True)
class Clearance:
    """The links of the robot inside the ground at one start, deepest first (m below 0)."""

    below: tuple[tuple[str, float], ...]
    root_height: float  # the root link's height there

    @property
    def inside(self) -> bool:
        return bool(self.below)

    @property
    def depth(self) -> float:
        return self.below[0][1] if self.below else 0.0

    def links(self, limit: int = 3) -> str:
        shown = ", ".join(name for name, _ in self.below[:limit])
        more = len(self.below) - limit
        return shown + (f" and {more} more" if more > 0 else "")


def touching(sim: Sim) -> set[str]:
    """The links of the robot the ground touches now (CPU only)."""
    return {link for link, _, _ in sim.ground_contacts()}


def standing_on(sim: Sim) -> set[str]:
    """The links the robot stands on, or would land on, as it starts: its lowest, within
    :data:`statics.TOUCHING` of its lowest point (by their lowest points, not the contacts:
    none are reported before the first step, and a keyframe may hold the robot above the
    floor)."""
    lowest = sim.lowest_points()
    bottom = min(lowest.values(), default=0.0)
    return {link for link, z in lowest.items() if z <= bottom + statics.TOUCHING}


class FloorPress:
    """Which of some sets of the robot's links the floor presses on now, while random actions
    run: a mounted robot's random targets drive it into the floor it stands on, and random
    actions topple a free one onto links never made to carry it, so what such links do may be
    the floor's doing. The links a free robot stands on as it starts carry it by design and
    count for nothing (a knee buckling under the robot's own weight stays its failure).
    Watched on the CPU only (the contact list), and only where ``watch`` says so."""

    def __init__(self, sim: Sim, moved: list[set[str]], watch: bool) -> None:
        self.sim = sim
        self.watching = watch and not sim.backend.gpu
        self.moved = moved if self.watching else []
        self.supports = standing_on(sim) if self.watching and not sim.fixed_root else set()

    def pressed(self, which: np.ndarray) -> dict[int, bool]:
        """For each set ``which`` (a mask over them) picks: whether the floor presses on one
        of its links now (beyond the supports); nothing where not watching."""
        if not self.watching or not which.any():
            return {}
        now = touching(self.sim) - self.supports
        return {int(i): bool(now & self.moved[i]) for i in np.nonzero(which)[0]}


def clearance(run: CheckRun, start: ResolvedKeyframe | None) -> Clearance:
    """Which links start inside the ground at ``start`` (cached per start on ``run``)."""
    label = keyframe_label(start)
    if label not in run.clearances:
        sim = run.sim(run.modes[0])
        sim.start(start)
        mounted = sim.mounted_links()
        below = sorted(
            ((name, -z) for name, z in sim.lowest_points().items() if name not in mounted),
            key=lambda item: -item[1],
        )
        inside = tuple((name, depth) for name, depth in below if depth > DEPTH)
        root = float(sim.root_position()[0, 2])
        run.clearances[label] = Clearance(inside, root)
    return run.clearances[label]


def note(run: CheckRun, start: ResolvedKeyframe | None) -> str:
    """What a finding from ``start`` adds when the robot starts inside the ground."""
    if run.backend.gpu or not run.modes:
        return ""
    found = clearance(run, start)
    if not found.inside:
        return ""
    depth = f"{found.depth * 100:.3g} cm"
    return f"; it starts with {found.links()} {depth} inside the ground ({STARTS_IN_GROUND})"


def load_contacts(run: CheckRun) -> dict[tuple[str, str], float]:
    """Pairs of the robot's links deeper in contact than ``checks.self_contact.min_depth`` as
    the robot is loaded (cached on ``run``)."""
    if "load contacts" not in run.clearances:
        touching: dict[tuple[str, str], float] = {}
        if not run.robot.disable_self_collisions:
            sim = run.sim(run.modes[0])
            sim.start(None)
            sim.hold_drive_targets()
            sim.sim_step()
            touching = {
                pair: depth
                for pair, depth in sorted(sim.self_contacts().items())
                if depth >= run.settings.self_contact.min_depth
            }
        run.clearances["load contacts"] = touching
    return run.clearances["load contacts"]


def load_skipped(run: CheckRun, start: ResolvedKeyframe | None) -> bool:
    """Whether a check skips ``start``: the robot as loaded, when it starts inside the ground or
    with links of its own overlapping, and the spec has keyframes to start from instead (what
    ManiSkill's tasks and its demo do; the ground and self_contact checks report the load)."""
    if start is not None or not run.robot.keyframes or run.backend.gpu:
        return False
    return clearance(run, None).inside or bool(load_contacts(run))


def check(run: CheckRun) -> list[Finding]:
    if run.backend.gpu:
        return [Finding(NAME, None, "-", Status.SKIP, "contacts are read on the CPU only")]
    return [_start(run, start) for start in [*run.robot.keyframes, None]]


def _start(run: CheckRun, start: ResolvedKeyframe | None) -> Finding:
    found = clearance(run, start)
    subject = keyframe_label(start) if start is not None else "load"
    deepest = found.below[0][0] if found.below else None
    values = metrics(depth=found.depth, links=len(found.below), deepest=deepest)
    if not found.inside:
        return Finding(NAME, None, subject, Status.PASS, "clear of the ground", values)
    lift = found.root_height + found.depth + LIFT_MARGIN
    where = (
        f"at keyframe '{start.name}'"
        if start is not None
        else "as Empty-v1 loads it (its root at the origin, every joint at 0 within its limits)"
    )
    message = (
        f"{where}, links {found.links()} reach {found.depth * 100:.3g} cm below the ground of "
        "ManiSkill's scenes: PhysX pushes them out from the first step"
    )
    path: tuple[str, ...]
    if start is not None:
        path = ("keyframes", start.name, "pose")
        p = [round(v, 4) for v in start.p]
        hint = (
            f"raise the keyframe's pose to clear the ground: pose: {{p: [{p[0]:g}, {p[1]:g}, "
            f"{lift:.3g}]}} (or mount the robot where its task puts it)"
        )
        diagnostic = error(run.at(path), STARTS_IN_GROUND, message, hint)
    else:
        path = ("keyframes",) if run.robot.keyframes else ("uid",)
        hint = (
            "give the robot a keyframe whose pose lifts it clear, e.g. keyframes: {rest: "
            f"{{pose: {{p: [0, 0, {lift:.3g}]}}}}}}: ManiSkill's tasks and its demo put a robot "
            "at its keyframe (Empty-v1 itself loads every robot at the origin)"
        )
        if run.robot.keyframes:
            message += "; the checks start from the keyframes instead"
            hint = (
                "nothing to change if the robot is always placed at a keyframe; a task that "
                "loads it at the origin gets it inside the ground"
            )
            diagnostic = warning(run.at(path), STARTS_IN_GROUND, message, hint)
        else:
            diagnostic = error(run.at(path), STARTS_IN_GROUND, message, hint)
    status = Status.FAIL if diagnostic.severity is Severity.ERROR else Status.INFO
    summary = f"{found.links()} {found.depth * 100:.3g} cm inside the ground"
    return Finding(NAME, None, subject, status, summary, values, (diagnostic,))
