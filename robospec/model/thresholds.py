"""Thresholds more than one stage judges by, in one place (no pydantic: ``validate`` and
``new`` import them without it).

- robospec check's defaults (:mod:`.check_settings` fields default to these), which other
  tools work to as well: ``new``'s scaffold gains hold a load within a share of the drift and
  meet the step, and its rest-pose search clears the contact depth check reports; ``tune
  --reference`` excites the drives with the same step;
- validate's bounds that ``robospec import`` applies to an agent class's own values (RS414,
  RS408) as the checks do to a spec's (RS304, RS318).
"""

from __future__ import annotations

MAX_JOINT_DRIFT = 0.05  # rad (m): checks.keyframe_hold.max_joint_drift
STEP = 0.1  # rad (rad/s): checks.step_response.step
PRISMATIC_STEP = 0.01  # m (m/s): checks.step_response.prismatic_step
MIN_CONTACT_DEPTH = 0.001  # m: checks.self_contact.min_depth

# how far a keyframe's joint value may lie outside the joint's limits (rounding in the written
# numbers), rad or m
LIMIT_TOLERANCE = 1e-6
# an end-effector controller's stiffness below this is no arm's: a bound passed by position
MIN_EE_STIFFNESS = 1.0
