"""A ``<collision>`` element's replacement: the new elements, one per shape, and the files
they name."""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from lxml import etree


@dataclass(frozen=True)
class Result:
    """One collision element's replacement: new elements and files, or nothing (kept)."""

    method: str  # "unfitted": no primitive within the bound (elements: none)
    elements: tuple[etree._Element, ...]
    files: tuple[tuple[str, str], ...]  # (file name, OBJ text)
    vertices: int
    fit_error: float | None = None
    fit: str = ""
    primitives: int = 0


def as_meshes(
    method: str,
    collision: etree._Element,
    objs: Sequence[tuple[str, int]],
    stem: str,
    assets: Path,
) -> Result:
    """One ``<collision>`` per OBJ, each a copy of the original (origin, scale, name) naming its
    file: every part is then one convex shape whether or not the loader splits files."""
    elements: list[etree._Element] = []
    files: list[tuple[str, str]] = []
    for part, (text, _) in enumerate(objs):
        file_name = f"{stem}.obj" if len(objs) == 1 else f"{stem}_{part}.obj"
        element = copy.deepcopy(collision)
        mesh = element.find("geometry/mesh")
        assert mesh is not None
        mesh.set("filename", str(assets / file_name))
        if len(objs) > 1 and element.get("name"):
            element.set("name", f"{element.get('name')}_{part}")
        elements.append(element)
        files.append((file_name, text))
    return Result(method, tuple(elements), tuple(files), sum(n for _, n in objs))


def replace_element(collision: etree._Element, elements: Sequence[etree._Element]) -> None:
    parent = collision.getparent()
    assert parent is not None
    position = parent.index(collision)
    tail = collision.tail
    parent.remove(collision)
    for offset, element in enumerate(elements):
        element.tail = tail
        parent.insert(position + offset, element)
