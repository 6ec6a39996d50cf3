"""``robospec new``: a spec scaffolded from a robot description, by job.

* What the description says the robot is: :mod:`.analysis` (its groups, :mod:`.groups`; its
  body and drives), its gains (:mod:`.gains`, :mod:`.joint_gains`, over :mod:`.joint_loads`;
  a gripper's from its force, :mod:`.grip`).
* The scaffold: :mod:`.scaffold` writes the spec (its controllers :mod:`.scaffold_controllers`,
  what tasks call :mod:`.task_members`); :mod:`.spec_text` makes its text, measured in ManiSkill
  where it is installed.
* The rest-pose search over a contacts callable: :mod:`.pose_search`, moving the joints of
  :mod:`.joint_space`.
* Collision exemptions over the kinematic tree (the pairs declared never_collide):
  :mod:`.exemptions`.
* The gains' refinement in simulation: :mod:`.refinement`.
* The child process that loads the robot in ManiSkill and runs the search, the exemptions and
  the refinement there: :mod:`.probe`; the parent's side of it (the request, the answer read
  back): :mod:`.rest_pose`.
* ``--attach``: :mod:`.attach` mounts parts on the scaffold.
"""
