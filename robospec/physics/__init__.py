"""``robospec check``: headless physics checks of a compiled robot in SAPIEN, on the CPU.

One module per check (``action_layout``, ``ground``, ``mimic_limits``, ``keyframe_hold``,
``gravity``, ``self_contact``, ``loops``, ``step_response``, ``random_actions``: the order of
``batch.CHECKS``), each ``check(run) -> list[Finding]``; :mod:`.batch` runs them in order (in
the worker process of :mod:`.worker`, which :mod:`.isolation` starts), with :mod:`.task_run`
(``--task``) and :mod:`.render` (``--render``) after them; :mod:`.report` renders the results.
The checks reach ManiSkill only through :mod:`.sim`; :mod:`.mujoco_hold` holds an MJCF robot's
keyframe in MuJoCo too (for ``keyframe_hold``), with :mod:`.mujoco_servos`.
"""
