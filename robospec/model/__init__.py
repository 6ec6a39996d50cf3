"""Stage 2: plain data + source map → a typed spec, with located diagnostics.

- :mod:`robospec.model.validate`: ``build_spec`` validates loaded data into a ``Spec``;
- :mod:`robospec.model.spec` and its neighbours: the spec models, written with pydantic (the
  source of the JSON Schema, the docs and the validators);
- :mod:`robospec.model.frozen`: what ``build_spec`` validates with and returns, those models
  frozen into plain records and pydantic-core schemas (made by :mod:`robospec.model.freeze`,
  cached by :mod:`robospec.model.frozen_cache`), which need no pydantic.

This package imports none of them: importing one module of the stage costs only that module.
"""
