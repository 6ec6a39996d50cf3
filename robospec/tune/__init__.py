"""``robospec tune``: stiffness, damping and (where a drive saturates) force_limit per
controller, found in simulation so that each joint's step response meets the spec's targets
(``checks.tune``), measured exactly as ``robospec check`` measures it
(:func:`robospec.physics.step_response.step_trace`); ``--write`` puts them in the spec as a
person would edit it.

``command`` runs the search (``search``) in a worker process (``worker``), reports
(``report``), writes the spec (``write``: YAML, ``toml_write``: TOML) and the plots
(:mod:`robospec.physics.plot`). ``reference`` (fitting a recorded trajectory) is its own
package, reached only through ``--reference``.
"""
