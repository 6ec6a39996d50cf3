"""``robospec check``: headless physics checks of a compiled robot in SAPIEN, on the CPU.

One module per check (``keyframe_hold``, ``random_actions``, ``step_response``,
``self_contact``, ``action_layout``), each ``check(run) -> list[Finding]``; :mod:`.runner`
runs them in order, :mod:`.report` renders the results. Only :mod:`.sim` talks to ManiSkill.
"""
