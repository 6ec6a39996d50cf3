"""Getting started from a robot description: ``robospec inspect`` (what a URDF/MJCF/xacro file
holds), ``robospec new`` (a spec scaffolded from it) and ``robospec doc`` (a Markdown robot card
of a compiled spec).

:mod:`.commands` is what each command does apart from argument parsing. :mod:`.description_file`
reads the description; :mod:`.inspect` reports on it; :mod:`.analysis` reads what ``new`` needs
(:mod:`.groups`, :mod:`.gains`, :mod:`.joint_loads`); :mod:`.scaffold` writes the spec;
:mod:`.rest_pose` and :mod:`.refine` measure it in ManiSkill, in the child process of
:mod:`.pose_probe`; :mod:`.attach` mounts parts; :mod:`.layout` computes action layouts and
:mod:`.card` renders the card.
"""
