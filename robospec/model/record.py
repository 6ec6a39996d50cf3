"""The base of the validated spec's classes: plain objects that pydantic-core fills in.

pydantic-core builds a model by creating the object with ``cls.__new__`` and setting its
``__dict__`` and ``__pydantic_fields_set__``; it needs nothing else from the class. A record
offers the part of pydantic's ``BaseModel`` interface the later stages use (attributes,
``model_fields``, ``model_fields_set``, ``model_dump``, ``model_copy``), is immutable, and
compares and hashes as a frozen pydantic model does, without importing pydantic.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from pydantic_core import SchemaValidator


@dataclass(frozen=True)
class FieldSpec:
    """What the later stages ask of a field: whether a spec must give it."""

    required: bool

    def is_required(self) -> bool:
        return self.required


class Record:
    """One validated spec model (a subclass per model, generated in robospec.model.frozen)."""

    model_fields: ClassVar[Mapping[str, FieldSpec]] = {}
    # the validator of a record class, by name: robospec.model.frozen sets it when it has made
    # the classes and their schemas (this module is below that one and does not import it)
    validator_for: ClassVar[Callable[[str], SchemaValidator]]

    # where pydantic-core puts what it sets besides the fields, as on pydantic's BaseModel
    __slots__ = (
        "__dict__",
        "__pydantic_extra__",
        "__pydantic_fields_set__",
        "__pydantic_private__",
    )
    __pydantic_fields_set__: set[str]

    def __init__(self, **fields: Any) -> None:
        """Validate ``fields`` as the model does (how default values are made)."""
        type(self).validator_for(type(self).__name__).validate_python(fields, self_instance=self)

    @property
    def model_fields_set(self) -> set[str]:
        """The fields the spec gave (the others hold their defaults)."""
        return self.__pydantic_fields_set__

    def model_dump(self, *, exclude_none: bool = False) -> dict[str, Any]:
        """The fields as plain data, records included, as pydantic's ``model_dump()``."""
        return {
            name: _dump(value, exclude_none)
            for name, value in self.__dict__.items()
            if not (exclude_none and value is None)
        }

    def model_copy(self, *, update: Mapping[str, Any] | None = None) -> Any:
        """A shallow copy with ``update``'s fields replaced (and counted as given)."""
        clone = object.__new__(type(self))
        fields = dict(self.__dict__)
        fields_set = set(self.__pydantic_fields_set__)
        if update:
            fields.update(update)
            fields_set.update(update)
        object.__setattr__(clone, "__dict__", fields)
        object.__setattr__(clone, "__pydantic_fields_set__", fields_set)
        return clone

    def __setattr__(self, name: str, value: Any) -> None:
        raise TypeError(f"{type(self).__name__} is immutable; use model_copy(update=...)")

    def __delattr__(self, name: str) -> None:
        raise TypeError(f"{type(self).__name__} is immutable")

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return self.__dict__ == other.__dict__

    def __hash__(self) -> int:
        return hash((type(self), *self.__dict__.values()))

    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={value!r}" for name, value in self.__dict__.items())
        return f"{type(self).__name__}({fields})"

    def __getstate__(self) -> dict[str, Any]:
        return {"fields": self.__dict__, "fields_set": self.__pydantic_fields_set__}

    def __setstate__(self, state: dict[str, Any]) -> None:
        object.__setattr__(self, "__dict__", state["fields"])
        object.__setattr__(self, "__pydantic_fields_set__", state["fields_set"])


def _dump(value: Any, exclude_none: bool) -> Any:
    if isinstance(value, Record):
        return value.model_dump(exclude_none=exclude_none)
    if isinstance(value, dict):
        return {k: _dump(v, exclude_none) for k, v in value.items()}
    if isinstance(value, list):
        return [_dump(v, exclude_none) for v in value]
    return value
