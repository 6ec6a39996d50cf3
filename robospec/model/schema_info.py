"""Which keys a spec model accepts at a given place, for did-you-mean hints on unknown keys."""

from __future__ import annotations

import types
import typing
from typing import Any, get_args, get_origin

from pydantic import BaseModel


def fields_for(loc: tuple[Any, ...], data: Any = None) -> list[str]:
    from robospec.model.spec import Spec

    candidates: list[Any] = [Spec]
    for element in loc:
        following: list[Any] = []
        for tp in candidates:
            following.extend(_step(tp, element))
        candidates = following
    names: list[str] = []
    for tp in candidates:
        for model in _models(tp):
            names.extend(n for n in model.model_fields if n not in names)
    return names


def _unwrap(tp: Any) -> list[Any]:
    origin = get_origin(tp)
    if origin is typing.Annotated:
        return _unwrap(get_args(tp)[0])
    if origin in (typing.Union, types.UnionType):
        out: list[Any] = []
        for arg in get_args(tp):
            out.extend(_unwrap(arg))
        return out
    return [tp]


def _models(tp: Any) -> list[type[BaseModel]]:
    return [t for t in _unwrap(tp) if isinstance(t, type) and issubclass(t, BaseModel)]


def _step(tp: Any, element: Any) -> list[Any]:
    out: list[Any] = []
    for member in _unwrap(tp):
        if isinstance(member, type) and issubclass(member, BaseModel):
            if element in member.model_fields:
                out.append(member.model_fields[element].annotation)
            continue
        origin = get_origin(member)
        if origin is dict and isinstance(element, str):
            out.append(get_args(member)[1])
        elif origin is list and isinstance(element, int):
            out.append(get_args(member)[0])
    if not out:
        # a discriminated-union tag: pick the member whose `type` literal is the tag
        for model in _models(tp):
            field = model.model_fields.get("type")
            if field is not None and element in get_args(field.annotation):
                out.append(model)
    return out
