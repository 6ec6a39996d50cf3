"""``robospec solve``: demonstrations by ManiSkill's own motion-planning solutions, for any arm
with a two-finger gripper, planned by robospec from the spec (docs/solve.md)."""
