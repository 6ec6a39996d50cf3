"""What several tools read from a robot description's structure: its kinematic tree
(:mod:`.tree`), where its links are at given joint values (:mod:`.forward`, over the MJCF
reading of :mod:`.mjcf_model` and the rigid transforms of :mod:`.frames`), and what kind of body
it is (:mod:`.morphology`: legs, wheels, arms). ``new``, ``doc --images`` and ``optimize`` share
them; nothing here imports ManiSkill."""
