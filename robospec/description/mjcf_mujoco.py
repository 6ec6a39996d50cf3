"""An MJCF model read by MuJoCo's rules, where they differ from ManiSkill's loader's.

ManiSkill's loader (mirrored by :mod:`robospec.description.mjcf`) reads ``<include>`` only as
a direct child of ``<mujoco>`` and keeps quirky default tables; what the file *means* — which
the reports of what ManiSkill drops, the ``<key>`` keyframes and the actuator gains are about —
follows MuJoCo:

* ``<include file=...>`` may stand anywhere; its children take its place (paths relative to
  the main file). Read here lazily, each file once, at most :data:`MAX_INCLUDE_DEPTH` deep.
* Default classes inherit from the class they are nested in; the top-level ``<default>`` is
  class ``main``. An element takes its own ``class``, else the ``childclass`` of the nearest
  body above it, else ``main``.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from lxml import etree

from robospec.description.urdf import parse_xml

MAIN_CLASS = "main"
MAX_INCLUDE_DEPTH = 8
ReadFile = Callable[[str], bytes]
Table = dict[str, dict[str, str]]  # tag -> attribute -> value


@dataclass
class Includes:
    """``<include>`` as MuJoCo reads it, wherever it stands; each file parsed once."""

    model_path: str
    read: ReadFile
    file_of: dict[etree._Element, str]  # an included file's root element -> its path
    _roots: dict[str, etree._Element | None] = field(default_factory=dict)

    def root(self, include: etree._Element) -> etree._Element | None:
        """The included file's root element; None when it cannot be read or parsed (the
        structure parse reports the includes ManiSkill reads; others say so where used)."""
        full = os.path.join(os.path.dirname(self.model_path), include.get("file") or "")
        if full not in self._roots:
            self._roots[full] = None
            try:
                data = self.read(full)
            except OSError:
                return None
            root, _ = parse_xml(data, full)
            self._roots[full] = root
            if root is not None:
                self.file_of[root] = full
        return self._roots[full]

    def children(self, element: etree._Element, depth: int = 0) -> Iterator[etree._Element]:
        """``element``'s child elements with every ``<include>`` replaced by what it holds."""
        for child in element:
            if not isinstance(child.tag, str):
                continue
            if child.tag != "include":
                yield child
                continue
            root = self.root(child) if depth < MAX_INCLUDE_DEPTH else None
            if root is not None:
                yield from self.children(root, depth + 1)

    def find_all(self, element: etree._Element, tag: str) -> list[etree._Element]:
        return [child for child in self.children(element) if child.tag == tag]


def read_classes(top: list[etree._Element], includes: Includes) -> dict[str, Table]:
    """Every default class's table, inherited values included (MuJoCo's rules)."""
    classes: dict[str, Table] = {MAIN_CLASS: {}}

    def read(node: etree._Element, inherited: Table) -> None:
        name = node.get("class", MAIN_CLASS)
        table = {tag: dict(values) for tag, values in inherited.items()}
        nested = []
        for child in includes.children(node):
            if child.tag == "default":
                nested.append(child)
            else:
                table.setdefault(str(child.tag), {}).update(child.attrib)
        classes[name] = table
        for child in nested:
            read(child, table)

    for default in (el for el in top if el.tag == "default"):
        read(default, {})
    return classes


def attributes(
    classes: dict[str, Table], element: etree._Element, childclass: str = MAIN_CLASS
) -> dict[str, str]:
    """``element``'s attributes over its class's defaults for its tag (MuJoCo's rules)."""
    table = classes.get(element.get("class", childclass)) or classes[MAIN_CLASS]
    merged = dict(table.get(str(element.tag), {}))
    merged.update(element.attrib)
    return merged


def childclass(element: etree._Element) -> str:
    """The class ``element`` takes its defaults from: its own ``class``, else the nearest
    ``childclass`` of a body above it (the body's own for a body), else ``main``."""
    own = element.get("class")
    if own is not None:
        return own
    holders = [element] if element.tag == "body" else []
    for holder in (*holders, *element.iterancestors("body")):
        if holder.get("childclass") is not None:
            return str(holder.get("childclass"))
    return MAIN_CLASS


def effective(table: dict[str, Table], element: etree._Element) -> dict[str, str]:
    """``element``'s attributes over the defaults of its class for its tag."""
    defaults = table.get(childclass(element)) or table.get(MAIN_CLASS, {})
    merged = dict(defaults.get(str(element.tag), {}))
    merged.update(element.attrib)
    return merged
