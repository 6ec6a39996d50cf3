"""Getting started from a robot description: ``robospec inspect`` (what a URDF/MJCF/xacro file
holds), ``robospec new`` (a spec scaffolded from it) and ``robospec doc`` (a Markdown robot card
of a compiled spec).

:mod:`.commands` is what each command does apart from argument parsing: each returns a
:class:`.commands.CommandResult` (its report, the files it writes, its diagnostics) that the CLI
renders and writes. :mod:`.description_file` reads the description; :mod:`.inspect` reports on
it (with :mod:`.mounting`'s frames); :mod:`.new` scaffolds the spec (one module per job, the
ManiSkill side in a child process); :mod:`.card` renders the card (with :mod:`.layout`'s action
layouts). ManiSkill runs only in child processes: new's probe (:mod:`.new.probe`, which
runs :mod:`.new.refinement`) and ``--attach``'s seam sampler (:mod:`.new.attach`).
"""
