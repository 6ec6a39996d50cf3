"""Mend class ``asset_names: first | last`` (RS719, MJCF): assets defined twice under one name.

MuJoCo refuses a model that names two meshes (or textures, materials, height fields) alike
(``repeated name 'x' in mesh``); ManiSkill's loader keeps the last definition without a word,
so a geom meant for the first loads the other file, or none (RS094: commonly reported as a
missing mesh file). ``first`` keeps each name's first definition and removes the repeats,
``last`` keeps the last (what ManiSkill's loader did). ``robospec new`` chooses only where the
choice changes nothing or only one definition names a file that is there.
"""

from __future__ import annotations

import os
from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.derive.mjcf_files import named_files
from robospec.derive.mjcf_tree import mujoco_mesh_name, whole
from robospec.diagnostics.codes import MENDED_ASSET_NAMES, MJCF_REPEATED_ASSET

NAME = "asset_names"
KINDS = frozenset({"mjcf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_ASSET_NAMES
FIXES = (MJCF_REPEATED_ASSET,)
WHY = "assets are defined twice under one name (MuJoCo refuses it; ManiSkill takes the last)"

NAMED_ASSETS = ("mesh", "texture", "material", "hfield", "skin")


def repeats(root: etree._Element) -> list[list[etree._Element]]:
    """Each asset name defined more than once (per kind, as MuJoCo names them): its
    definitions in file order."""
    found: dict[tuple[str, str], list[etree._Element]] = {}
    for section in root.iterfind("asset"):
        for element in section:
            if not isinstance(element.tag, str) or element.tag not in NAMED_ASSETS:
                continue
            name = mujoco_mesh_name(element) if element.tag == "mesh" else element.get("name")
            if name:
                found.setdefault((element.tag, name), []).append(element)
    return [elements for elements in found.values() if len(elements) > 1]


def apply(document: Document, policy: str) -> None:
    root = whole(document)
    for elements in repeats(root):
        kept = elements[0] if policy == "first" else elements[-1]
        for element in elements:
            if element is kept:
                continue
            name = element.get("name") or mujoco_mesh_name(element)
            document.changed(
                element,
                f"{element.tag!s} '{name}' (defined again, line {kept.sourceline} kept)",
                _described(element),
                "removed",
            )
            document.remove(element)


def _described(element: etree._Element) -> str:
    shown = {k: v for k, v in element.attrib.items() if k != "name"}
    return " ".join(f'{k}="{v}"' for k, v in shown.items()) or "a definition"


def suggest(document: Document) -> str | None:
    """``first`` where every repeat says the same or only the first names a file that is
    there; ``last`` where only the last does; else nothing (only the user knows)."""
    trial = document.trial()
    root = whole(trial)
    found = repeats(root)
    if not found:
        return None
    files = dict(named_files(root, document.source.path))
    choices = set()
    for elements in found:
        definitions = {_described(e) for e in elements}
        present = [e for e in elements if e not in files or os.path.isfile(files[e])]
        if len(definitions) == 1 or present == elements[:1]:
            choices.add("first")
        elif present == elements[-1:]:
            choices.add("last")
        else:
            return None
    return choices.pop() if len(choices) == 1 else None
