"""What ManiSkill 3.0.1's scenes give every robot they hold, read from its source: facts the
checks of descriptions, specs and contacts measure against (no import of ManiSkill here)."""

from __future__ import annotations

# the bits of collision group 2 its scene builders set on the ground's shapes (its Fetch's
# FETCH_WHEELS_COLLISION_BIT and FETCH_BASE_COLLISION_BIT): a link with either never touches
# the floor
GROUND_BITS = (30, 31)
# SceneConfig.contact_offset (m): every shape of its scenes
CONTACT_OFFSET = 0.02
