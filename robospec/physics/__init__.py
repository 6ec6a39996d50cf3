"""``robospec check``: headless physics checks of a compiled robot in SAPIEN, on the CPU.

One module per check (``keyframe_hold``, ``random_actions``, ``step_response``,
``self_contact``, ``action_layout``), each ``check(run) -> list[Finding]``; :mod:`.batch`
runs them in order (in the worker process of :mod:`.worker`, which :mod:`.isolation` starts),
:mod:`.report` renders the results. Only :mod:`.sim` talks to ManiSkill.
"""
