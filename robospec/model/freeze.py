"""Freeze the pydantic spec models: the source of :mod:`robospec.model.frozen`'s records.

The pydantic models are the one source of truth: the JSON Schema, the docs and this freezer
read them. But importing pydantic and building their validators is most of what `robospec
validate` would spend. So this module writes what those validators are made of, as the text of
a Python module:

- one :class:`~robospec.model.record.Record` class per model, with the same name, bases and
  fields, and the behaviour mixins of :mod:`robospec.model.rules`;
- each model's pydantic-core schema as a Python literal, in which the models' classes are the
  records and every function is one from :mod:`robospec.model.rules` (the same functions the
  pydantic models run; anything else stops the freezer with the place it was found).

pydantic-core then validates with exactly the rules and messages this pydantic uses. The text
is made by the pydantic installed, for its pydantic-core, and cached
(:mod:`robospec.model.frozen_cache`); ``python -m robospec.model.freeze`` prints it.
"""

from __future__ import annotations

import functools
import importlib
import math
import sys
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import pydantic
import pydantic_core
from pydantic import BaseModel
from pydantic._internal import _validators as pydantic_validators

import robospec.model.rules as rules
from robospec.model.common import StrictModel

# where the spec models are defined, each after the ones it uses
MODEL_MODULES = (
    "robospec.model.common",
    "robospec.model.controllers",
    "robospec.model.members",
    "robospec.model.check_settings",
    "robospec.model.mends",
    "robospec.model.mechanisms",
    "robospec.model.spec",
)
_DROPPED_KEYS = frozenset({"metadata", "serialization"})
# pydantic's own checks of constraints on a value a function made, and their twins in rules
_CONSTRAINTS = {"gt": rules.greater_than, "ge": rules.greater_than_or_equal}


class FreezeError(Exception):
    """The models hold something a frozen schema cannot name."""


@dataclass(frozen=True)
class Ref:
    """A name in the frozen module standing for a class or a function."""

    source: str  # as written in the frozen module's text


def model_classes() -> list[type[StrictModel]]:
    """Every spec model in the order it was defined (so nested models come first)."""
    found: list[type[StrictModel]] = []
    for name in MODEL_MODULES:
        module = importlib.import_module(name)
        found += [
            value
            for value in vars(module).values()
            if isinstance(value, type)
            and issubclass(value, StrictModel)
            and value is not StrictModel
            and value.__module__ == name
        ]
    missing = _all_subclasses(StrictModel) - set(found)
    if missing:
        names = sorted(f"{c.__module__}.{c.__qualname__}" for c in missing)
        raise FreezeError(f"spec models outside {MODEL_MODULES}: {names}")
    duplicates = sorted(n for n, k in Counter(c.__name__ for c in found).items() if k > 1)
    if duplicates:
        raise FreezeError(f"two spec models share a name: {duplicates}")
    return found


def _all_subclasses(cls: type[object]) -> set[type]:
    out: set[type] = set()
    for sub in cls.__subclasses__():
        if sub.__module__.startswith("robospec.model."):
            out |= {sub, *_all_subclasses(sub)}
    return out


def frozen_schemas() -> dict[str, Any]:
    """Each model's pydantic-core schema, by class name, as a tree of plain data and
    :class:`Ref`s."""
    out: dict[str, Any] = {}
    for cls in model_classes():
        # pydantic inlines a nested model's schema as it finds it, built or not, so a schema's
        # shape depends on what was built before: rebuild all, nested models first (they are
        # defined first), for the same schemas in every process
        cls.model_rebuild(force=True)
        out[cls.__name__] = _convert(cls.__pydantic_core_schema__, cls.__name__)
    return out


def _convert(node: Any, where: str) -> Any:
    if isinstance(node, dict):
        out: dict[str, Any] = {}
        for key, value in node.items():
            if key in _DROPPED_KEYS:
                continue
            if key in ("ref", "schema_ref"):
                out[key] = _ref_name(value)
            else:
                out[key] = _convert(value, f"{where}.{key}")
        return out
    if isinstance(node, (list, tuple)):
        items = [_convert(v, where) for v in node]
        return items if isinstance(node, list) else tuple(items)
    if isinstance(node, float) and not math.isfinite(node):
        raise FreezeError(f"{where}: a non-finite number {node!r}")
    if node is None or isinstance(node, (str, int, float, bool)):
        return node
    return _name(node, where)


def _name(obj: Any, where: str) -> Ref:
    if obj is dict or obj is list:
        return Ref(obj.__name__)
    if isinstance(obj, type) and issubclass(obj, BaseModel):
        if not issubclass(obj, StrictModel):
            raise FreezeError(f"{where}: {obj.__qualname__} is not a spec model")
        return Ref(obj.__name__)
    if isinstance(obj, functools.partial):
        return _constraint(obj, where)
    if callable(obj) and getattr(obj, "__module__", None) == rules.__name__:
        function_name = obj.__name__
        if getattr(rules, function_name, None) is not obj:
            raise FreezeError(f"{where}: {obj.__qualname__} is not a name in {rules.__name__}")
        return Ref(f"rules.{function_name}")
    raise FreezeError(
        f"{where}: {obj!r} cannot be frozen; validators and default factories of spec models "
        f"must be functions of {rules.__name__}"
    )


def _constraint(partial: functools.partial[Any], where: str) -> Ref:
    """``Field(gt=0)`` on a Number: pydantic's check with its bound, as the rules' twin."""
    key = _constraint_key(partial)
    constraint = _CONSTRAINTS.get(key or "")
    (bound,) = partial.keywords.values() if key else (None,)
    if constraint is None or isinstance(bound, bool) or not isinstance(bound, (int, float)):
        raise FreezeError(f"{where}: a partial of {partial.func!r} has no frozen equivalent")
    return Ref(f"functools.partial(rules.{constraint.__name__}, {key}={bound!r})")


def _constraint_key(partial: functools.partial[Any]) -> str | None:
    """Which constraint (``"gt"``, ...) a partial of pydantic's checks with its one keyword.

    The keyword names it (pydantic 2.7-2.8 and 2.11 on), or is the generic
    ``constraint_value`` (2.9-2.10), where pydantic's lookup tells which function checks what.
    """
    if getattr(partial.func, "__module__", None) != pydantic_validators.__name__:
        return None
    if partial.args or len(partial.keywords) != 1:
        return None
    (key,) = partial.keywords
    if key != "constraint_value":
        return key
    lookup = getattr(pydantic_validators, "get_constraint_validator", None)
    if lookup is None:
        return None
    return next((c for c in _CONSTRAINTS if lookup(c) is partial.func), None)


def _ref_name(ref: str) -> str:
    # pydantic's refs end in ':<id of the class>', which differs from run to run
    module_and_name, _, _ = ref.partition(":")
    return module_and_name


# -- writing the frozen module ------------------------------------------------------------


def frozen_source() -> str:
    """The text of the frozen module for the models as they are now, made by this pydantic:
    what :mod:`robospec.model.frozen` runs in its own namespace."""
    classes = model_classes()
    schemas = frozen_schemas()
    constants = _Constants(schemas)
    schema_lines = [f"    {name!r}: {constants.emit(tree)}," for name, tree in schemas.items()]
    parts = [
        _HEADER.format(pydantic=pydantic.VERSION, core=pydantic_core.__version__),
        *(_class_source(cls) for cls in classes),
        "",
        "# Shared parts of the schemas below, each written once.",
        *constants.lines,
        "",
        "# Each model's pydantic-core schema, by class name.",
        "SCHEMAS: dict[str, Any] = {",
        *schema_lines,
        "}",
        "",
    ]
    return "\n".join(parts)


_HEADER = """\
# The spec models, frozen: record classes and pydantic-core schemas. GENERATED by
# robospec.model.freeze with pydantic {pydantic} (pydantic-core {core}) from the models in
# robospec.model; robospec.model.frozen runs it, and caches it per pydantic-core and model source.
# No docstring: this text runs in robospec.model.frozen's namespace and would replace its own.

from __future__ import annotations

import functools
from typing import Any

import robospec.model.rules as rules
from robospec.model.record import FieldSpec, Record
"""


def _class_source(cls: type[StrictModel]) -> str:
    model_bases = [b.__name__ for b in cls.__bases__ if issubclass(b, StrictModel)]
    model_bases = [b for b in model_bases if b != StrictModel.__name__] or ["Record"]
    mixins = []
    for base in cls.__bases__:
        if issubclass(base, BaseModel):
            continue
        if base.__module__ != rules.__name__ or getattr(rules, base.__name__, None) is not base:
            raise FreezeError(f"{cls.__name__}: base {base!r} is not a mixin of {rules.__name__}")
        mixins.append(f"rules.{base.__name__}")
    doc = (cls.__doc__ or cls.__name__).strip().split("\n\n")[0]
    doc = " ".join(line.strip() for line in doc.splitlines()).replace("\\", "\\\\")
    fields = ", ".join(f"{n!r}: FieldSpec({f.is_required()})" for n, f in cls.model_fields.items())
    return (
        f"\n\nclass {cls.__name__}({', '.join(model_bases + mixins)}):\n"
        f'    """{doc.replace(chr(34) * 3, chr(39) * 3)}"""\n\n'
        f"    __slots__ = ()\n"
        f"    model_fields = {{{fields}}}\n"
    )


class _Constants:
    """Writes trees as Python expressions, hoisting every part that occurs more than once
    into a module constant (the 200 copies of a number's schema become one)."""

    _MIN_HOISTED = 40  # characters: shorter parts are cheaper to repeat than to name

    def __init__(self, trees: dict[str, Any]) -> None:
        self._text: dict[int, str] = {}
        self._count: Counter[str] = Counter()
        self._named: dict[str, str] = {}
        self.lines: list[str] = []
        for tree in trees.values():
            for text in self._texts(tree):
                self._count[text] += 1

    def _texts(self, node: Any) -> Iterator[str]:
        """Count pass: every container's full text, bottom-up."""
        if isinstance(node, dict):
            for value in node.values():
                yield from self._texts(value)
        elif isinstance(node, (list, tuple)):
            for value in node:
                yield from self._texts(value)
        else:
            return
        text = self._full(node)
        yield text

    def _full(self, node: Any) -> str:
        cached = self._text.get(id(node))
        if cached is None:
            cached = self._render(node, self._full)
            self._text[id(node)] = cached
        return cached

    def emit(self, node: Any) -> str:
        """The expression for ``node``, hoisting repeated parts (defined in ``lines``)."""
        if not isinstance(node, (dict, list, tuple)):
            return self._render(node, self.emit)
        full = self._full(node)
        if self._count[full] < 2 or len(full) < self._MIN_HOISTED:
            return self._render(node, self.emit)
        name = self._named.get(full)
        if name is None:
            expression = self._render(node, self.emit)
            name = f"_S{len(self._named)}"
            self._named[full] = name
            self.lines.append(f"{name} = {expression}")
        return name

    @staticmethod
    def _render(node: Any, inner: Any) -> str:
        if isinstance(node, dict):
            return "{" + ", ".join(f"{k!r}: {inner(v)}" for k, v in node.items()) + "}"
        if isinstance(node, list):
            return "[" + ", ".join(inner(v) for v in node) + "]"
        if isinstance(node, tuple):
            return "(" + "".join(f"{inner(v)}, " for v in node) + ")"
        if isinstance(node, Ref):
            return node.source
        return repr(node)


def main() -> int:
    """Print the frozen module's text (what the cache holds for this pydantic)."""
    sys.stdout.write(frozen_source())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
