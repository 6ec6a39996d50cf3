"""``robospec tune --reference``: fit a robot's drive gains so that its simulated response to a
recorded trajectory's commanded targets matches the positions measured (``trajectory`` reads
the file, ``replay`` runs it in ManiSkill, ``fit`` searches the gains, ``mujoco_reference``
makes the trajectory in MuJoCo, ``command`` is the CLI's entry point)."""
