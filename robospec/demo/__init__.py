"""Robots shown running: :mod:`.tour` is ``scripts/demo`` (build the example specs, step each
robot headless and tell how it went) and :mod:`.viewer` is ``robospec demo SPEC`` (ManiSkill's
viewer, for people with a screen)."""
