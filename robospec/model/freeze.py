"""Freeze the pydantic spec models into :mod:`robospec.model.frozen`.

The pydantic models are the source of truth: the JSON Schema, the docs and the freezer read
them. But importing pydantic and building their validators is most of what `robospec validate`
used to spend. So this module writes, ahead of time, what those validators are made of:

- one :class:`~robospec.model.record.Record` class per model, with the same name, bases and
  fields, and the behaviour mixins of :mod:`robospec.model.rules`;
- each model's pydantic-core schema as a Python literal, in which the models' classes are the
  records and every function is one from :mod:`robospec.model.rules` (the same functions the
  pydantic models run; anything else stops the freezer with the place it was found).

pydantic-core then validates with exactly the rules and messages pydantic would use, and
``tests/test_frozen_model.py`` fails when the frozen module is out of date or validates any
spec differently. Regenerate with::

    python -m robospec.model.freeze --write
"""

from __future__ import annotations

import argparse
import functools
import importlib
import math
import sys
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pydantic_core
from pydantic import BaseModel

from robospec.model import rules
from robospec.model.common import StrictModel

FROZEN_PATH = Path(__file__).with_name("frozen.py")
# where the spec models are defined, each after the ones it uses
MODEL_MODULES = (
    "robospec.model.common",
    "robospec.model.controllers",
    "robospec.model.members",
    "robospec.model.check_settings",
    "robospec.model.spec",
)
_DROPPED_KEYS = frozenset({"metadata", "serialization"})
# pydantic's own constraint functions, for constraints on a value a function made
_CONSTRAINTS = {
    "greater_than_validator": rules.greater_than,
    "greater_than_or_equal_validator": rules.greater_than_or_equal,
}


class FreezeError(Exception):
    """The models hold something a frozen schema cannot name."""


@dataclass(frozen=True)
class Ref:
    """A name in the frozen module standing for a class or a function."""

    source: str  # as written in robospec/model/frozen.py
    target: Any  # what it stands for once imported


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


def _all_subclasses(cls: type) -> set[type]:
    out: set[type] = set()
    for sub in cls.__subclasses__():
        if sub.__module__.startswith("robospec.model."):
            out |= {sub, *_all_subclasses(sub)}
    return out


def frozen_schemas(records: dict[str, Any] | None = None) -> dict[str, Any]:
    """Each model's pydantic-core schema, by class name, as a tree of plain data and
    :class:`Ref`s. ``records``: the record classes the refs stand for (by name), if known."""
    out: dict[str, Any] = {}
    for cls in model_classes():
        # pydantic inlines a nested model's schema as it finds it, built or not, so a schema's
        # shape depends on what was built before: rebuild all, nested models first (they are
        # defined first), for the same schemas in every process
        cls.model_rebuild(force=True)
        out[cls.__name__] = _convert(cls.__pydantic_core_schema__, cls.__name__, records or {})
    return out


def live_schemas(records: dict[str, Any]) -> dict[str, Any]:
    """Every model's schema with the refs replaced by what they stand for: what a pydantic-core
    other than the frozen module's validates with (see :mod:`robospec.model.core`)."""
    return {name: _materialize(tree) for name, tree in frozen_schemas(records).items()}


def _convert(node: Any, where: str, records: dict[str, Any]) -> Any:
    if isinstance(node, dict):
        out: dict[str, Any] = {}
        for key, value in node.items():
            if key in _DROPPED_KEYS:
                continue
            if key in ("ref", "schema_ref"):
                out[key] = _ref_name(value)
            else:
                out[key] = _convert(value, f"{where}.{key}", records)
        return out
    if isinstance(node, (list, tuple)):
        items = [_convert(v, where, records) for v in node]
        return items if isinstance(node, list) else tuple(items)
    if isinstance(node, float) and not math.isfinite(node):
        raise FreezeError(f"{where}: a non-finite number {node!r}")
    if node is None or isinstance(node, (str, int, float, bool)):
        return node
    return _name(node, where, records)


def _name(obj: Any, where: str, records: dict[str, Any]) -> Ref:
    if obj is dict or obj is list:
        return Ref(obj.__name__, obj)
    if isinstance(obj, type) and issubclass(obj, BaseModel):
        if not issubclass(obj, StrictModel):
            raise FreezeError(f"{where}: {obj.__qualname__} is not a spec model")
        return Ref(obj.__name__, records.get(obj.__name__))
    if isinstance(obj, functools.partial):
        constraint = _CONSTRAINTS.get(getattr(obj.func, "__name__", ""))
        pydantic_own = obj.func.__module__ == "pydantic._internal._validators"
        if constraint is None or obj.args or not pydantic_own:
            raise FreezeError(f"{where}: a partial of {obj.func!r} has no frozen equivalent")
        (key, bound), *more = obj.keywords.items()
        if more or not isinstance(bound, (int, float)):
            raise FreezeError(f"{where}: constraint {obj.keywords!r} has no frozen equivalent")
        source = f"functools.partial(rules.{constraint.__name__}, {key}={bound!r})"
        return Ref(source, functools.partial(constraint, **{key: bound}))
    if callable(obj) and getattr(obj, "__module__", None) == rules.__name__:
        if getattr(rules, obj.__name__, None) is not obj:
            raise FreezeError(f"{where}: {obj.__qualname__} is not a name in {rules.__name__}")
        return Ref(f"rules.{obj.__name__}", obj)
    raise FreezeError(
        f"{where}: {obj!r} cannot be frozen; validators and default factories of spec models "
        f"must be functions of {rules.__name__}"
    )


def _ref_name(ref: str) -> str:
    # pydantic's refs end in ':<id of the class>', which differs from run to run
    module_and_name, _, _ = ref.partition(":")
    return module_and_name


def _materialize(node: Any) -> Any:
    if isinstance(node, Ref):
        return node.target
    if isinstance(node, dict):
        return {k: _materialize(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_materialize(v) for v in node]
    if isinstance(node, tuple):
        return tuple(_materialize(v) for v in node)
    return node


# -- writing robospec/model/frozen.py -----------------------------------------------------


def frozen_source() -> str:
    """The text of robospec/model/frozen.py for the models as they are now."""
    classes = model_classes()
    schemas = frozen_schemas()
    constants = _Constants(schemas)
    schema_lines = [f"    {name!r}: {constants.emit(tree)}," for name, tree in schemas.items()]
    parts = [
        _HEADER.format(version=pydantic_core.__version__),
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


_HEADER = '''\
"""The spec models, frozen: record classes and pydantic-core schemas. GENERATED, do not edit.

Written by ``python -m robospec.model.freeze --write`` from the pydantic models in
robospec.model; tests/test_frozen_model.py fails when it is out of date. See
robospec/model/freeze.py for why it exists.
"""
# ruff: noqa: E501

from __future__ import annotations

import functools
from typing import Any

from robospec.model import rules
from robospec.model.record import FieldSpec, Record

PYDANTIC_CORE_VERSION = {version!r}
"""The pydantic-core the schemas were frozen with (another one rebuilds them: model.core)."""
'''


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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m robospec.model.freeze", description=__doc__)
    parser.add_argument("--write", action="store_true", help=f"write {FROZEN_PATH.name}")
    parser.add_argument("--check", action="store_true", help="exit 1 if it is out of date")
    args = parser.parse_args(argv)
    source = frozen_source()
    if args.write:
        FROZEN_PATH.write_text(source, encoding="utf-8")
        return 0
    if args.check:
        current = FROZEN_PATH.read_text(encoding="utf-8") if FROZEN_PATH.exists() else ""
        if current != source:
            print(f"{FROZEN_PATH} is out of date: python -m robospec.model.freeze --write")
            return 1
        return 0
    sys.stdout.write(source)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
