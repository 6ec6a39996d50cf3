"""RS534: a joint whose rated force cannot carry gravity where check steps it.

A step response that finds a joint's drive held at its force limit for the whole step, under
gravity, is not a verdict on its gains when that force limit is the description's rating (its
URDF ``<limit effort>``, its MJCF actuator's ``forcerange``) and gravity alone takes nearly all
of it (:data:`GRAVITY_SHARE`) at that pose: the motor as rated cannot lift its own link there,
and no stiffness or damping changes that. ``check`` then says so at the rating in the
description, as a warning about the rating, instead of calling the controller too slow
(RS505) or off target (RS507). ``robospec new`` finds the same thing when it measures its
gains (RS609, "measured in ManiSkill"). Where the spec's ``force_limit`` is below the rating,
the spec holds the joint back: RS505 stays, and says to raise it.

Passing: an arm rated well above what gravity puts on it; a mode where ManiSkill cancels
gravity (``balance_passive_force``).
Failing: an arm rated 3 N m whose 1 kg link, 0.3 m out, weighs 2.94 N m on its shoulder.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from robospec.description.ratings import joint_ratings
from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import RATING_BELOW_GRAVITY

if TYPE_CHECKING:  # robospec new reads GRAVITY_SHARE without loading the simulation's modules
    from robospec.physics.check_run import CheckRun
    from robospec.physics.sim import Sim

# gravity's share of the rating at which the rating, not the gains, is what the step meets
GRAVITY_SHARE = 0.9
SATURATED_SHARE = 0.5  # of the step: held at its force limit that long, the drive is at its end


def gravity_bound(
    run: CheckRun,
    sim: Sim,
    controller: str,
    joint: str,
    force_limit: float,
    saturated: float,
    prismatic: bool,
) -> Diagnostic | None:
    """RS534 for ``joint``, held at ``force_limit`` for ``saturated`` of its step, where that is
    its rating and gravity takes nearly all of it (the robot as it stands after the step);
    None where the gains, or the spec's force limit, are what holds it back."""
    if saturated <= SATURATED_SHARE or sim.gravity_off():
        return None
    rating = joint_ratings(run.context.description).get(joint)
    if rating is None or force_limit < rating.value * (1 - 1e-3):
        return None
    load = abs(sim.gravity_loads().get(joint, 0.0))
    if not math.isfinite(load) or load < GRAVITY_SHARE * rating.value:
        return None
    unit = "N" if prismatic else "N m"
    return warning(
        run.context.at_description(rating.line),
        RATING_BELOW_GRAVITY,
        f"joint '{joint}' is rated {rating.value:g} {unit} ({rating.what}), and gravity alone "
        f"puts {load:.3g} {unit} on it where controller '{controller}' ({sim.mode}) steps it: "
        f"its drive was held at that rating for {saturated:.0%} of the step. The robot as "
        "rated cannot lift this link here; no gains change that",
        "if the motor gives more, correct the rating (and force_limit); else step it from a "
        "pose it can carry, or let ManiSkill cancel gravity (balance_passive_force: true)",
    )
