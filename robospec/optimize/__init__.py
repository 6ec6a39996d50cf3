"""robospec optimize: the same robot, described so that it simulates faster.

``robospec optimize SPEC -o OUT.yaml`` compiles the spec, then writes beside OUT.yaml a condensed
copy of its URDF (fixed joints merged into their parents, every link the spec names kept:
:mod:`robospec.optimize.condense`), with collision shapes SAPIEN simulates well
(:mod:`robospec.optimize.shapes`) and the link pairs that never touch declared ``never_collide``
(:mod:`robospec.optimize.collision_matrix`), and OUT.yaml, the spec pointing at it
(:mod:`robospec.optimize.command`).
"""
