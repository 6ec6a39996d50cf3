"""Getting started from a robot description: ``robospec inspect`` (what a URDF/MJCF/xacro file
holds), ``robospec new`` (a spec scaffolded from it) and ``robospec doc`` (a Markdown robot card
of a compiled spec).

One stage per module: :mod:`.source` reads a description file, :mod:`.tree` walks its kinematic
tree, :mod:`.inspect` reports on it, :mod:`.groups` guesses joint groups, :mod:`.scaffold` writes
the spec, :mod:`.layout` computes action layouts and :mod:`.card` renders the card. Nothing here
imports ManiSkill.
"""
