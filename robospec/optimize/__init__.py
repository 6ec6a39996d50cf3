"""robospec optimize: the same robot, described so that it simulates faster.

``robospec optimize SPEC -o OUT.yaml`` compiles the spec, then writes beside OUT.yaml a condensed
copy of its URDF (fixed joints merged into their parents, every link the spec names kept:
:mod:`robospec.optimize.links`, :mod:`robospec.optimize.condense`), with collision shapes SAPIEN
simulates well (:mod:`robospec.optimize.shapes`) and the link pairs that never touch declared
``never_collide`` (:mod:`robospec.optimize.collision_matrix`,
:mod:`robospec.optimize.never_collide`), and OUT.yaml, the spec pointing at it
(:mod:`robospec.optimize.spec_rewrite`). :mod:`robospec.optimize.command` runs the stages, with
the options (:mod:`robospec.optimize.options`) and the files written
(:mod:`robospec.optimize.outputs`), and returns the result the CLI renders
(:mod:`robospec.optimize.report`).
"""
