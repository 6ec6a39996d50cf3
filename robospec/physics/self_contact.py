"""RS508: links of the robot touch each other at a keyframe.

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

Passing: the Panda's ``rest`` keyframe: no two links touch.
Failing: a keyframe that folds the Panda's fingers into its fifth link; the hint suggests
``never_collide: [[panda_leftfinger, panda_link5]]``.
"""

from __future__ import annotations

from robospec.diagnostics import warning
from robospec.physics import ground
from robospec.physics.check_run import CheckRun, keyframe_label
from robospec.physics.findings import Finding, Status, metrics

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
    for keyframe in run.keyframes:
        sim.start(keyframe)
        sim.hold_drive_targets()
        sim.sim_step()
        touching = {
            pair: depth for pair, depth in sorted(sim.self_contacts().items()) if depth >= min_depth
        }
        label = keyframe_label(keyframe)
        details = tuple(metrics(link_a=a, link_b=b, depth=d) for (a, b), d in touching.items())
        if not touching:
            findings.append(
                Finding(NAME, None, label, Status.PASS, "no links touch", metrics(pairs=0))
            )
            continue
        listed = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for (a, b), d in touching.items())
        rule = ", ".join(f"[{a}, {b}]" for a, b in touching)
        diagnostic = run.fail(
            run.keyframe_path(keyframe),
            "RS508",
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
                (diagnostic,),
                details,
            )
        )
    return findings


def _load(run: CheckRun) -> Finding:
    touching = ground.load_contacts(run)
    if not touching:
        return Finding(NAME, None, "load", Status.PASS, "no links touch", metrics(pairs=0))
    listed = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for (a, b), d in touching.items())
    rule = ", ".join(f"[{a}, {b}]" for a, b in touching)
    diagnostic = warning(
        run.at(("keyframes",)),
        "RS508",
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
