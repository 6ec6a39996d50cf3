"""RS508 and RS734: links of the robot touch each other at a keyframe.

Each keyframe is set, the drives are told to hold it, and one physics step runs; every pair of
the robot's own links then in contact deeper than ``checks.self_contact.min_depth`` is reported
with the rule that would let them touch. Links a joint connects never collide in PhysX, so they
never appear. Skipped when ``loader.disable_self_collisions`` is set. The robot as ManiSkill
loads it (every joint at 0, within its limits) is checked too: for a spec without keyframes it
is the only start (an error); with keyframes a warning — tasks start from those, and random
actions skip the load (ManiSkill's own robots load this way in ``Empty-v1``, and blow up).

A touching pair at rest pushes the robot away from its keyframe from the first step. When the
contact is meant (a closed hand, a finger resting on the palm), declare it in the spec; else the
keyframe needs another pose.

Links a closed loop joins (``loops:``, with the links welded to them) are not reported: the
loop's drive holds them together where they meet.

A pair with one link in a mounted part (``parts:``) and the other outside it is the part's
pose pushing it into the robot: RS734, at the part's ``pose``, at the first keyframe it happens.

Passing: the Panda's ``rest`` keyframe: no two links touch.
Failing: a keyframe that folds the Panda's fingers into its fifth link; the hint suggests
``never_collide: [[panda_leftfinger, panda_link5]]``.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import LINKS_TOUCH_AT_KEYFRAME, PART_INSIDE_ROBOT
from robospec.physics import ground
from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics
from robospec.resolve.mechanisms import loop_joined

NAME = "self_contact"


def check(run: CheckRun) -> list[Finding]:
    if run.context.robot.disable_self_collisions:
        return [Finding(NAME, None, "-", Status.SKIP, "disable_self_collisions is set")]
    if run.backend.gpu:
        return [Finding(NAME, None, "-", Status.SKIP, "contacts are read on the CPU only")]
    sim = run.sim(run.modes[0])
    min_depth = run.settings.self_contact.min_depth
    findings = []
    if run.robot.keyframes:
        findings.append(_load(run))
    reported: set[str] = set()  # parts already said to be inside the robot
    joined = loop_joined(run.context.description, [loop.links for loop in run.robot.loops])
    for keyframe in run.keyframes:
        sim.start(keyframe)
        sim.hold_drive_targets()
        sim.sim_step()
        touching = {
            pair: depth
            for pair, depth in sorted(sim.self_contacts().items())
            if depth >= min_depth and frozenset(pair) not in joined
        }
        label = keyframe_label(keyframe)
        details = tuple(metrics(link_a=a, link_b=b, depth=d) for (a, b), d in touching.items())
        if not touching:
            findings.append(
                Finding(NAME, None, label, Status.PASS, "no links touch", metrics(pairs=0))
            )
            continue
        diagnostics = list(_inside_parts(run, touching, label, reported))
        touching = {pair: d for pair, d in touching.items() if not _across(run, pair)}
        if not touching:
            findings.append(
                Finding(
                    NAME,
                    None,
                    label,
                    Status.FAIL,
                    "a part is inside the robot",
                    metrics(pairs=len(details)),
                    tuple(diagnostics),
                    details,
                )
            )
            continue
        listed = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for (a, b), d in touching.items())
        rule = ", ".join(f"[{a}, {b}]" for a, b in touching)
        diagnostic = run.fail(
            run.keyframe_path(keyframe),
            LINKS_TOUCH_AT_KEYFRAME,
            f"at keyframe '{label}' these links of the robot touch: {listed}",
            f"if they are meant to touch, add `never_collide: [{rule}]`; otherwise move the "
            "keyframe apart",
        )
        findings.append(
            Finding(
                NAME,
                None,
                label,
                Status.FAIL,
                f"{len(touching)} touching pair(s): {listed}",
                metrics(pairs=len(touching)),
                (*diagnostics, diagnostic),
                details,
            )
        )
    return findings


def _load(run: CheckRun) -> Finding:
    # a pair across a mounted part's seam is the part's pose, which RS734 says at the keyframes
    joined = loop_joined(run.context.description, [loop.links for loop in run.robot.loops])
    touching = {
        p: d
        for p, d in ground.load_contacts(run).items()
        if not _across(run, p) and frozenset(p) not in joined
    }
    if not touching:
        return Finding(NAME, None, "load", Status.PASS, "no links touch", metrics(pairs=0))
    listed = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for (a, b), d in touching.items())
    rule = ", ".join(f"[{a}, {b}]" for a, b in touching)
    diagnostic = warning(
        run.at(("keyframes",)),
        LINKS_TOUCH_AT_KEYFRAME,
        f"as ManiSkill loads the robot (every joint at 0, within its limits) these links touch: "
        f"{listed}; the checks start from the keyframes instead",
        f"a task that loads it this way gets them pushed apart; if they are meant to touch, "
        f"add `never_collide: [{rule}]`",
    )
    details = tuple(metrics(link_a=a, link_b=b, depth=d) for (a, b), d in touching.items())
    summary = f"{len(touching)} touching pair(s): {listed}"
    return Finding(
        NAME,
        None,
        "load",
        Status.INFO,
        summary,
        metrics(pairs=len(touching)),
        (diagnostic,),
        details,
    )


def _part_of(run: CheckRun, link: str) -> str | None:
    return next((p.name for p in run.context.robot.parts if link in p.links), None)


def _across(run: CheckRun, pair: tuple[str, str]) -> bool:
    """Whether the pair straddles the seam of a mounted part."""
    return _part_of(run, pair[0]) != _part_of(run, pair[1])


def _inside_parts(
    run: CheckRun, touching: dict[tuple[str, str], float], label: str, reported: set[str]
) -> Iterator[Diagnostic]:
    """RS734 for each part that a pair across its seam shows inside the robot, deepest first."""
    by_part: dict[str, list[tuple[str, str, float]]] = {}
    for (a, b), depth in touching.items():
        for inside, outside in ((a, b), (b, a)):
            part = _part_of(run, inside)
            if part is not None and part != _part_of(run, outside):
                by_part.setdefault(part, []).append((inside, outside, depth))
    for part, pairs in by_part.items():
        if part in reported:
            continue
        reported.add(part)
        inside, outside, depth = max(pairs, key=lambda p: p[2])
        rule = ", ".join(f"[{o}, {i}]" for i, o, _ in pairs)
        yield run.fail(
            ("parts", part, "pose"),
            PART_INSIDE_ROBOT,
            f"part '{part}' is inside the robot at keyframe '{label}': its link '{inside}' is "
            f"{depth * 1000:.1f} mm into '{outside}'"
            + (f" (and {len(pairs) - 1} more pair(s))" if len(pairs) > 1 else ""),
            "move the part with `pose:` (robospec inspect names the mount's frames); where it "
            "is meant to touch there (its base against the flange), declare "
            f"`never_collide: [{rule}]`",
        )
