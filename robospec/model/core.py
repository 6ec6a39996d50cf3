"""pydantic-core validators for the spec's record classes.

With the pydantic-core the schemas in :mod:`robospec.model.frozen` were frozen with, they are
used as they are: no pydantic import, no schema generation. With another pydantic-core (a
schema's format may change between versions) the schemas are built afresh from the pydantic
models, the way the freezer builds them, which is slower but validates the same.
"""

from __future__ import annotations

import functools
from typing import Any

import pydantic_core
from pydantic_core import SchemaValidator

from robospec.model import frozen


@functools.cache
def validator_for(name: str) -> SchemaValidator:
    """The validator of the model called ``name`` (``"Spec"``: a whole spec)."""
    return SchemaValidator(schema_for(name))


def schema_for(name: str) -> Any:
    if frozen_schemas_usable():
        return frozen.SCHEMAS[name]
    return _live_schemas()[name]


@functools.cache
def _live_schemas() -> dict[str, Any]:
    # every model is rebuilt to make them, so they are made once for all
    from robospec.model.freeze import live_schemas

    return live_schemas(records())


def frozen_schemas_usable() -> bool:
    return pydantic_core.__version__ == frozen.PYDANTIC_CORE_VERSION


def records() -> dict[str, Any]:
    """Every record class, by name."""
    from robospec.model.record import Record

    return {
        name: value
        for name, value in vars(frozen).items()
        if isinstance(value, type) and issubclass(value, Record) and value is not Record
    }
